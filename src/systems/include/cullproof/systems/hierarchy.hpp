// A hierarchy culler: one node test of Assarsson & Möller 2000 run down a binary BVH, with the
// per-node state that test keeps from frame to frame. It is the culling stack behind cullproof's
// node-test systems (bvh-pc-octant, bvh-pc-tr, bvh-pc-octant-tr) and behind every configuration
// of the scene simulator and its Table 1.
//
// The tests (stable kebab-case names, used in the simulator's CSV/JSON and the corpus):
//   perspective-transform  the DirectModel baseline (A&M §2): cull.hpp perspective_transform
//   basic-np               n/p-vertex test, six planes per node (A&M §3.1)
//   pc-octant              plane coherency (§3.2) + the corrected octant test (§3.3); plane
//                          coherency alone when the frustum is not symmetric or not bounded
//   pc-tr                  plane coherency + TR coherency (§3.5, TrCoherencyCuller)
//   pc-octant-tr           plane coherency + octant + TR coherency
//   masking                plane masking (§3.4): children skip the planes their parent is inside
//   lib-bvh-plain, lib-bvh-masked, lib-bvh-coherent
//                          cull_bvh.hpp's traversals (cullproof/core/cull_bvh.hpp)
// A node found inside accepts its subtree without tests.
//
// When each optimisation is used (only when the frame keeps it valid):
//  - octant: only when OctantCuller accepts the frustum of the frame's projection (bounded and
//    symmetric, A&M §3.3 and footnote 6), decided once per projection: a rigid camera motion
//    keeps a frustum symmetric and its centre distance;
//  - TR coherency: only in frames whose camera motion TrCoherencyCuller classifies as still, a
//    pure translation or a pure rotation about one camera axis, with the projection unchanged
//    since the previous frame (a zoom changes the side planes, which a rotation run would not
//    account for); otherwise plane coherency (and the octant) decide. Rotation coherency needs
//    the perspective pose; an orthographic view, or a pose the culler refuses, gets translation
//    coherency only. Nodes whose boxes changed lose their TR state and get a full test.
#pragma once

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/systems/system.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof {

enum class HierarchyTest : int {
  perspective_transform,
  basic_np,
  pc_octant,
  pc_tr,
  pc_octant_tr,
  masking,
  lib_bvh_plain,
  lib_bvh_masked,
  lib_bvh_coherent,
};
inline constexpr int kHierarchyTestCount = 9;
/// The stable name ("pc-octant-tr", ...).
std::string_view to_string(HierarchyTest t) noexcept;

/// The octant decision for a projection: OctantCuller (which refuses unbounded or asymmetric
/// frusta) on the eye-space frustum frustum_from_matrix(proj, depth). Per-frame float planes far
/// from the origin carry rounding of ~1e-6 that OctantCuller's 1e-5 relative tolerance may refuse
/// for near planes close to the eye, so the decision and the centre distance d1 are made on the
/// projection alone (a rigid camera motion keeps both). Returns the refusal, or "" with *d1 set.
std::string octant_decision(const glm::mat4& proj, DepthConvention depth, double* d1);

/// What the last cull did.
struct HierarchyFrame {
  std::uint64_t visited = 0, tests = 0;  ///< nodes visited, plane tests (TR: 6 per full test)
  bool octant_used = false;              ///< the octant test decided this frame's nodes
  bool tr_used = false;                  ///< TR coherency decided this frame's nodes
  std::string octant_why, tr_why;        ///< why not, when the test uses them and they were not used
};

class HierarchyCuller {
 public:
  struct Options {
    /// Negative control for tests (unsound): TR coherency runs through a change of projection
    /// as if there had been none.
    bool ignore_projection_change = false;
  };
  /// Culls `bvh`, which must outlive the culler and keep its node count; its boxes may change
  /// between culls (a refit), which moved() reports.
  HierarchyCuller(HierarchyTest test, const Bvh& bvh);
  HierarchyCuller(HierarchyTest test, const Bvh& bvh, Options options);
  ~HierarchyCuller();
  HierarchyCuller(HierarchyCuller&&) noexcept;
  HierarchyCuller& operator=(HierarchyCuller&&) noexcept;

  HierarchyTest test() const noexcept;
  /// Forgets every cache: the next cull is a first frame.
  void reset();
  /// The nodes whose boxes changed since the last cull (objects moved, ancestors refitted).
  void moved(const std::vector<std::uint32_t>& nodes);
  /// One frame: `out` gets the visible primitives (input indices of the BVH, leaf order) with
  /// their verdicts. With `node_verdicts`, also every node's verdict (255: not visited).
  void cull(const CullView& view, VisibleSet& out, std::vector<std::uint8_t>* node_verdicts = nullptr);
  const HierarchyFrame& frame() const noexcept;
  /// The plane that rejected a node last (plane coherency; -1: none).
  std::int8_t last_plane(std::uint32_t node) const;
  /// A node's TR coherency state.
  const TrObjectState& tr_state(std::uint32_t node) const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace cullproof

// The simulator's culling engine (internal to cullproof_sim): per-configuration, per-view state
// kept across frames, the per-frame set-up of each configuration and one traversal skeleton
// shared by every timed configuration.
#pragma once

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/core/node_tests.hpp"
#include "cullproof/sim/simulate.hpp"

#include <optional>
#include <string>
#include <vector>

namespace cullproof::sim::detail {

/// A traversal's output: visible leaves with verdict; optionally every visited node's verdict.
struct Output {
  std::vector<std::uint32_t> leaves;
  std::vector<std::uint8_t> verdicts;      ///< Visibility of leaves[i] (inside or intersecting)
  std::vector<std::uint8_t> node_verdict;  ///< when recording: per node, 255 = not visited
  std::uint64_t visited = 0, tests = 0;
};

/// State of one configuration in one view, kept across frames.
struct ConfigView {
  std::vector<std::int8_t> pc;        ///< plane-coherency cache per node
  std::vector<TrObjectState> tr;      ///< TR state per node
  TrCoherencyCuller trc;
  BvhCoherency lib;                   ///< cull_bvh_coherent's cache
  // set-up of the current frame
  const View* view = nullptr;
  node::SelectedPlanes sel;
  bool octant_ok = false;
  std::optional<OctantCuller> oct;  ///< this frame's, when octant_ok
  std::string octant_why;
  bool oct_checked = false, oct_valid = false;  ///< the octant decision for projection oct_proj
  glm::mat4 oct_proj{1.0f};
  double oct_d1 = 0.0;               ///< the centre distance of projection oct_proj
  bool tr_used = false;
  std::string tr_why;
  TrCoherencyCuller::Stats tr_before;
};

/// The octant decision for a projection: OctantCuller (which refuses unbounded or asymmetric
/// frusta) on the eye-space frustum frustum_from_matrix(proj). A rigid camera motion keeps a
/// frustum symmetric and its centre distance d1, so the decision and d1 are made once per
/// projection, not per frame (per-frame float planes far from the origin carry rounding of
/// ~1e-6 that OctantCuller's 1e-5 relative tolerance may refuse for near planes close to the
/// eye; the oracle checks every frame's verdicts, rounding included). Returns the refusal
/// message, or "" with *d1 set.
std::string octant_decision(const glm::mat4& proj, DepthConvention depth, double* d1);

class Engine {
 public:
  Engine(const World& world, int views);
  /// Fresh state (first frame next).
  void reset();
  /// Per-frame set-up of configuration c in view v: planes, octant (if the configuration uses it
  /// and the frustum allows it), TR frame (if the configuration uses it); moved nodes lose their
  /// TR state; a changed projection (zoom) starts a TR frame without pose and disables TR.
  void setup(Config c, int v, const View& view, bool projection_changed, const std::vector<std::uint32_t>& moved);
  /// Runs configuration c in view v (after setup). `record` fills out.node_verdict.
  void run(Config c, int v, Output& out, bool record);
  ConfigView& state(Config c, int v) { return states_[static_cast<std::size_t>(c)][static_cast<std::size_t>(v)]; }

 private:
  const World& w_;
  std::vector<std::vector<ConfigView>> states_;
};

}  // namespace cullproof::sim::detail

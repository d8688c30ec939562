// cullproof bounding-volume hierarchy over AABBs and its culling traversals: plain hierarchical
// culling, plane masking (Assarsson & Möller 2000 §3.4; Cesium "Fast Hierarchical Culling",
// after Sýkora & Jelínek) and plane coherency per node (A&M §3.2).
#pragma once

#include "cullproof/core/cull.hpp"

#include <array>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cullproof {

/// One node of a flattened BVH (32 bytes, 32-byte aligned: a node never straddles two cache
/// lines; the vector allocates with aligned new). Depth-first order: an interior node's left child is
/// the next node, its right child is `right_or_first`. A leaf (count > 0) holds the primitives
/// prim_order[right_or_first .. right_or_first + count).
struct alignas(32) BvhNode {
  Aabb box;
  std::uint32_t right_or_first = 0;
  std::uint32_t count = 0;  ///< 0: interior node
  bool is_leaf() const noexcept { return count != 0; }
};

/// A BVH over a set of boxes. Every node's box is the exact componentwise min/max of its
/// children's boxes (leaf: of its primitives' boxes), so a node encloses its whole subtree.
/// The primitives of any subtree are contiguous in prim_order (and in prim_boxes).
struct Bvh {
  std::vector<BvhNode> nodes;                ///< nodes[0] is the root (empty when no primitives)
  std::vector<std::uint32_t> prim_order;     ///< input indices in leaf order
  std::vector<Aabb> prim_boxes;              ///< prim_boxes[k] is the box of prim_order[k]
  /// subtree_prims[i] = {begin, end}: the subtree of node i holds prim_order[begin .. end).
  std::vector<std::array<std::uint32_t, 2>> subtree_prims;
  std::uint32_t leaf_count() const noexcept;
};

/// The split of the median-split builders (build_bvh, and the simulator's world over instances and
/// their triangles): the longest axis of the bounds of the items' centres (x on a tie with y or z,
/// y on a tie with z), then the items of [first, last) reordered in place so that the `at` whose
/// centres lie lowest along it come first (ties by item number: deterministic). `centre(item)`
/// gives an item's centre. Returns the axis.
template <class Centre>
int median_split(std::uint32_t* first, std::uint32_t* last, std::size_t at, const Centre& centre) {
  glm::vec3 lo = centre(*first), hi = lo;
  for (const std::uint32_t* p = first + 1; p < last; ++p) {
    lo = glm::min(lo, glm::vec3(centre(*p)));
    hi = glm::max(hi, glm::vec3(centre(*p)));
  }
  const glm::vec3 ext = hi - lo;
  const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  std::nth_element(first, first + at, last, [&](std::uint32_t a, std::uint32_t b) {
    const float ca = centre(a)[axis], cb = centre(b)[axis];
    return ca < cb || (ca == cb && a < b);
  });
  return axis;
}

/// Median-split builder (src/core/cull/bvh_build.cpp): split the centroid bounds' longest axis at
/// the median centroid (std::nth_element) until a node holds at most max_leaf_size primitives.
/// O(n log n); depth <= ceil(log2 n) + 1. Boxes must be valid (min <= max).
Bvh build_bvh(const std::vector<Aabb>& boxes, std::uint32_t max_leaf_size = 1);

/// The same tree over new primitive boxes (boxes[i] is primitive i's, as given to build_bvh): every
/// node's box recomputed bottom-up as the exact min/max of its children's (a leaf's: of its
/// primitives'), so a node again encloses its subtree (a refit after objects moved). O(node
/// count). Throws std::invalid_argument when the count of boxes is not the BVH's.
void refit_bvh(Bvh& bvh, const std::vector<Aabb>& boxes);

/// Per-traversal counters.
struct CullStats {
  std::uint64_t nodes_visited = 0;  ///< nodes whose box was tested (or accepted by a mask)
  std::uint64_t plane_tests = 0;    ///< plane/box tests done (one per plane evaluated)
};

/// The visible primitives: input indices with their verdict (inside or intersecting). Order:
/// leaf order. Cleared by the traversals.
struct VisibleSet {
  std::vector<std::uint32_t> indices;
  std::vector<Visibility> verdicts;
  void clear() noexcept { indices.clear(); verdicts.clear(); }
};

/// The visible primitives as runs of leaf order: run r covers the primitives at leaf positions
/// first .. end - 1, i.e. the input indices prim_order[first .. end) of the BVH culled, all with
/// one verdict. The runs are in leaf order, non-empty and maximal: a run never ends where the
/// next one begins with the same verdict. A subtree accepted whole (plane mask 0) is one run
/// however many primitives it holds; a culler that draws contiguous ranges (primitives stored
/// in leaf order) can use them without an index per primitive. Cleared by the traversals.
struct VisibleRun {
  std::uint32_t first = 0;
  std::uint32_t end = 0;
  Visibility verdict = Visibility::outside;
  bool operator==(const VisibleRun& o) const noexcept {
    return first == o.first && end == o.end && verdict == o.verdict;
  }
};
struct VisibleRuns {
  std::vector<VisibleRun> runs;
  /// Working storage of the traversals, not part of the result: two words per primitive of the
  /// largest BVH culled into this object, kept between calls so that culling frame after frame
  /// into the same object allocates nothing.
  std::vector<std::uint32_t> scratch;
  void clear() noexcept { runs.clear(); }
  /// The number of primitives the runs cover.
  std::uint64_t count() const noexcept;
};

/// The same visible set as indices and verdicts (VisibleSet, leaf order): prim_order[k] for every
/// k of every run, in order. prim_order is the culled BVH's (Bvh::prim_order, BvhWide::prim_order).
/// Throws std::out_of_range naming the run if a run is empty or reaches past prim_order.
void expand_runs(const VisibleRuns& runs, const std::vector<std::uint32_t>& prim_order, VisibleSet& out);

/// Plain hierarchical culling (Cesium "Basic Hierarchical Culling"): every visited node gets the
/// six-plane n/p-vertex test; outside prunes, inside accepts the subtree without tests.
void cull_bvh_plain(const Frustum& frustum, const Bvh& bvh, VisibleSet& out, CullStats& stats);

/// Plane masking: bit k of the mask set = the node may still straddle plane k; a child skips
/// the planes its parent is inside (A&M §3.4, Cesium "Hierarchical Culling with Plane
/// Masking"); mask 0 accepts the subtree. Same verdicts as cull_bvh_plain, fewer plane tests.
void cull_bvh_masked(const Frustum& frustum, const Bvh& bvh, VisibleSet& out, CullStats& stats);

/// Per-node plane-coherency cache for cull_bvh_coherent: one byte per node, the plane that
/// rejected the node last time (-1: none). Keep it between frames.
struct BvhCoherency {
  std::vector<std::int8_t> last_plane;
};

/// Masking plus plane coherency per node (A&M §3.2 + §3.4): a node first tests the plane that
/// rejected it last frame. `cache` is resized to the node count if needed. Same verdicts as
/// cull_bvh_plain.
void cull_bvh_coherent(const Frustum& frustum, const Bvh& bvh, BvhCoherency& cache, VisibleSet& out,
                       CullStats& stats);

// ---- Wide BVHs (4 and 8 children per node) ------------------------------------------------------

/// Child reference of a wide node's lane. Interior child: the index of its node (< kBvhWideLeaf).
/// Leaf child: kBvhWideLeaf | primitive count. Unused lane: kBvhWideEmpty.
inline constexpr std::uint32_t kBvhWideLeaf = 0x80000000u;
inline constexpr std::uint32_t kBvhWideEmpty = 0xffffffffu;

/// One node of a W-wide BVH (W = 4: 128 bytes, two cache lines; W = 8: 256 bytes, four), the
/// children's boxes stored as structure of arrays so that one SIMD vector holds one coordinate
/// of all the children. Lane j's box is exactly the box of the binary node it was collapsed from
/// (so it encloses its subtree). Lane j's primitives are prim_order[first[j] .. first[j + 1]);
/// for the last lane the range ends where the node's own range ends (its parent lane's end; the
/// root's: the primitive count). Unused lanes come last, with child == kBvhWideEmpty, first ==
/// the node's end and a copy of lane 0's box (never reported).
template <int W>
struct alignas(64) BvhWideNode {
  /// box[a][j]: coordinate a of lane j's box; a = 0, 1, 2: min x, y, z; a = 3, 4, 5: max x, y, z
  /// (the order of Aabb's six floats).
  float box[6][W];
  std::uint32_t child[W];  ///< child reference of lane j (kBvhWideLeaf, kBvhWideEmpty)
  std::uint32_t first[W];  ///< first primitive (index into prim_order) of lane j's subtree
};
using Bvh4Node = BvhWideNode<4>;
using Bvh8Node = BvhWideNode<8>;
static_assert(sizeof(Bvh4Node) == 128 && sizeof(Bvh8Node) == 256, "wide nodes: whole cache lines");

/// A W-wide BVH collapsed from a binary one (build_bvh4, build_bvh8). Owns copies of the binary
/// BVH's primitive order and boxes (the traversal needs nothing else).
template <int W>
struct BvhWide {
  std::vector<BvhWideNode<W>> nodes;       ///< depth-first; nodes[0] is the root when root == 0
  /// The root as a child reference: 0 (nodes[0]), kBvhWideLeaf | count (the binary root is a
  /// leaf, nodes is empty) or kBvhWideEmpty (no primitives).
  std::uint32_t root = kBvhWideEmpty;
  Aabb root_box{};                         ///< the binary root's box
  std::uint32_t depth = 0;                 ///< node levels (0 when nodes is empty)
  std::vector<std::uint32_t> prim_order;   ///< input indices in leaf order (as Bvh::prim_order)
  std::vector<Aabb> prim_boxes;            ///< prim_boxes[k] is the box of prim_order[k]
};
using Bvh4 = BvhWide<4>;
using Bvh8 = BvhWide<8>;

/// Collapses a binary BVH into a 4- or 8-wide one (src/core/cull/bvh_wide_build.cpp): each wide node
/// starts from a binary interior node's two children and repeatedly replaces its interior child
/// of largest surface area by that child's two children, in place, until it has W children or
/// only leaves (Dammertz, Hanika & Keller 2008, "Shallow Bounding Volume Hierarchies for Fast
/// SIMD Ray Tracing of Incoherent Rays"; Wald, Benthin & Boulos 2008, "Getting Rid of Packets":
/// wide BVHs collapsed from binary ones). The binary nodes' boxes, primitive ranges and leaf
/// order are kept as they are; binary leaves stay leaves. O(binary node count).
Bvh4 build_bvh4(const Bvh& bvh);
Bvh8 build_bvh8(const Bvh& bvh);

}  // namespace cullproof

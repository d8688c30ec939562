// cullproof bounding-volume hierarchy over AABBs and its culling traversals: plain hierarchical
// culling, plane masking (Assarsson & Möller 2000 §3.4; Cesium "Fast Hierarchical Culling",
// after Sýkora & Jelínek) and plane coherency per node (A&M §3.2).
#pragma once

#include "cullproof/cull.hpp"

#include <array>
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

/// Median-split builder (src/cull/bvh_build.cpp): split the centroid bounds' longest axis at
/// the median centroid (std::nth_element) until a node holds at most max_leaf_size primitives.
/// O(n log n); depth <= ceil(log2 n) + 1. Boxes must be valid (min <= max).
Bvh build_bvh(const std::vector<Aabb>& boxes, std::uint32_t max_leaf_size = 1);

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

}  // namespace cullproof

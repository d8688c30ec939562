// BVH culling traversals: plain hierarchical culling, plane masking, plane coherency per node.
//
// Sources: Cesium blog "Fast Hierarchical Culling", pseudocode "Basic Hierarchical Culling" and
// "Hierarchical Culling with Plane Masking", after Sýkora & Jelínek, "Efficient View Frustum
// Culling", §2.5; Assarsson & Möller 2000, §3.4 "Masking" (after Bishop et
// al. 1998) and §3.2 "The Plane-Coherency Test".
// Node test: the n/p-vertex test of A&M §3.1 (pn_vertex.cpp), with the same evaluation order,
// so a node's verdict is bit-for-bit pn_vertex's.
// Mask: bit k set = the node may still straddle plane k (Cesium's "mask[planeIndex] is true
// iff the node might intersect that plane"); a plane whose n-vertex value is >= 0 is cleared
// for the whole subtree; mask 0 = inside every plane: the subtree is accepted without tests.
// Masking never changes a verdict, rounding included: a child box lies within its parent's box
// (exact min/max), the n-vertex of the child is componentwise on the inner side of the
// parent's, and the float evaluation ((nx*x + ny*y) + nz*z) + d is monotone in each coordinate
// for fixed n (each product and each sum rounds monotonically), so a child's n-vertex value is
// >= its parent's and a plane the parent is inside in float is one the child is inside in float.
// Claim: conservative (as pn_vertex). Touching: as pn_vertex.
// Output: visible primitives with verdict inside or intersecting, counters nodes_visited and
// plane_tests (one per plane evaluated, the n-vertex evaluation not counted separately).
// Branches, not branch-free selects: the masks of neighbouring nodes agree, so the branches are
// well predicted (the branch-free variants measured: bench/cull/NOTES.md).
#include "cullproof/core/cull_bvh.hpp"

#include "cullproof/core/bvh_planes.hpp"
#include "cullproof/core/bvh_traverse.hpp"

#include <cstddef>

namespace cullproof {

namespace {

using bvh_detail::floats;
using bvh_detail::Prepared;
using bvh_detail::test_plane;

// The visible set, in traverse_bvh's terms.
struct ToVisibleSet {
  const Bvh& bvh;
  VisibleSet& out;
  void node(std::uint32_t, Visibility) const noexcept {}
  void one(std::uint32_t position, Visibility v) const {
    out.indices.push_back(bvh.prim_order[position]);
    out.verdicts.push_back(v);
  }
  void subtree(std::uint32_t first, std::uint32_t last) const {
    out.indices.insert(out.indices.end(), bvh.prim_order.begin() + first, bvh.prim_order.begin() + last);
    out.verdicts.insert(out.verdicts.end(), last - first, Visibility::inside);
  }
};

// The node tests. kMask: skip planes cleared in the mask. kCoherent: test the cached plane
// first. kMask == false tests all six planes at every node (the plain traversal).
template <bool kMask, bool kCoherent>
void traverse(const Frustum& f, const Bvh& bvh, std::int8_t* cache, VisibleSet& out, CullStats& stats) {
  out.clear();
  const Prepared prep(f);
  auto test = [&](std::uint32_t index, const Aabb& box, std::uint32_t& mask, std::uint64_t& tests) {
    const float* b = floats(box);
    if (!kMask) mask = 0x3fu;
    if (kCoherent) {
      const int c = cache[index];
      if (c >= 0 && (mask >> c) & 1u) {
        ++tests;
        const int r = test_plane(prep.p[c], b);
        if (r == 0) return Visibility::outside;
        if (r == 2) mask &= ~(1u << c);
      }
      for (std::uint32_t m = mask & ~(c >= 0 ? 1u << c : 0u); m != 0; m &= m - 1) {
        const int i = __builtin_ctz(m);
        ++tests;
        const int r = test_plane(prep.p[i], b);
        if (r == 0) {
          cache[index] = static_cast<std::int8_t>(i);
          return Visibility::outside;
        }
        if (r == 2) mask &= ~(1u << i);
      }
      return mask == 0 ? Visibility::inside : Visibility::intersecting;
    }
    return node::masked(prep, box, mask, tests);  // the set bits, lowest first
  };
  auto prim_test = [&](const Aabb& box, std::uint32_t mask, std::uint64_t& tests) {
    const int r = bvh_detail::test_masked(prep, floats(box), kMask ? mask : 0x3fu, tests);
    return r == 0 ? Visibility::outside : r == 1 ? Visibility::intersecting : Visibility::inside;
  };
  ToVisibleSet emit{bvh, out};
  traverse_bvh(bvh, test, prim_test, emit, stats.nodes_visited, stats.plane_tests);
}

}  // namespace

void cull_bvh_plain(const Frustum& f, const Bvh& bvh, VisibleSet& out, CullStats& stats) {
  traverse<false, false>(f, bvh, nullptr, out, stats);
}

void cull_bvh_masked(const Frustum& f, const Bvh& bvh, VisibleSet& out, CullStats& stats) {
  traverse<true, false>(f, bvh, nullptr, out, stats);
}

void cull_bvh_coherent(const Frustum& f, const Bvh& bvh, BvhCoherency& cache, VisibleSet& out,
                       CullStats& stats) {
  if (cache.last_plane.size() != bvh.nodes.size()) cache.last_plane.assign(bvh.nodes.size(), -1);
  traverse<true, true>(f, bvh, cache.last_plane.data(), out, stats);
}

}  // namespace cullproof

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

#include <cstddef>

namespace cullproof {

namespace {

using bvh_detail::floats;
using bvh_detail::Prepared;
using bvh_detail::test_plane;

void append_subtree(const Bvh& bvh, std::uint32_t node, VisibleSet& out) {
  const std::uint32_t first = bvh.subtree_prims[node][0], last = bvh.subtree_prims[node][1];
  out.indices.insert(out.indices.end(), bvh.prim_order.begin() + first, bvh.prim_order.begin() + last);
  out.verdicts.insert(out.verdicts.end(), last - first, Visibility::inside);
}

struct Entry {
  std::uint32_t node;
  std::uint32_t mask;
};

// Shared traversal. kMask: skip planes cleared in the mask. kCoherent: test the cached plane
// first. kMask == false tests all six planes at every node (the plain traversal).
template <bool kMask, bool kCoherent>
void traverse(const Frustum& f, const Bvh& bvh, std::int8_t* cache, VisibleSet& out, CullStats& stats) {
  out.clear();
  if (bvh.nodes.empty()) return;
  const Prepared prep(f);
  Entry stack[128];
  int top = 0;
  stack[top++] = Entry{0, 0x3fu};
  std::uint64_t visited = 0, tests = 0;
  while (top > 0) {
    const Entry e = stack[--top];
    const BvhNode& node = bvh.nodes[e.node];
    ++visited;
    const float* b = floats(node.box);
    std::uint32_t mask = kMask ? e.mask : 0x3fu;
    bool outside = false;
    if (kCoherent) {
      const int c = cache[e.node];
      if (c >= 0 && (mask >> c) & 1u) {
        ++tests;
        const int r = test_plane(prep.p[c], b);
        if (r == 0) outside = true;
        else if (r == 2) mask &= ~(1u << c);
      }
      if (!outside) {
        for (std::uint32_t m = mask & ~(c >= 0 ? 1u << c : 0u); m != 0; m &= m - 1) {
          const int i = __builtin_ctz(m);
          ++tests;
          const int r = test_plane(prep.p[i], b);
          if (r == 0) { outside = true; cache[e.node] = static_cast<std::int8_t>(i); break; }
          if (r == 2) mask &= ~(1u << i);
        }
      }
    } else {
      for (std::uint32_t m = mask; m != 0; m &= m - 1) {  // the set bits, lowest first
        const int i = __builtin_ctz(m);
        ++tests;
        const int r = test_plane(prep.p[i], b);
        if (r == 0) { outside = true; break; }
        if (r == 2) mask &= ~(1u << i);
      }
    }
    if (outside) continue;
    if (mask == 0) {
      append_subtree(bvh, e.node, out);
      continue;
    }
    if (node.is_leaf()) {
      if (node.count == 1) {  // the leaf box is the primitive's box
        out.indices.push_back(bvh.prim_order[node.right_or_first]);
        out.verdicts.push_back(Visibility::intersecting);
        continue;
      }
      for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
        const int r = bvh_detail::test_masked(prep, floats(bvh.prim_boxes[k]), kMask ? mask : 0x3fu, tests);
        if (r == 0) continue;
        out.indices.push_back(bvh.prim_order[k]);
        out.verdicts.push_back(r == 1 ? Visibility::intersecting : Visibility::inside);
      }
      continue;
    }
    __builtin_prefetch(&bvh.nodes[node.right_or_first]);  // popped after the left subtree
    stack[top++] = Entry{node.right_or_first, mask};
    stack[top++] = Entry{e.node + 1, mask};
  }
  stats.nodes_visited += visited;
  stats.plane_tests += tests;
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

// Hierarchical culling over a binary BVH with the node test chosen by the caller: the one
// traversal behind cull_bvh_plain, cull_bvh_masked and cull_bvh_coherent (cull_bvh.hpp) and
// behind every configuration the simulator times (src/sim/engine.cpp). Sources: Cesium blog
// "Fast Hierarchical Culling" ("Basic Hierarchical Culling", "Hierarchical Culling with Plane
// Masking"), after Sýkora & Jelínek, "Efficient View Frustum Culling", §2.5; Assarsson & Möller
// 2000, §3.4.
#pragma once

#include "cullproof/core/cull_bvh.hpp"

#include <cstdint>

namespace cullproof {

/// Depth first, the left child first. At each node reached with plane mask m (the root with
/// 0x3f), test(node, box, mask, tests) gives the node's verdict, mask starting as m (the test may
/// clear the planes the node is inside: its children start from what it leaves):
///  - outside: the subtree is skipped;
///  - inside: every primitive of the subtree is reported inside (emit.subtree(first, last), the
///    positions bvh.subtree_prims[node] in bvh.prim_order);
///  - intersecting: a leaf of one primitive reports it intersecting (emit.one(position, v)); a
///    leaf of several tests each (prim_test(box, mask, tests): outside, intersecting or inside)
///    and reports those not outside; an interior node's children are visited with the mask.
/// emit.node(node, verdict) sees every node tested. Adds to `visited` and `tests`.
template <class NodeTest, class PrimTest, class Emit>
void traverse_bvh(const Bvh& bvh, NodeTest&& test, PrimTest&& prim_test, Emit& emit, std::uint64_t& visited,
                  std::uint64_t& tests) {
  if (bvh.nodes.empty()) return;
  struct Entry {
    std::uint32_t node, mask;
  };
  Entry stack[256];  // depth-first over a binary tree: one pending right child per level
  int top = 0;
  stack[top++] = Entry{0, 0x3fu};
  std::uint64_t n_visited = 0, n_tests = 0;
  while (top > 0) {
    const Entry e = stack[--top];
    const BvhNode& node = bvh.nodes[e.node];
    ++n_visited;
    std::uint32_t mask = e.mask;
    const Visibility v = test(e.node, node.box, mask, n_tests);
    emit.node(e.node, v);
    if (v == Visibility::outside) continue;
    if (v == Visibility::inside) {
      emit.subtree(bvh.subtree_prims[e.node][0], bvh.subtree_prims[e.node][1]);
      continue;
    }
    if (node.is_leaf()) {
      if (node.count == 1) {  // the leaf box is the primitive's box
        emit.one(node.right_or_first, Visibility::intersecting);
        continue;
      }
      for (std::uint32_t k = node.right_or_first; k < node.right_or_first + node.count; ++k) {
        const Visibility r = prim_test(bvh.prim_boxes[k], mask, n_tests);
        if (r != Visibility::outside) emit.one(k, r);
      }
      continue;
    }
    __builtin_prefetch(&bvh.nodes[node.right_or_first]);  // popped after the left subtree
    stack[top++] = Entry{node.right_or_first, mask};
    stack[top++] = Entry{e.node + 1, mask};
  }
  visited += n_visited;
  tests += n_tests;
}

}  // namespace cullproof

// Wide BVHs (4 or 8 children per node) by collapsing a binary BVH.
//
// Sources: H. Dammertz, J. Hanika, A. Keller, "Shallow Bounding Volume Hierarchies for Fast SIMD
// Ray Tracing of Incoherent Rays", EGSR 2008 (the QBVH: four children per node, their boxes
// stored as structure of arrays and tested with one SIMD instruction per coordinate, built by
// collapsing binary splits); I. Wald, C. Benthin, S. Boulos, "Getting Rid of Packets", IRT 2008
// (multi-branching BVHs collapsed from binary ones). Rule used here (the greedy one of wide-BVH
// builders such as Embree's): a wide node starts from the two children of a binary interior
// node and repeatedly opens, in place, its interior child of largest surface area until it has
// W children or only leaves (ties: the first such child).
// Soundness: nothing is recomputed. A lane's box is the binary node's box (exact min/max of its
// subtree), its primitive range the binary node's range; opening a child in place keeps the
// children in binary depth-first order, so the wide depth-first traversal meets the leaves in
// the binary leaf order. Depth: at most the binary depth (each wide level consumes at least one
// binary level).
#include "cullproof/core/cull_bvh.hpp"

#include <cassert>

namespace cullproof {

namespace {

float half_area(const Aabb& b) noexcept {
  const glm::vec3 e = b.max - b.min;
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

template <int W>
struct Collapser {
  const Bvh& bin;
  BvhWide<W>& out;

  std::uint32_t left(std::uint32_t i) const noexcept { return i + 1; }
  std::uint32_t right(std::uint32_t i) const noexcept { return bin.nodes[i].right_or_first; }

  // Child reference of binary node i (building its wide subtree if interior).
  std::uint32_t ref(std::uint32_t i, std::uint32_t level) {
    const BvhNode& n = bin.nodes[i];
    if (n.is_leaf()) return kBvhWideLeaf | n.count;
    return build(i, level);
  }

  // Builds the wide node for binary interior node b; returns its index.
  std::uint32_t build(std::uint32_t b, std::uint32_t level) {
    if (level > out.depth) out.depth = level;
    std::uint32_t kids[W] = {left(b), right(b)};
    int count = 2;
    while (count < W) {
      int best = -1;
      float best_area = -1.0f;
      for (int j = 0; j < count; ++j) {
        if (bin.nodes[kids[j]].is_leaf()) continue;
        const float a = half_area(bin.nodes[kids[j]].box);
        if (a > best_area) { best_area = a; best = j; }
      }
      if (best < 0) break;
      const std::uint32_t open = kids[best];
      for (int j = count; j > best + 1; --j) kids[j] = kids[j - 1];
      kids[best] = left(open);
      kids[best + 1] = right(open);
      ++count;
    }
    const std::uint32_t index = static_cast<std::uint32_t>(out.nodes.size());
    out.nodes.emplace_back();
    const std::uint32_t end = bin.subtree_prims[b][1];
    for (int j = 0; j < W; ++j) {
      const Aabb& box = bin.nodes[kids[j < count ? j : 0]].box;
      BvhWideNode<W>& w = out.nodes[index];
      for (int a = 0; a < 3; ++a) {
        w.box[a][j] = box.min[a];
        w.box[3 + a][j] = box.max[a];
      }
      w.first[j] = j < count ? bin.subtree_prims[kids[j]][0] : end;
      w.child[j] = kBvhWideEmpty;
    }
    for (int j = 0; j < count; ++j) {  // depth-first: the children's wide nodes follow
      const std::uint32_t r = ref(kids[j], level + 1);
      out.nodes[index].child[j] = r;  // (ref may reallocate out.nodes: index, not a reference)
    }
    return index;
  }
};

template <int W>
BvhWide<W> collapse(const Bvh& bvh) {
  BvhWide<W> out;
  out.prim_order = bvh.prim_order;
  out.prim_boxes = bvh.prim_boxes;
  if (bvh.nodes.empty()) return out;
  out.root_box = bvh.nodes[0].box;
  if (bvh.nodes[0].is_leaf()) {
    out.root = kBvhWideLeaf | bvh.nodes[0].count;
    return out;
  }
  // Interior binary nodes: one fewer than the leaves; a wide node consumes at least one.
  out.nodes.reserve(bvh.nodes.size() / 2 + 1);
  Collapser<W> c{bvh, out};
  out.root = c.build(0, 1);
  assert(out.root == 0);
  return out;
}

}  // namespace

Bvh4 build_bvh4(const Bvh& bvh) { return collapse<4>(bvh); }
Bvh8 build_bvh8(const Bvh& bvh) { return collapse<8>(bvh); }

}  // namespace cullproof

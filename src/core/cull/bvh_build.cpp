// Median-split BVH builder over AABBs.
//
// Source: the classic top-down median split (Kay & Kajiya 1986 style object median; see also
// Ericson, "Real-Time Collision Detection", §6.2.1 "Top-down construction", median of the
// centroid coordinates along the axis of greatest spread). Chosen over binned SAH because
// view-frustum culling cost is not the ray-tracing cost SAH models, and because its soundness
// and depth bound are easy to state: every node box is the exact min/max of its subtree's boxes
// (float min/max is exact), so a node encloses its subtree; each split halves the primitive
// count, so the depth is at most ceil(log2 n) + 1.
// Layout: depth-first, left child at index + 1, so a subtree is a contiguous node range and its
// primitives a contiguous range of prim_order.
#include "cullproof/core/cull_bvh.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace cullproof {

namespace {

struct Builder {
  const std::vector<Aabb>& boxes;
  std::vector<glm::vec3> centroids;
  Bvh& bvh;
  std::uint32_t leaf_size;

  Aabb bounds(std::uint32_t first, std::uint32_t last) const {
    Aabb b = boxes[bvh.prim_order[first]];
    for (std::uint32_t k = first + 1; k < last; ++k) {
      const Aabb& o = boxes[bvh.prim_order[k]];
      b.min = glm::min(b.min, o.min);
      b.max = glm::max(b.max, o.max);
    }
    return b;
  }

  // A node's box is the exact min/max of its primitives' boxes: a leaf's computed from them, an
  // interior node's as the union of its children's (the same values, min and max being exact).
  void build(std::uint32_t first, std::uint32_t last) {
    const std::uint32_t index = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes.push_back(BvhNode{Aabb{}, 0, 0});
    bvh.subtree_prims.push_back({first, last});
    const std::uint32_t n = last - first;
    if (n <= leaf_size) {
      bvh.nodes[index].box = bounds(first, last);
      bvh.nodes[index].right_or_first = first;
      bvh.nodes[index].count = n;
      return;
    }
    const std::uint32_t mid = first + n / 2;
    auto* base = bvh.prim_order.data();
    median_split(base + first, base + last, n / 2, [&](std::uint32_t k) -> const glm::vec3& { return centroids[k]; });
    build(first, mid);
    const std::uint32_t right = static_cast<std::uint32_t>(bvh.nodes.size());
    bvh.nodes[index].right_or_first = right;
    build(mid, last);
    const Aabb& a = bvh.nodes[index + 1].box;
    const Aabb& b = bvh.nodes[right].box;
    bvh.nodes[index].box = Aabb{glm::min(a.min, b.min), glm::max(a.max, b.max)};
  }
};

}  // namespace

std::uint32_t Bvh::leaf_count() const noexcept {
  std::uint32_t c = 0;
  for (const BvhNode& n : nodes) c += n.is_leaf() ? 1u : 0u;
  return c;
}

Bvh build_bvh(const std::vector<Aabb>& boxes, std::uint32_t max_leaf_size) {
  Bvh bvh;
  if (boxes.empty()) return bvh;
  if (max_leaf_size == 0) max_leaf_size = 1;
  bvh.prim_order.resize(boxes.size());
  std::iota(bvh.prim_order.begin(), bvh.prim_order.end(), 0u);
  Builder b{boxes, {}, bvh, max_leaf_size};
  b.centroids.reserve(boxes.size());
  for (const Aabb& box : boxes) b.centroids.push_back(box.center());
  bvh.nodes.reserve(2 * boxes.size());
  bvh.subtree_prims.reserve(2 * boxes.size());
  b.build(0, static_cast<std::uint32_t>(boxes.size()));
  bvh.prim_boxes.reserve(boxes.size());
  for (std::uint32_t k : bvh.prim_order) bvh.prim_boxes.push_back(boxes[k]);
  return bvh;
}

void refit_bvh(Bvh& bvh, const std::vector<Aabb>& boxes) {
  if (boxes.size() != bvh.prim_order.size())
    throw std::invalid_argument("refit_bvh: " + std::to_string(boxes.size()) + " boxes for a BVH over " +
                                std::to_string(bvh.prim_order.size()) + " primitives");
  for (std::size_t k = 0; k < bvh.prim_order.size(); ++k) bvh.prim_boxes[k] = boxes[bvh.prim_order[k]];
  auto join = [](Aabb a, const Aabb& b) {
    a.min = glm::min(a.min, b.min);
    a.max = glm::max(a.max, b.max);
    return a;
  };
  // Depth-first order puts every child after its parent: from the last node back, a node's
  // children are refitted before it.
  for (std::size_t i = bvh.nodes.size(); i-- > 0;) {
    BvhNode& n = bvh.nodes[i];
    if (n.is_leaf()) {
      Aabb b = bvh.prim_boxes[n.right_or_first];
      for (std::uint32_t k = n.right_or_first + 1; k < n.right_or_first + n.count; ++k) b = join(b, bvh.prim_boxes[k]);
      n.box = b;
    } else {
      n.box = join(bvh.nodes[i + 1].box, bvh.nodes[n.right_or_first].box);
    }
  }
}

}  // namespace cullproof

// Unit tests of the BVH builder and its traversals (cullproof/cull_bvh.hpp).
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/cull_bvh.hpp"

#include <algorithm>
#include <map>
#include <random>

namespace cullproof {
namespace {

using V = Visibility;

std::vector<Aabb> scene(std::uint32_t seed, int n, float extent = 40.0f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> c(-extent, extent), e(0.0f, 1.5f);
  std::vector<Aabb> out;
  for (int i = 0; i < n; ++i) {
    const glm::vec3 lo(c(rng), c(rng), c(rng) - extent / 2);
    out.push_back(Aabb{lo, lo + glm::vec3(e(rng), e(rng), e(rng))});
  }
  return out;
}

std::map<std::uint32_t, Visibility> as_map(const VisibleSet& s) {
  std::map<std::uint32_t, Visibility> m;
  for (std::size_t k = 0; k < s.indices.size(); ++k) m[s.indices[k]] = s.verdicts[k];
  return m;
}

std::map<std::uint32_t, Visibility> flat(const Frustum& f, const std::vector<Aabb>& boxes) {
  std::map<std::uint32_t, Visibility> m;
  for (std::uint32_t i = 0; i < boxes.size(); ++i) {
    const V v = pn_vertex(f, boxes[i]);
    if (v != V::outside) m[i] = v;
  }
  return m;
}

TEST(CullBvh, BuilderNodesEncloseTheirSubtreesAndCoverEveryPrimitiveOnce) {
  for (std::uint32_t leaf : {1u, 4u}) {
    const auto boxes = scene(1, 1000);
    const Bvh bvh = build_bvh(boxes, leaf);
    std::vector<int> seen(boxes.size(), 0);
    for (std::size_t i = 0; i < bvh.nodes.size(); ++i) {
      const BvhNode& n = bvh.nodes[i];
      if (n.is_leaf()) {
        EXPECT_LE(n.count, leaf);
        for (std::uint32_t k = n.right_or_first; k < n.right_or_first + n.count; ++k) {
          const Aabb& b = boxes[bvh.prim_order[k]];
          ++seen[bvh.prim_order[k]];
          EXPECT_TRUE(glm::all(glm::lessThanEqual(n.box.min, b.min)) && glm::all(glm::greaterThanEqual(n.box.max, b.max)));
        }
      } else {
        for (std::size_t child : {i + 1, std::size_t(n.right_or_first)}) {
          const Aabb& b = bvh.nodes[child].box;
          EXPECT_TRUE(glm::all(glm::lessThanEqual(n.box.min, b.min)) && glm::all(glm::greaterThanEqual(n.box.max, b.max)));
        }
      }
    }
    for (int s : seen) EXPECT_EQ(s, 1);
  }
}

TEST(CullBvh, EmptyAndSingleBox) {
  const Bvh empty = build_bvh({});
  VisibleSet out;
  CullStats st;
  cull_bvh_masked(test::sym90(), empty, out, st);
  EXPECT_TRUE(out.indices.empty());
  const Bvh one = build_bvh({test::inside_box()});
  cull_bvh_plain(test::sym90(), one, out, st);
  ASSERT_EQ(out.indices.size(), 1u);
  EXPECT_EQ(out.verdicts[0], V::inside);
}

TEST(CullBvh, AllTraversalsGiveTheFlatPnVertexVerdicts) {
  const auto boxes = scene(2, 5000);
  for (std::uint32_t leaf : {1u, 3u}) {
    const Bvh bvh = build_bvh(boxes, leaf);
    for (const Frustum& f : {test::sym90(), test::sym90_infinite(), test::ortho(), test::off_axis()}) {
      const auto expect = flat(f, boxes);
      VisibleSet plain, masked, coherent;
      CullStats sp, sm, sc;
      BvhCoherency cache;
      cull_bvh_plain(f, bvh, plain, sp);
      cull_bvh_masked(f, bvh, masked, sm);
      cull_bvh_coherent(f, bvh, cache, coherent, sc);
      EXPECT_EQ(as_map(plain), expect);
      EXPECT_EQ(as_map(masked), expect) << "masking changed a verdict";
      EXPECT_EQ(as_map(coherent), expect);
      cull_bvh_coherent(f, bvh, cache, coherent, sc);  // second frame, warm cache
      EXPECT_EQ(as_map(coherent), expect);
      EXPECT_LE(sm.plane_tests, sp.plane_tests) << "masking adds plane tests";
      EXPECT_EQ(sm.nodes_visited, sp.nodes_visited);
    }
  }
}

TEST(CullBvh, EverythingInsideVisitsOnlyTheRoot) {
  const auto boxes = scene(3, 2000, 1.0f);
  Bvh bvh = build_bvh(boxes);
  Frustum big = test::ortho();
  for (int i = 0; i < 6; ++i) big[i].d = 1000;
  VisibleSet out;
  CullStats st;
  cull_bvh_masked(big, bvh, out, st);
  EXPECT_EQ(out.indices.size(), boxes.size());
  EXPECT_EQ(st.nodes_visited, 1u);
  EXPECT_EQ(st.plane_tests, 6u);
  for (V v : out.verdicts) EXPECT_EQ(v, V::inside);
}

TEST(CullBvh, CoherencyCacheSavesPlaneTestsOnAStillFrame) {
  const auto boxes = scene(4, 5000);
  const Bvh bvh = build_bvh(boxes);
  BvhCoherency cache;
  VisibleSet out;
  CullStats first, second;
  cull_bvh_coherent(test::sym90(), bvh, cache, out, first);
  cull_bvh_coherent(test::sym90(), bvh, cache, out, second);
  EXPECT_LT(second.plane_tests, first.plane_tests);
}

}  // namespace
}  // namespace cullproof

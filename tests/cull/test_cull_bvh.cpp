// Unit tests of the BVH builder and its traversals (cullproof/core/cull_bvh.hpp).
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/simd/bvh_wide.hpp"

#include <glm/ext/matrix_transform.hpp>
#include <hwy/targets.h>

#include <algorithm>
#include <map>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>

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

// ---- Wide BVHs (build_bvh4 / build_bvh8, cull_bvh4_masked / cull_bvh8_masked) ----------------------

// Both widths through one interface, for the typed tests.
template <int W>
BvhWide<W> build_wide(const Bvh& bin);
template <>
Bvh4 build_wide<4>(const Bvh& bin) { return build_bvh4(bin); }
template <>
Bvh8 build_wide<8>(const Bvh& bin) { return build_bvh8(bin); }
void cull_wide(const Frustum& f, const Bvh4& bvh, VisibleSet& out, CullStats& st) { cull_bvh4_masked(f, bvh, out, st); }
void cull_wide(const Frustum& f, const Bvh8& bvh, VisibleSet& out, CullStats& st) { cull_bvh8_masked(f, bvh, out, st); }
void cull_wide(const Frustum& f, const Bvh4& bvh, VisibleRuns& out, CullStats& st) { cull_bvh4_masked(f, bvh, out, st); }
void cull_wide(const Frustum& f, const Bvh8& bvh, VisibleRuns& out, CullStats& st) { cull_bvh8_masked(f, bvh, out, st); }

template <class T>
class CullBvhWide : public ::testing::Test {};
using Widths = ::testing::Types<std::integral_constant<int, 4>, std::integral_constant<int, 8>>;
struct WidthName {
  template <class T>
  static std::string GetName(int) { return "W" + std::to_string(T::value); }
};
TYPED_TEST_SUITE(CullBvhWide, Widths, WidthName);

// The output of `got` is exactly `want`'s: same indices, same verdicts, same order.
::testing::AssertionResult same_output(const VisibleSet& want, const VisibleSet& got) {
  if (got.indices.size() != got.verdicts.size())
    return ::testing::AssertionFailure() << "indices/verdicts size mismatch";
  if (got.indices.size() != want.indices.size())
    return ::testing::AssertionFailure() << "visible count " << got.indices.size() << ", expected " << want.indices.size();
  for (std::size_t k = 0; k < want.indices.size(); ++k) {
    if (got.indices[k] != want.indices[k] || got.verdicts[k] != want.verdicts[k])
      return ::testing::AssertionFailure() << "at position " << k << ": index " << got.indices[k] << " "
                                           << to_string(got.verdicts[k]) << ", expected " << want.indices[k] << " "
                                           << to_string(want.verdicts[k]);
  }
  return ::testing::AssertionSuccess();
}

// The runs are well formed (non-empty, in leaf order, within n_prims primitives, maximal: no run
// ends where the next begins with the same verdict, no verdict `outside`) and expand to `want`.
::testing::AssertionResult runs_are(const VisibleSet& want, const VisibleRuns& runs,
                                    const std::vector<std::uint32_t>& prim_order) {
  for (std::size_t i = 0; i < runs.runs.size(); ++i) {
    const VisibleRun& r = runs.runs[i];
    if (r.first >= r.end || r.end > prim_order.size() || r.verdict == V::outside)
      return ::testing::AssertionFailure() << "run " << i << " [" << r.first << ", " << r.end << ") "
                                           << to_string(r.verdict) << " is empty, too long or outside";
    if (i > 0) {
      const VisibleRun& p = runs.runs[i - 1];
      if (r.first < p.end) return ::testing::AssertionFailure() << "run " << i << " begins before run " << i - 1 << " ends";
      if (r.first == p.end && r.verdict == p.verdict)
        return ::testing::AssertionFailure() << "runs " << i - 1 << " and " << i << " are not merged";
    }
  }
  VisibleSet got;
  expand_runs(runs, prim_order, got);
  if (runs.count() != got.indices.size()) return ::testing::AssertionFailure() << "count() " << runs.count();
  return same_output(want, got);
}

template <int W>
Aabb lane_box(const BvhWideNode<W>& n, int j) {
  return Aabb{glm::vec3(n.box[0][j], n.box[1][j], n.box[2][j]), glm::vec3(n.box[3][j], n.box[4][j], n.box[5][j])};
}

bool encloses(const Aabb& outer, const Aabb& inner) {
  return glm::all(glm::lessThanEqual(outer.min, inner.min)) && glm::all(glm::greaterThanEqual(outer.max, inner.max));
}

bool same_box(const Aabb& a, const Aabb& b) { return a.min == b.min && a.max == b.max; }

// Walks the wide BVH checking its invariants against the binary one; appends the leaf lanes'
// primitive ranges in traversal order and the lane boxes.
template <int W>
void check_wide(const BvhWide<W>& wide, std::uint32_t node, std::uint32_t first, std::uint32_t end, const Aabb& box,
                std::uint32_t level, std::vector<std::array<std::uint32_t, 2>>& leaves, std::vector<Aabb>& lanes) {
  const BvhWideNode<W>& n = wide.nodes[node];
  EXPECT_LE(level, wide.depth);
  EXPECT_EQ(n.first[0], first);
  int used = 0;
  while (used < W && n.child[used] != kBvhWideEmpty) ++used;
  EXPECT_GE(used, 2) << "a wide node has at least the two children of a binary node";
  for (int j = used; j < W; ++j) {
    EXPECT_EQ(n.child[j], kBvhWideEmpty) << "unused lanes come last";
    EXPECT_EQ(n.first[j], end);
  }
  for (int j = 0; j < used; ++j) {
    const std::uint32_t f = n.first[j], e = j + 1 < W ? n.first[j + 1] : end;
    ASSERT_LT(f, e) << "lane ranges are non-empty and in order";
    EXPECT_TRUE(encloses(box, lane_box(n, j)));
    for (std::uint32_t k = f; k < e; ++k) EXPECT_TRUE(encloses(lane_box(n, j), wide.prim_boxes[k]));
    lanes.push_back(lane_box(n, j));
    if (n.child[j] >= kBvhWideLeaf) {
      EXPECT_EQ(n.child[j] & ~kBvhWideLeaf, e - f) << "leaf lane count";
      leaves.push_back({f, e});
    } else {
      EXPECT_GT(n.child[j], node) << "depth-first: children follow their parent";
      check_wide(wide, n.child[j], f, e, lane_box(n, j), level + 1, leaves, lanes);
    }
  }
  if (used < W) {
    for (int j = 0; j < used; ++j) EXPECT_GE(n.child[j], kBvhWideLeaf) << "a node is filled while it has interior lanes";
  }
}

TYPED_TEST(CullBvhWide, CollapseKeepsTheBinaryBoxesRangesAndLeafOrder) {
  constexpr int W = TypeParam::value;
  for (std::uint32_t leaf : {1u, 3u}) {
    for (int count : {2, 3, 5, 9, 1000}) {
      SCOPED_TRACE("leaf " + std::to_string(leaf) + " count " + std::to_string(count));
      const auto boxes = scene(11, count);
      const Bvh bin = build_bvh(boxes, leaf);
      const BvhWide<W> wide = build_wide<W>(bin);
      EXPECT_EQ(wide.prim_order, bin.prim_order);
      ASSERT_EQ(wide.prim_boxes.size(), bin.prim_boxes.size());
      EXPECT_TRUE(same_box(wide.root_box, bin.nodes[0].box));
      if (bin.nodes[0].is_leaf()) {  // the root is a leaf: no wide node
        EXPECT_EQ(wide.root, kBvhWideLeaf | bin.nodes[0].count);
        EXPECT_TRUE(wide.nodes.empty());
        continue;
      }
      ASSERT_EQ(wide.root, 0u);
      std::vector<std::array<std::uint32_t, 2>> leaves;
      std::vector<Aabb> lanes;
      check_wide(wide, 0, 0, static_cast<std::uint32_t>(boxes.size()), wide.root_box, 1, leaves, lanes);
      // The leaf lanes are the binary leaves, in the binary depth-first order.
      std::vector<std::array<std::uint32_t, 2>> bin_leaves;
      for (const BvhNode& n : bin.nodes)
        if (n.is_leaf()) bin_leaves.push_back({n.right_or_first, n.right_or_first + n.count});
      EXPECT_EQ(leaves, bin_leaves);
      // Every lane box is the box of a binary node (nothing recomputed).
      for (const Aabb& b : lanes)
        EXPECT_TRUE(std::any_of(bin.nodes.begin(), bin.nodes.end(), [&](const BvhNode& n) { return same_box(n.box, b); }));
      EXPECT_LE(wide.nodes.size(), (bin.nodes.size() - 1) / 2) << "at most one wide node per binary interior node";
    }
  }
}

TYPED_TEST(CullBvhWide, EmptySingleAndRootLeaf) {
  constexpr int W = TypeParam::value;
  VisibleSet out, want;
  CullStats st, sw;
  const BvhWide<W> empty = build_wide<W>(build_bvh({}));
  EXPECT_EQ(empty.root, kBvhWideEmpty);
  out.indices.push_back(7);  // the traversal clears the output
  out.verdicts.push_back(V::inside);
  cull_wide(test::sym90(), empty, out, st);
  EXPECT_TRUE(out.indices.empty() && out.verdicts.empty());
  EXPECT_EQ(st.nodes_visited, 0u);
  EXPECT_EQ(st.plane_tests, 0u);
  VisibleRuns runs;
  runs.runs.push_back(VisibleRun{0, 1, V::inside});  // cleared too
  cull_wide(test::sym90(), empty, runs, st);
  EXPECT_TRUE(runs.runs.empty());
  EXPECT_EQ(st.nodes_visited, 0u);
  // One primitive: inside, straddling, touching from outside (intersecting), touching from
  // inside (inside), outside, behind.
  for (const Aabb& b : {test::inside_box(), test::straddle_right_box(), test::touch_near_outside_box(),
                        test::touch_near_inside_box(), test::outside_box(), test::behind_box()}) {
    const Bvh bin = build_bvh({b});
    const BvhWide<W> wide = build_wide<W>(bin);
    EXPECT_EQ(wide.root, kBvhWideLeaf | 1u);
    EXPECT_TRUE(wide.nodes.empty());
    cull_bvh_masked(test::sym90(), bin, want, sw);
    cull_wide(test::sym90(), wide, out, st);
    EXPECT_TRUE(same_output(want, out));
    CullStats sr;
    cull_wide(test::sym90(), wide, runs, sr);
    EXPECT_TRUE(runs_are(want, runs, wide.prim_order));
    const V v = pn_vertex(test::sym90(), b);
    ASSERT_EQ(out.indices.size(), v == V::outside ? 0u : 1u);
    if (v != V::outside) {
      EXPECT_EQ(out.verdicts[0], v);
    }
  }
  EXPECT_EQ(st.nodes_visited, sw.nodes_visited);
  EXPECT_EQ(st.plane_tests, sw.plane_tests);
  // The root is a leaf of several primitives (leaf size >= count): each primitive tested.
  const std::vector<Aabb> few = {test::inside_box(), test::outside_box(), test::straddle_right_box(),
                                 test::touch_near_outside_box()};
  const Bvh bin = build_bvh(few, 8);
  const BvhWide<W> wide = build_wide<W>(bin);
  EXPECT_EQ(wide.root, kBvhWideLeaf | 4u);
  cull_bvh_masked(test::sym90(), bin, want, sw);
  cull_wide(test::sym90(), wide, out, st);
  EXPECT_TRUE(same_output(want, out));
  EXPECT_EQ(as_map(out), flat(test::sym90(), few));
  cull_wide(test::sym90(), wide, runs, st);
  EXPECT_TRUE(runs_are(want, runs, wide.prim_order));
}

// Boxes on an integer grid: against ortho() (planes x, y = +-1, z = -1, -10) and sym90() many
// boxes touch a plane exactly, from inside and from outside; flat boxes and point boxes too.
std::vector<Aabb> grid_scene() {
  std::vector<Aabb> out;
  for (int x = -3; x <= 2; ++x)
    for (int y = -3; y <= 2; ++y)
      for (int z = -12; z <= 1; ++z) {
        const glm::vec3 lo(x, y, z);
        out.push_back(Aabb{lo, lo + glm::vec3(1)});
        out.push_back(Aabb{lo, lo + glm::vec3(0, 1, 0.5f)});  // flat in x
        out.push_back(Aabb{lo, lo});                          // a point
      }
  return out;
}

// Frusta for the equality tests: the fixtures, a plane n == 0 containing nothing, a half-space
// alone (the other planes n == 0, d >= 0: all space), and seeded random perspective and
// orthographic views.
std::vector<std::pair<std::string, Frustum>> test_frusta() {
  std::vector<std::pair<std::string, Frustum>> fs = {
      {"sym90", test::sym90()}, {"sym90_infinite", test::sym90_infinite()}, {"ortho", test::ortho()},
      {"off_axis", test::off_axis()}};
  Frustum none = test::ortho();
  none[kFar] = Plane{{0, 0, 0}, -1};  // contains nothing
  fs.emplace_back("degenerate_nothing", none);
  Frustum half;
  for (int i = 0; i < 6; ++i) half[i] = Plane{{0, 0, 0}, i == 2 ? 0.0f : 1.0f};  // n == 0, d >= 0: all space
  half[kLeft] = Plane{{1, 0, 0}, 0};  // x >= 0
  fs.emplace_back("half_space", half);
  std::mt19937 rng(77);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < 12; ++i) {
    const glm::vec3 eye(60 * u(rng), 60 * u(rng), 60 * u(rng)), at(20 * u(rng), 20 * u(rng), 20 * u(rng));
    const glm::mat4 p = i % 3 == 2 ? glm::ortho(-20.0f, 15.0f, -10.0f, 12.0f, 1.0f, 90.0f)
                                   : glm::perspective(glm::radians(20.0f + 50 * (u(rng) + 1)), 1.5f, 0.5f, 80.0f);
    fs.emplace_back("random" + std::to_string(i), frustum_from_matrix(p * glm::lookAt(eye, at, glm::vec3(0, 1, 0))));
  }
  return fs;
}

// Every SIMD target compiled in and supported here (Highway's one-lane fallback included), on
// three scenes, leaf sizes 1, 2 and 4 and the frusta above: the same output as cull_bvh_plain and
// cull_bvh_masked (indices, verdicts, order), and the flat pn_vertex verdicts.
TYPED_TEST(CullBvhWide, SameOutputAsTheBinaryTraversalsOnEveryTarget) {
  constexpr int W = TypeParam::value;
  const std::vector<std::vector<Aabb>> scenes = {scene(2, 5000), scene(5, 37, 3.0f), grid_scene()};
  const auto frusta = test_frusta();
  const auto targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  std::string names;
  for (const std::int64_t target : targets) names += std::string(" ") + hwy::TargetName(target);
  this->RecordProperty("targets", names);
  std::size_t max_visible = 0, max_runs = 0;
  for (const std::int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    EXPECT_EQ(std::string(bvh_wide_simd_target()), hwy::TargetName(target));
    for (std::size_t si = 0; si < scenes.size(); ++si) {
      for (std::uint32_t leaf : {1u, 2u, 4u}) {
        const Bvh bin = build_bvh(scenes[si], leaf);
        const BvhWide<W> wide = build_wide<W>(bin);
        for (const auto& [name, f] : frusta) {
          SCOPED_TRACE(std::string(hwy::TargetName(target)) + " scene " + std::to_string(si) + " leaf " +
                       std::to_string(leaf) + " " + name);
          VisibleSet plain, masked, w;
          CullStats sp, sm, sw;
          cull_bvh_plain(f, bin, plain, sp);
          cull_bvh_masked(f, bin, masked, sm);
          cull_wide(f, wide, w, sw);
          EXPECT_TRUE(same_output(plain, w));
          EXPECT_TRUE(same_output(masked, w));
          EXPECT_EQ(as_map(w), flat(f, scenes[si])) << "differs from the flat pn_vertex";
          max_visible = std::max(max_visible, w.indices.size());
          // The run output: the same visible set, the same counters.
          VisibleRuns runs;
          CullStats sr;
          cull_wide(f, wide, runs, sr);
          EXPECT_TRUE(runs_are(plain, runs, wide.prim_order));
          EXPECT_EQ(sr.nodes_visited, sw.nodes_visited);
          EXPECT_EQ(sr.plane_tests, sw.plane_tests);
          max_runs = std::max(max_runs, runs.runs.size());
          // Counters: every visited lane tests at least one plane, at most six; the primitives
          // of multi-primitive leaves at most six each.
          EXPECT_GE(sw.nodes_visited, 1u);
          EXPECT_LE(sw.nodes_visited, 1 + W * wide.nodes.size());
          EXPECT_GE(sw.plane_tests, sw.nodes_visited);
          EXPECT_LE(sw.plane_tests, 6 * (sw.nodes_visited + (leaf > 1 ? scenes[si].size() : 0)));
        }
      }
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  EXPECT_GT(max_visible, 2048u) << "the output stage was filled and flushed";
  EXPECT_GT(max_runs, 256u) << "more runs than the run stage (256) holds: merged across flushes";
}

// Runs merge across lanes, nodes and stage flushes (the stage holds 256 runs): a row of 2000
// boxes all inside is one run, all straddling one run, and alternately inside and straddling
// 2000 runs.
TYPED_TEST(CullBvhWide, RunsAreMaximalAcrossLanesNodesAndFlushes) {
  constexpr int W = TypeParam::value;
  // Box k: x in [2k, 2k + 1], y in [0, 1], z in [0, 0.9] (k even) or [0.25, 1.15] (k odd).
  std::vector<Aabb> row;
  for (int k = 0; k < 2000; ++k) {
    const float z = k % 2 == 0 ? 0.0f : 0.25f;
    row.push_back(Aabb{{2.0f * k, 0, z}, {2.0f * k + 1, 1, z + 0.9f}});
  }
  const Bvh bin = build_bvh(row);
  const BvhWide<W> wide = build_wide<W>(bin);
  Frustum f;
  for (int i = 0; i < 6; ++i) f[i] = Plane{{0, 0, 0}, 1};  // all space
  VisibleSet want;
  VisibleRuns runs;
  CullStats st;
  const auto check = [&](std::size_t n_runs, const char* what) {
    SCOPED_TRACE(what);
    cull_bvh_plain(f, bin, want, st);
    cull_wide(f, wide, runs, st);
    ASSERT_TRUE(runs_are(want, runs, wide.prim_order));
    EXPECT_EQ(want.indices.size(), row.size());
    EXPECT_EQ(runs.runs.size(), n_runs);
  };
  f[kLeft] = Plane{{1, 0, 0}, 0.5f};  // x >= -0.5
  check(1, "all inside");
  EXPECT_EQ(runs.runs[0], (VisibleRun{0, 2000, V::inside}));
  f[kTop] = Plane{{0, -1, 0}, 0.5f};  // y <= 0.5: every box straddles
  check(1, "all straddling");
  EXPECT_EQ(runs.runs[0], (VisibleRun{0, 2000, V::intersecting}));
  f[kTop] = Plane{{0, 0, 0}, 1};
  f[kFar] = Plane{{0, 0, -1}, 1.0f};  // z <= 1: even boxes inside, odd ones straddle
  check(2000, "alternating");  // (leaf order is x order here)
  for (std::size_t k = 0; k < runs.runs.size(); ++k)
    EXPECT_EQ(runs.runs[k].verdict, wide.prim_order[k] % 2 == 0 ? V::inside : V::intersecting);
}

TEST(CullBvh, ExpandRunsRejectsAnEmptyOrOverlongRun) {
  const std::vector<std::uint32_t> order = {4, 2, 0, 1, 3};
  VisibleRuns runs;
  runs.runs = {VisibleRun{0, 2, V::inside}, VisibleRun{3, 5, V::intersecting}};
  VisibleSet out;
  expand_runs(runs, order, out);
  EXPECT_EQ(out.indices, (std::vector<std::uint32_t>{4, 2, 1, 3}));
  EXPECT_EQ(out.verdicts, (std::vector<V>{V::inside, V::inside, V::intersecting, V::intersecting}));
  EXPECT_EQ(runs.count(), 4u);
  runs.runs.push_back(VisibleRun{5, 6, V::inside});
  try {
    expand_runs(runs, order, out);
    ADD_FAILURE() << "no exception";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("run 2 [5, 6)"), std::string::npos) << e.what();
  }
  runs.runs.back() = VisibleRun{3, 3, V::inside};
  EXPECT_THROW(expand_runs(runs, order, out), std::out_of_range);
}

TYPED_TEST(CullBvhWide, CountersOnHandCases) {
  constexpr int W = TypeParam::value;
  const auto boxes = scene(3, 2000, 1.0f);
  const Bvh bin = build_bvh(boxes);
  const BvhWide<W> wide = build_wide<W>(bin);
  VisibleSet out;
  // Everything inside: the root alone, six tests, every primitive inside in leaf order.
  Frustum big = test::ortho();
  for (int i = 0; i < 6; ++i) big[i].d = 1000;
  CullStats all;
  cull_wide(big, wide, out, all);
  EXPECT_EQ(all.nodes_visited, 1u);
  EXPECT_EQ(all.plane_tests, 6u);
  EXPECT_EQ(out.indices, bin.prim_order);
  for (V v : out.verdicts) EXPECT_EQ(v, V::inside);
  // Nothing visible: the root is rejected by its first plane.
  Frustum away = test::ortho();
  away[kLeft].d = -1000;
  CullStats none;
  cull_wide(away, wide, out, none);
  EXPECT_TRUE(out.indices.empty());
  EXPECT_EQ(none.nodes_visited, 1u);
  EXPECT_EQ(none.plane_tests, 1u);
  // One real plane (x >= 0), five containing all space: the root tests six planes and keeps
  // one in its mask, so every other visited lane tests exactly one plane. A wide node is opened
  // iff the lane (or root) box it hangs from straddles x = 0; each of its used lanes is counted.
  Frustum one;
  for (int i = 0; i < 6; ++i) one[i] = Plane{{0, 0, 0}, 1};
  one[kLeft] = Plane{{1, 0, 0}, 0};
  CullStats s1;
  cull_wide(one, wide, out, s1);
  EXPECT_EQ(s1.plane_tests, 6 + (s1.nodes_visited - 1));
  std::uint64_t lanes = 1;  // the root
  std::vector<std::pair<std::uint32_t, Aabb>> todo = {{0u, wide.root_box}};
  while (!todo.empty()) {
    const auto [i, b] = todo.back();
    todo.pop_back();
    if (!(b.min.x < 0 && b.max.x >= 0)) continue;
    const BvhWideNode<W>& n = wide.nodes[i];
    for (int j = 0; j < W; ++j) {
      if (n.child[j] == kBvhWideEmpty) continue;
      ++lanes;
      if (n.child[j] < kBvhWideLeaf) todo.push_back({n.child[j], lane_box(n, j)});
    }
  }
  EXPECT_EQ(s1.nodes_visited, lanes);
  EXPECT_EQ(as_map(out), flat(one, boxes));
  // The counters accumulate over calls, as the binary traversals'.
  CullStats twice;
  cull_wide(one, wide, out, twice);
  cull_wide(one, wide, out, twice);
  EXPECT_EQ(twice.nodes_visited, 2 * s1.nodes_visited);
  EXPECT_EQ(twice.plane_tests, 2 * s1.plane_tests);
}

// A point on the plane x + (1 + 2^-12) y = 0 in float: with separate rounding the value is
// fl(1 + 2^-11) + fl(-(1 + 2^-12)^2) = (1 + 2^-11) - (1 + 2^-11) = 0 (inside, as pn_vertex), but a
// fused multiply-add would give -2^-24 (outside). Checked on every SIMD target.
TYPED_TEST(CullBvhWide, NoFusedMultiplyAdd) {
  constexpr int W = TypeParam::value;
  const float y = -(1.0f + 0x1p-12f);
  const glm::vec3 p(1.0f + 0x1p-11f, y, 0.5f);
  Frustum f;
  for (int i = 0; i < 6; ++i) f[i] = Plane{{0, 0, 0}, 1};  // all space
  f[kLeft] = Plane{{1.0f, 1.0f + 0x1p-12f, 0.0f}, 0.0f};
  ASSERT_EQ(f[kLeft].eval(p), 0.0f);
  // The point box among boxes on both sides, so that the root straddles the plane.
  const std::vector<Aabb> boxes = {Aabb{{-10, -10, 0}, {-9, -9, 1}}, Aabb{p, p}, Aabb{{10, 10, 0}, {11, 11, 1}},
                                   Aabb{{-1, -2, 0}, {1, 2, 1}}, Aabb{{-3, 2, 0}, {-2, 3, 1}}};
  ASSERT_EQ(pn_vertex(f, Aabb{p, p}), V::inside);
  for (std::uint32_t leaf : {1u, 2u}) {
    const Bvh bin = build_bvh(boxes, leaf);
    const BvhWide<W> wide = build_wide<W>(bin);
    VisibleSet want, got;
    CullStats st;
    cull_bvh_plain(f, bin, want, st);
    for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
      hwy::SetSupportedTargetsForTest(target);
      cull_wide(f, wide, got, st);
      EXPECT_TRUE(same_output(want, got)) << hwy::TargetName(target) << " leaf " << leaf;
      EXPECT_EQ(as_map(got)[1], V::inside) << hwy::TargetName(target);
    }
    hwy::SetSupportedTargetsForTest(0);
  }
}

// The equality checks above can fail: a flipped verdict, a dropped or an extra primitive, a
// swapped order, and a wrong wide BVH (a leaf lane moved away) are all caught.
TYPED_TEST(CullBvhWide, TheComparisonCatchesAFlippedVerdictADroppedLeafAndAWrongTree) {
  constexpr int W = TypeParam::value;
  const auto boxes = scene(2, 5000);
  const Bvh bin = build_bvh(boxes);
  const Frustum f = test::sym90();
  VisibleSet want, got;
  CullStats st;
  cull_bvh_masked(f, bin, want, st);
  BvhWide<W> wide = build_wide<W>(bin);
  cull_wide(f, wide, got, st);
  ASSERT_TRUE(same_output(want, got));
  ASSERT_GT(want.indices.size(), 10u);
  const auto n_inside = std::count(want.verdicts.begin(), want.verdicts.end(), V::inside);
  ASSERT_GT(n_inside, 0);
  ASSERT_LT(static_cast<std::size_t>(n_inside), want.verdicts.size());
  VisibleSet m = got;
  m.verdicts[3] = m.verdicts[3] == V::inside ? V::intersecting : V::inside;
  EXPECT_FALSE(same_output(want, m));
  EXPECT_NE(as_map(m), flat(f, boxes));
  m = got;
  m.indices.erase(m.indices.begin() + 5);
  m.verdicts.erase(m.verdicts.begin() + 5);
  EXPECT_FALSE(same_output(want, m));
  EXPECT_NE(as_map(m), flat(f, boxes));
  m = got;
  m.indices.push_back(m.indices[0]);
  m.verdicts.push_back(m.verdicts[0]);
  EXPECT_FALSE(same_output(want, m));
  m = got;
  std::swap(m.indices[1], m.indices[2]);
  std::swap(m.verdicts[1], m.verdicts[2]);
  EXPECT_FALSE(same_output(want, m));
  // A tree whose single-primitive leaf lane holding a visible primitive is moved behind the
  // camera drops that primitive.
  bool moved = false;
  for (BvhWideNode<W>& n : wide.nodes) {
    for (int j = 0; j < W && !moved; ++j) {
      if (n.child[j] != (kBvhWideLeaf | 1u) || pn_vertex(f, wide.prim_boxes[n.first[j]]) == V::outside) continue;
      for (int a : {2, 5}) n.box[a][j] = 50.0f;  // z = 50: behind the near plane
      moved = true;
    }
    if (moved) break;
  }
  ASSERT_TRUE(moved);
  cull_wide(f, wide, got, st);
  EXPECT_FALSE(same_output(want, got));
  EXPECT_EQ(got.indices.size() + 1, want.indices.size());
}

}  // namespace
}  // namespace cullproof

// The fast family's hierarchical and array forms against its per-box tests, on frames of the
// project's case distributions (gen::draw_frame: the generic families around one camera, the hard
// ones, subnormal values, camera paths): every traversal gives each box pn_vertex's verdict and
// the SIMD batch pn_vertex_index's, bit for bit. On `huge`, where plane values overflow float,
// they are not the same test: pn_vertex's NaN comparisons, pn_vertex_index's double fallback and
// the wide traversals' lanes answer differently (docs/float-range.md); it is left out here.
#include "cullproof/core/cull.hpp"
#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/core/node_tests.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/simd/bvh_wide.hpp"
#include "cullproof/simd/cull_batch.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

using namespace cullproof;

namespace {

constexpr std::size_t kBoxes = 64;      // per frame
constexpr std::uint64_t kFrames = 4;   // per distribution

// Each box's verdict as the visible set gives it (outside: not listed).
std::vector<Visibility> verdicts(const VisibleSet& set, std::size_t n) {
  std::vector<Visibility> out(n, Visibility::outside);
  for (std::size_t k = 0; k < set.indices.size(); ++k) out.at(set.indices[k]) = set.verdicts[k];
  return out;
}

class OnEveryDistribution : public ::testing::TestWithParam<gen::Distribution> {};

TEST_P(OnEveryDistribution, TraversalsAndTheBatchGivePnVertexVerdicts) {
  const gen::Distribution d = GetParam();
  std::size_t boxes_seen = 0;
  for (std::uint64_t i = 0; i < kFrames; ++i) {
    const gen::Frame frame = gen::draw_frame(d, 1, i, kBoxes, kAabbKind);
    const Frustum& f = frame.frustum.planes;
    std::vector<Aabb> boxes;
    for (const Volume& v : frame.volumes) boxes.push_back(std::get<Aabb>(v));
    if (boxes.empty()) continue;
    boxes_seen += boxes.size();
    SCOPED_TRACE(std::string(gen::to_string(d)) + " frame " + std::to_string(i));
    std::vector<Visibility> want, want_wide;
    for (const Aabb& b : boxes) want.push_back(pn_vertex(f, b)), want_wide.push_back(pn_vertex_index(f, b));

    for (std::uint32_t leaf_size : {1u, 4u}) {
      const Bvh bvh = build_bvh(boxes, leaf_size);
      VisibleSet set;
      CullStats stats;
      cull_bvh_plain(f, bvh, set, stats);
      EXPECT_EQ(verdicts(set, boxes.size()), want) << "cull_bvh_plain, leaves of " << leaf_size;
      cull_bvh_masked(f, bvh, set, stats);
      EXPECT_EQ(verdicts(set, boxes.size()), want) << "cull_bvh_masked, leaves of " << leaf_size;
      BvhCoherency cache;
      for (int again = 0; again < 2; ++again) {  // the second pass starts from the cached planes
        cull_bvh_coherent(f, bvh, cache, set, stats);
        EXPECT_EQ(verdicts(set, boxes.size()), want) << "cull_bvh_coherent pass " << again;
      }
      cull_bvh4_masked(f, build_bvh4(bvh), set, stats);
      EXPECT_EQ(verdicts(set, boxes.size()), want) << "cull_bvh4_masked, leaves of " << leaf_size;
      cull_bvh8_masked(f, build_bvh8(bvh), set, stats);
      EXPECT_EQ(verdicts(set, boxes.size()), want) << "cull_bvh8_masked, leaves of " << leaf_size;
    }

    std::vector<float> c[6];
    for (const Aabb& b : boxes)
      for (int a = 0; a < 3; ++a) c[a].push_back(b.min[a]), c[3 + a].push_back(b.max[a]);
    const AabbSoa soa{c[0].data(), c[1].data(), c[2].data(), c[3].data(), c[4].data(), c[5].data(), boxes.size()};
    std::vector<std::uint64_t> visible(bitset_words(boxes.size())), inside(bitset_words(boxes.size()));
    classify_aabbs_bitset(f, soa, visible.data(), inside.data());
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const bool vis = visible[k / 64] >> (k % 64) & 1u, in = inside[k / 64] >> (k % 64) & 1u;
      const Visibility got = !vis ? Visibility::outside : in ? Visibility::inside : Visibility::intersecting;
      EXPECT_EQ(got, want_wide[k]) << "classify_aabbs_bitset, box " << k;
    }
  }
  // Every family makes boxes (degenerate ones included): frames left empty would test nothing.
  EXPECT_GT(boxes_seen, 0u) << gen::to_string(d) << " gave no box in " << kFrames << " frames";
}

INSTANTIATE_TEST_SUITE_P(Families, OnEveryDistribution, ::testing::ValuesIn(gen::no_overflow_distributions()),
                         [](const ::testing::TestParamInfo<gen::Distribution>& p) {
                           std::string name(gen::to_string(p.param));
                           for (char& ch : name)
                             if (ch == '-') ch = '_';
                           return name;
                         });

// The per-node tests that the hierarchical cullers and the simulator compose, against the per-box
// tests built on them, on the frames of every generic family: the same verdicts (and, for plane
// coherency, the same cache and the same count of plane tests, from every cache content); the
// octant composition with its cache against OctantCuller's corrected test on the symmetric frusta
// among them.
TEST(NodeTests, ComposeToTheLibrarysPerBoxTests) {
  std::size_t boxes_seen = 0, octant_boxes = 0;
  for (const gen::Distribution d : gen::generic_distributions())
    for (std::uint64_t i = 0; i < 40; ++i) {
      const gen::Frame frame = gen::draw_frame(d, 7, i, kBoxes, kAabbKind);
      const Frustum& f = frame.frustum.planes;
      SCOPED_TRACE(std::string(gen::to_string(d)) + " frame " + std::to_string(i));
      const node::SelectedPlanes sel(f);
      std::optional<OctantCuller> octant;
      if (is_bounded(f) && is_symmetric(f, 1e-5)) octant.emplace(f);
      for (const Volume& v : frame.volumes) {
        const Aabb& box = std::get<Aabb>(v);
        ++boxes_seen;
        std::uint64_t tests = 0;
        const Visibility want = pn_vertex(f, box);
        EXPECT_EQ(node::all_planes(sel, box, tests), want);
        for (int start = -1; start < 6; ++start) {
          std::int8_t mine = static_cast<std::int8_t>(start);
          PlaneCoherencyCache lib{static_cast<std::int8_t>(start)};
          std::uint64_t t1 = 0, t2 = 0;
          EXPECT_EQ(node::plane_coherency(sel, box, mine, t1), plane_coherency_test(f, box, lib, &t2));
          EXPECT_EQ(mine, lib.last_outside_plane);
          EXPECT_EQ(t1, t2);
        }
        std::uint32_t mask = 0x3f;
        EXPECT_EQ(node::masked(sel, box, mask, tests), want);
        if (octant) {
          // A second pass starts from the plane the first one cached: one plane test for a box
          // it rejected, the same verdicts.
          ++octant_boxes;
          std::int8_t cache = -1;
          const Visibility first = node::octant_coherent(*octant, sel, box, cache, tests);
          EXPECT_EQ(first, octant->classify_corrected(box));
          std::uint64_t again = 0;
          EXPECT_EQ(node::octant_coherent(*octant, sel, box, cache, again), first);
          if (first == Visibility::outside && cache >= 0) {
            EXPECT_EQ(again, 1u);
          }
        }
      }
    }
  EXPECT_GT(boxes_seen, 0u);
  EXPECT_GT(octant_boxes, 0u) << "no symmetric frustum among the frames: the octant composition went untested";
  RecordProperty("octant_boxes", static_cast<int>(octant_boxes));
}

}  // namespace

// Certified-exact culling against the oracle on every family: the verdict equals the truth,
// case by case (no error of any class; the claim's band is zero). Every volume of a case meets
// every method that can take it: AABBs also as OBBs (when the float centre and half-extents are
// exact), points as flat boxes, OBBs and balls of radius 0; AABBs and spheres through the batch
// forms as well. Built twice: as is, and (test_exact_certified_fma) with the float stages compiled
// with -mfma -ffp-contract=fast, so that the bounds are checked with contraction too.
#include "cullproof/simd/batch_combinations.hpp"
#include "cullproof/simd/batch_spheres.hpp"
#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/simd/certified_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"
#include "cullproof/simd/exact_certified_batch.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/methods/methods.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <rapidcheck.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

using namespace cullproof;

namespace {

#ifdef CULLPROOF_FMA_BUILD
bool cpu_has_fma() { return __builtin_cpu_supports("fma"); }
#else
bool cpu_has_fma() { return true; }
#endif

// The AABB as an OBB, when to_obb describes exactly the same points.
bool exact_obb(const Aabb& b, Obb& out) {
  out = to_obb(b);
  for (int i = 0; i < 3; ++i)
    if (double(out.center[i]) - double(out.half[i]) != double(b.min[i]) ||
        double(out.center[i]) + double(out.half[i]) != double(b.max[i]))
      return false;
  return true;
}

Visibility batch(const char* name, const CaseFrustum& f, const Aabb& b) {
  Answer a;
  find_builtin(name)->prepare(f)->classify_batch(&b, 1, &a);
  return *a;
}
// The SIMD witness pass of the AABB batch on one box (as the only lane of a word): whether it
// proves the box intersecting from `seed`.
bool simd_witness(const ExactCertifiedFrustum& f, const Aabb& b, const glm::vec3& seed) {
  const AabbSoa one{&b.min.x, &b.min.y, &b.min.z, &b.max.x, &b.max.y, &b.max.z, 1};
  const std::uint64_t todo = 1;
  std::uint64_t meets = ~std::uint64_t{0};
  certified_meets_aabbs_bitset(f.certified, one, seed, &todo, &meets);
  return meets != 0;
}

// The AABB array form's float passes on one box (the only lane of a word): whether they decide
// it, and the verdict. The frame's prepared data is used as is: with prepare_exact_certified
// compiled for FMA (the fma build), its float items are the fused computation's.
bool float_pass(const ExactCertifiedFrustum& f, const Aabb& b, const glm::vec3& seed, Visibility& v) {
  if (f.float_planes == 0) return false;
  alignas(64) float a[6][64] = {};
  for (int k = 0; k < 3; ++k) a[k][0] = b.min[k], a[3 + k][0] = b.max[k];
  const AabbSoa one{a[0], a[1], a[2], a[3], a[4], a[5], 1};
  FloatFirstResult r;
  exact_float_first(f, one, seed, r);
  if (r.outside[0] & 1u) return v = Visibility::outside, true;
  if (r.inside[0] & 1u) return v = Visibility::inside, true;
  if (r.meets[0] & 1u) return v = Visibility::intersecting, true;
  FloatOpenResult o;
  exact_float_open(f, one, r, o);
  if (o.count == 1 && (o.outside[0] & 1u)) return v = Visibility::outside, true;
  if (o.count == 1 && (o.meets[0] & 1u)) return v = Visibility::intersecting, true;
  return false;
}

// The AABB array form's box pass (stage 1 in double) on one box: whether it decides it, and the
// verdict. It must decide exactly the boxes the scalar cascade decides at stage 1, as it does
// (the same operations per lane): a box it decides that the scalar test sends on, or the reverse,
// is an error even when the verdict happens to be right.
bool box_pass(const ExactCertifiedFrustum& f, const Aabb& b, Visibility& v) {
  alignas(64) float a[6][64] = {};
  for (int k = 0; k < 3; ++k) a[k][0] = b.min[k], a[3 + k][0] = b.max[k];
  const std::uint64_t todo = 1;
  detail::PassProofs r;
  exact_box_planes(f, AabbSoa{a[0], a[1], a[2], a[3], a[4], a[5], 1}, &todo, r);
  if (r.outside[0] & 1u) return v = Visibility::outside, true;
  if (r.inside[0] & 1u) return v = Visibility::inside, true;
  if (r.meets[0] & 1u) return v = Visibility::intersecting, true;
  return false;
}

void expect_box_pass_is_stage_one(const ExactCertifiedFrustum& f, const Aabb& b) {
  ExactStage stage;
  const Visibility scalar = exact_certified_aabb(f, b, &stage);
  Visibility v{};
  const bool decided = box_pass(f, b, v);
  if (decided != (stage == ExactStage::planes && !f.empty))
    RC_FAIL(std::string("the box pass ") + (decided ? "decides" : "leaves") + " a box the scalar stage 1 " +
            (decided ? "leaves" : "decides"));
  if (decided && v != scalar)
    RC_FAIL("the box pass says " + std::string(to_string(v)) + ", the scalar cascade " + std::string(to_string(scalar)));
}

// The SIMD witness pass of the sphere batch on one sphere: whether it proves it intersecting.
bool simd_witness(const ExactCertifiedFrustum& f, const Sphere& s, const glm::vec3& seed) {
  const SphereSoa one{&s.center.x, &s.center.y, &s.center.z, &s.radius, 1};
  const std::uint64_t todo = 1;
  std::uint64_t meets = ~std::uint64_t{0};
  certified_meets_spheres_bitset(f.certified, one, seed, &todo, &meets);
  return meets != 0;
}

// The sphere array form's double pass on one ball (the only lane): whether it decides it, and
// the verdict.
bool double_pass(const ExactCertifiedFrustum& f, const Sphere& s, Visibility& v) {
  alignas(64) float a[4][kBallReadable] = {};
  a[0][0] = s.center.x, a[1][0] = s.center.y, a[2][0] = s.center.z, a[3][0] = s.radius;
  const std::uint64_t todo = 1;
  detail::PassProofs r;
  exact_ball_pass(f, SphereSoa{a[0], a[1], a[2], a[3], 1}, &todo, r);
  if (r.outside[0] & 1u) return v = Visibility::outside, true;
  if (r.inside[0] & 1u) return v = Visibility::inside, true;
  if (r.meets[0] & 1u) return v = Visibility::intersecting, true;
  return false;
}

Visibility batch(const char* name, const CaseFrustum& f, const Sphere& s) {
  Answer a;
  find_builtin(name)->prepare(f)->classify_batch(&s, 1, &a);
  return *a;
}

class ExactCertifiedOnEveryFamily : public ::testing::TestWithParam<gen::Distribution> {};

TEST_P(ExactCertifiedOnEveryFamily, EqualsTheOracle) {
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA";
  const gen::Distribution d = GetParam();
  const bool ok = rc::check(std::string("certified-exact equals the truth on ") + std::string(gen::to_string(d)), [d] {
    const gen::GenCase g = *gen::case_of(d);
    const Visibility truth = oracle::truth(g.frustum, g.volume);
    const ExactCertifiedFrustum f = prepare_exact_certified(g.frustum);
    auto expect = [&](const char* method, Visibility v) {
      if (v != truth)
        RC_FAIL(std::string(method) + " says " + std::string(to_string(v)) + ", the truth is " +
                std::string(to_string(truth)));
    };
    if (const Aabb* a = std::get_if<Aabb>(&g.volume)) {
      expect("aabb-exact-certified", exact_certified_aabb(f, *a));
      expect("aabb-batch-exact-certified", batch("aabb-batch-exact-certified", g.frustum, *a));
      // Every bit of the witness pass is a proof, from the frame's seed or from any float point.
      const auto t = *rc::gen::container<std::vector<float>>(3, rc::gen::elementOf(std::vector<float>{-1.0f, 0.0f, 0.25f, 0.5f, 1.0f, 3.0f}));
      const glm::vec3 seeds[2] = {glm::vec3(float(f.interior[0]), float(f.interior[1]), float(f.interior[2])),
                                  a->min + glm::vec3(t[0], t[1], t[2]) * (a->max - a->min)};
      for (const glm::vec3& seed : seeds) {
        if (!is_valid(Point{seed})) continue;
        if (simd_witness(f, *a, seed) && truth != Visibility::intersecting)
          RC_FAIL("the SIMD witness pass proved a box intersecting whose truth is " + std::string(to_string(truth)));
        Visibility v;
        if (float_pass(f, *a, seed, v) && v != truth)
          RC_FAIL("the float pass proved a box " + std::string(to_string(v)) + " whose truth is " +
                  std::string(to_string(truth)));
      }
      expect_box_pass_is_stage_one(f, *a);
      Obb o;
      if (exact_obb(*a, o)) expect("obb-exact-certified (the box as an OBB)", exact_certified_obb(f, o));
    } else if (const Obb* o = std::get_if<Obb>(&g.volume)) {
      expect("obb-exact-certified", exact_certified_obb(f, *o));
    } else if (const Sphere* s = std::get_if<Sphere>(&g.volume)) {
      expect("sphere-exact-certified", exact_certified_sphere(f, *s));
      expect("sphere-batch-exact-certified", batch("sphere-batch-exact-certified", g.frustum, *s));
      // From the frame's seed, and from points around the ball.
      const auto t = *rc::gen::container<std::vector<float>>(3, rc::gen::elementOf(std::vector<float>{-1.0f, -0.5f, 0.0f, 0.5f, 1.0f, 4.0f}));
      const glm::vec3 seeds[2] = {glm::vec3(float(f.interior[0]), float(f.interior[1]), float(f.interior[2])),
                                  s->center + glm::vec3(t[0], t[1], t[2]) * s->radius};
      for (const glm::vec3& seed : seeds)
        if (is_valid(Point{seed}) && simd_witness(f, *s, seed) && truth != Visibility::intersecting)
          RC_FAIL("the SIMD witness pass proved a sphere intersecting whose truth is " + std::string(to_string(truth)));
      // The double pass on the ball alone (not only on what the witness pass leaves).
      Visibility v;
      if (double_pass(f, *s, v) && v != truth)
        RC_FAIL("the double pass proved a sphere " + std::string(to_string(v)) + " whose truth is " +
                std::string(to_string(truth)));
    } else {
      const Point& p = std::get<Point>(g.volume);
      expect("aabb-exact-certified (the point as a box)", exact_certified_aabb(f, Aabb{p, p}));
      expect("obb-exact-certified (the point as an OBB)", exact_certified_obb(f, Obb{p, glm::mat3(1.0f), glm::vec3(0.0f)}));
      expect("sphere-exact-certified (the point as a ball)", exact_certified_sphere(f, Sphere{p, 0.0f}));
    }
  });
  EXPECT_TRUE(ok);
}

// The ends of the float range: a case of a touching or boundary family, with the frustum as its
// planes, moved to other magnitudes by powers of two: every coordinate and every plane offset
// times 2^k (the same geometry, scaled, while no value leaves the normal range), then each plane
// times its own 2^m. Large k takes coordinates towards FLT_MAX; small k and m make distances and
// coefficients subnormal (rounding them, which changes the geometry: the oracle judges what the
// floats are). Cases that would overflow are drawn again with smaller exponents.
// The exponent of the largest coefficient of plane p with its offset scaled by 2^k.
int top_exponent(const Plane& p, int k) {
  const float big = std::max({std::abs(p.n.x), std::abs(p.n.y), std::abs(p.n.z), std::abs(std::ldexp(p.d, k))});
  return big > 0.0f ? std::ilogb(big) : 0;
}

gen::GenCase scaled_case(gen::GenCase g, int k, const std::array<int, 6>& m) {
  const auto scale = [](float x, int e) { return std::ldexp(x, e); };
  Frustum f = g.frustum.planes;
  for (int j = 0; j < 6; ++j) {
    Plane& p = f[j];
    p.d = scale(p.d, k);
    p.n = glm::vec3(scale(p.n.x, m[std::size_t(j)]), scale(p.n.y, m[std::size_t(j)]), scale(p.n.z, m[std::size_t(j)]));
    p.d = scale(p.d, m[std::size_t(j)]);
  }
  g.frustum = frustum_spec(f);
  const auto v3 = [&](const glm::vec3& x) { return glm::vec3(scale(x.x, k), scale(x.y, k), scale(x.z, k)); };
  std::visit(
      [&](auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, Point>) v = v3(v);
        else if constexpr (std::is_same_v<T, Sphere>) v.center = v3(v.center), v.radius = scale(v.radius, k);
        else if constexpr (std::is_same_v<T, Aabb>) v.min = v3(v.min), v.max = v3(v.max);
        else v.center = v3(v.center), v.half = v3(v.half);
      },
      g.volume);
  return g;
}

TEST(ExactCertifiedFloatRange, EqualsTheOracleFromSubnormalsToFltMax) {
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA";
  const gen::Distribution families[] = {gen::Distribution::touch, gen::Distribution::contact, gen::Distribution::ulp,
                                        gen::Distribution::near_boundary, gen::Distribution::corner};
  const bool ok = rc::check("certified-exact equals the truth at every magnitude", [&] {
    const gen::Distribution d = *rc::gen::elementOf(std::vector<gen::Distribution>(std::begin(families), std::end(families)));
    const gen::GenCase base = *gen::case_of(d);
    // Coordinates up to 2^120 (the cases' own reach a few times 2^6: towards FLT_MAX), down to
    // below 2^-126 (subnormal), or in between; each plane scaled as far as its coefficients allow.
    const int range = *rc::gen::inRange(0, 3);
    const int k = range == 0 ? *rc::gen::inRange(100, 121) : range == 1 ? *rc::gen::inRange(-150, -120) : *rc::gen::inRange(-120, 100);
    std::array<int, 6> m;
    for (int j = 0; j < 6; ++j) m[std::size_t(j)] = *rc::gen::inRange(-150, 127 - top_exponent(base.frustum.planes[j], k));
    const gen::GenCase g = scaled_case(base, k, m);
    RC_PRE(is_valid(g.frustum.planes) && is_valid(g.volume));
    RC_TAG(range == 0 ? "coordinates towards FLT_MAX" : range == 1 ? "subnormal coordinates" : "between");
    const Visibility truth = oracle::truth(g.frustum, g.volume);
    const ExactCertifiedFrustum f = prepare_exact_certified(g.frustum);
    Visibility v;
    std::string method;
    if (const Aabb* a = std::get_if<Aabb>(&g.volume)) {
      const Visibility w = batch("aabb-batch-exact-certified", g.frustum, *a);
      if (w != truth)
        RC_FAIL("aabb-batch-exact-certified says " + std::string(to_string(w)) + ", the truth is " +
                std::string(to_string(truth)) + " (k = " + std::to_string(k) + ")");
      Visibility fp;
      const glm::vec3 seed(float(f.interior[0]), float(f.interior[1]), float(f.interior[2]));
      if (is_valid(Point{seed}) && float_pass(f, *a, seed, fp) && fp != truth)
        RC_FAIL("the float pass proved a box " + std::string(to_string(fp)) + ", the truth is " +
                std::string(to_string(truth)) + " (k = " + std::to_string(k) + ")");
      expect_box_pass_is_stage_one(f, *a);
      v = exact_certified_aabb(f, *a), method = "aabb-exact-certified";
    }
    else if (const Obb* o = std::get_if<Obb>(&g.volume)) v = exact_certified_obb(f, *o), method = "obb-exact-certified";
    else if (const Sphere* sp = std::get_if<Sphere>(&g.volume)) {
      const Visibility w = batch("sphere-batch-exact-certified", g.frustum, *sp);
      if (w != truth)
        RC_FAIL("sphere-batch-exact-certified says " + std::string(to_string(w)) + ", the truth is " +
                std::string(to_string(truth)) + " (k = " + std::to_string(k) + ")");
      Visibility dp;
      if (double_pass(f, *sp, dp) && dp != truth)
        RC_FAIL("the double pass proved a sphere " + std::string(to_string(dp)) + ", the truth is " +
                std::string(to_string(truth)) + " (k = " + std::to_string(k) + ")");
      v = exact_certified_sphere(f, *sp), method = "sphere-exact-certified";
    }
    else v = exact_certified_aabb(f, Aabb{std::get<Point>(g.volume), std::get<Point>(g.volume)}), method = "aabb-exact-certified (point)";
    if (v != truth)
      RC_FAIL(method + " says " + std::string(to_string(v)) + ", the truth is " + std::string(to_string(truth)) +
              " (k = " + std::to_string(k) + ")");
  });
  EXPECT_TRUE(ok);
}

// The stages in vector lanes (src/simd/exact_lanes.cpp: the planes of OBBs and spheres, an
// OBB's anchors, the programme that finds the frame's interior point and proposes stage 2's
// certificates) compute what the derivation does, operation for operation, so every SIMD target
// this machine runs prepares the same frame (interior point, anchors) and gives the same stage and
// verdict for every OBB, AABB and sphere of 64 frames (the properties above check the best target's
// verdicts against the oracle).
TEST(ExactCertifiedLanes, EveryTargetGivesTheSameFramesStagesAndVerdicts) {
  std::vector<gen::Frame> frames;
  for (gen::Distribution d : gen::generic_distributions())
    for (std::uint64_t i = 0; i < 4; ++i) frames.push_back(gen::draw_frame(d, 7, i, 1024, kAabbKind | kObbKind | kSphereKind));
  const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  std::vector<std::pair<Visibility, ExactStage>> first;
  std::vector<std::array<double, 3 * ExactCertifiedFrustum::kAnchors + 3>> points;
  for (const std::int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    SCOPED_TRACE(hwy::TargetName(target));
    std::size_t k = 0;
    int by_stage[3] = {0, 0, 0};
    for (std::size_t fi = 0; fi < frames.size(); ++fi) {
      const ExactCertifiedFrustum f = prepare_exact_certified(frames[fi].frustum);
      std::array<double, 3 * ExactCertifiedFrustum::kAnchors + 3> p{};
      for (int a = 0; a < ExactCertifiedFrustum::kAnchors; ++a)
        p[std::size_t(3 * a)] = f.anchor_x[std::size_t(a)], p[std::size_t(3 * a + 1)] = f.anchor_y[std::size_t(a)],
                         p[std::size_t(3 * a + 2)] = f.anchor_z[std::size_t(a)];
      for (int i = 0; i < 3; ++i) p[std::size_t(3 * ExactCertifiedFrustum::kAnchors + i)] = f.interior[std::size_t(i)];
      if (points.size() == fi) points.push_back(p);
      for (std::size_t i = 0; i < p.size(); ++i)  // bit for bit (the unused anchors are NaN)
        ASSERT_EQ(std::memcmp(&points[fi][i], &p[i], sizeof(double)), 0) << "frame " << fi << ", coordinate " << i;
      for (const Volume& volume : frames[fi].volumes) {
        ExactStage s = ExactStage::planes;
        Visibility v = Visibility::outside;
        if (const Obb* b = std::get_if<Obb>(&volume)) v = exact_certified_obb(f, *b, &s);
        else if (const Aabb* a = std::get_if<Aabb>(&volume)) v = exact_certified_aabb(f, *a, &s);
        else if (const Sphere* sp = std::get_if<Sphere>(&volume)) v = exact_certified_sphere(f, *sp, &s);
        else continue;
        ++by_stage[int(s)];
        if (first.size() == k) first.emplace_back(v, s);
        ASSERT_EQ(to_string(first[k].first), to_string(v)) << "volume " << k << " (frame " << fi << ")";
        ASSERT_EQ(to_string(first[k].second), to_string(s)) << "volume " << k;
        ++k;
      }
    }
    EXPECT_GT(by_stage[int(ExactStage::planes)], 3000);  // the data reaches both float stages
    EXPECT_GT(by_stage[int(ExactStage::axes)], 3000);
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The array forms on whole frames (1,024 boxes or balls of one distribution around one camera,
// as `cullproof verify` times them), on every SIMD target this machine runs: what the certified
// batch leaves is gathered across the frame; the boxes the first float pass leaves are sorted by J
// and tested on their combinations a vector at a time, boxes of different J side by side; the
// balls the witness pass leaves are sorted by J and given the cascade's proofs a ball per lane.
// Every verdict equals the oracle's truth.
TEST(ExactCertifiedArrays, WholeFramesEqualTheOracle) {
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA";
  const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  ASSERT_FALSE(targets.empty());
  for (gen::Distribution d : gen::generic_distributions())
    for (std::uint64_t i = 0; i < 2; ++i) {
      const gen::Frame boxes_frame = gen::draw_frame(d, 11, i, 1024, kAabbKind);
      const gen::Frame balls_frame = gen::draw_frame(d, 11, i, 1024, kSphereKind);
      std::vector<Aabb> boxes;
      std::vector<Sphere> balls;
      std::vector<Visibility> box_truth, ball_truth;
      for (const Volume& v : boxes_frame.volumes)
        boxes.push_back(std::get<Aabb>(v)), box_truth.push_back(oracle::truth(boxes_frame.frustum, v));
      for (const Volume& v : balls_frame.volumes)
        balls.push_back(std::get<Sphere>(v)), ball_truth.push_back(oracle::truth(balls_frame.frustum, v));
      const ExactCertifiedFrustum fb = prepare_exact_certified(boxes_frame.frustum);
      const ExactCertifiedFrustum fs = prepare_exact_certified(balls_frame.frustum);
      for (const std::int64_t target : targets) {
        hwy::SetSupportedTargetsForTest(target);
        std::vector<Visibility> got(boxes.size());
        exact_certified_aabbs(fb, boxes.data(), boxes.size(), got.data());
        for (std::size_t k = 0; k < boxes.size(); ++k)
          ASSERT_EQ(to_string(got[k]), to_string(box_truth[k])) << gen::to_string(d) << ", seed 11, frame " << i << ", box " << k
                                                                << " of gen::draw_frame, " << hwy::TargetName(target);
        got.assign(balls.size(), Visibility::outside);
        exact_certified_spheres(fs, balls.data(), balls.size(), got.data());
        for (std::size_t k = 0; k < balls.size(); ++k)
          ASSERT_EQ(to_string(got[k]), to_string(ball_truth[k])) << gen::to_string(d) << ", seed 11, frame " << i << ", ball " << k
                                                                 << " of gen::draw_frame, " << hwy::TargetName(target);
      }
      hwy::SetSupportedTargetsForTest(0);
    }
}

std::string distribution_name(const ::testing::TestParamInfo<gen::Distribution>& p) {
  std::string s(gen::to_string(p.param));
  for (char& ch : s)
    if (ch == '-') ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(AllDistributions, ExactCertifiedOnEveryFamily,
                         ::testing::ValuesIn(gen::parse_distributions("all")), distribution_name);

}  // namespace

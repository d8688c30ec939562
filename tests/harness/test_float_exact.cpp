// Float-exactness (gen::float_exact): hand-made cases on each side of the rule, and the rule's
// soundness against a correct float test: on a float-exact case the n/p-vertex, point and sphere
// tests make no error their exact-arithmetic claim forbids, so no allowance is needed there.
#include "cullproof/io/case_io.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cmath>

namespace cullproof {
namespace {

using gen::float_exact;

// Six axis-aligned unit planes around the box [-4, 4] x [-4, 4] x [-8, -1]: every coefficient a
// small integer.
CaseFrustum box_frustum() {
  Frustum f;
  f.planes[kLeft] = Plane{{1, 0, 0}, 4};
  f.planes[kRight] = Plane{{-1, 0, 0}, 4};
  f.planes[kBottom] = Plane{{0, 1, 0}, 4};
  f.planes[kTop] = Plane{{0, -1, 0}, 4};
  f.planes[kNear] = Plane{{0, 0, -1}, -1};
  f.planes[kFar] = Plane{{0, 0, 1}, 8};
  return frustum_spec(f);
}

TEST(FloatExact, DyadicBoxesPointsAndSpheresOnUnitPlanes) {
  const CaseFrustum f = box_frustum();
  EXPECT_TRUE(float_exact(f, Aabb{{4, -1, -3}, {5, 1, -2}}));           // touching the right plane
  EXPECT_TRUE(float_exact(f, Aabb{{0.25f, 0.5f, -3}, {0.75f, 1.5f, -2}}));
  // 0.1f + 4 needs 30 bits: the left plane's value at the corner rounds.
  EXPECT_FALSE(float_exact(f, Aabb{{0.1f, 0.2f, -3}, {0.3f, 0.4f, -2}}));
  EXPECT_TRUE(float_exact(f, Point{4, 4, -1}));                           // a frustum corner
  EXPECT_TRUE(float_exact(f, Sphere{{0, 0, -9.5f}, 1.5f}));              // tangent to the far plane
}

TEST(FloatExact, AProductOrAPartialSumThatRoundsIsNotExact) {
  CaseFrustum f = box_frustum();
  // 2^26 + 4 is not a float (floats there are 8 apart): the left plane's value at x = 2^26 rounds.
  EXPECT_FALSE(float_exact(f, Point{67108864.0f, 0, -2}));
  EXPECT_TRUE(float_exact(f, Point{16777216.0f, 0, -2})) << "2^24 + 4 is a float";
  // A product that needs more than 24 bits: 3 * 0.1f.
  f.planes[kLeft].n = {3, 0, 0};
  EXPECT_FALSE(float_exact(f, Point{0.1f, 0, -2}));
  // Every order counts: n = (1, 1, 0) at (2^24, -2^24, 0) with d = 1 sums to 1 left to right
  // after cancelling, but 2^24 + 1 (x then d) rounds.
  f = box_frustum();
  f.planes[kLeft] = Plane{{1, 1, 0}, 1};
  EXPECT_FALSE(float_exact(f, Point{16777216.0f, -16777216.0f, -2}));
  // A product below the subnormals: 2^-100 * 2^-100.
  f = box_frustum();
  f.planes[kLeft] = Plane{{std::ldexp(1.0f, -100), 0, 0}, 0};
  EXPECT_FALSE(float_exact(f, Point{std::ldexp(1.0f, -100), 0, -2}));
}

TEST(FloatExact, SpheresNeedExactlyUnitNormals) {
  CaseFrustum f = box_frustum();
  // 0.6f and 0.8f are not 0.6 and 0.8: their squares do not sum to 1 exactly.
  f.planes[kLeft] = Plane{{0.6f, 0.8f, 0}, 4};
  EXPECT_FALSE(float_exact(f, Sphere{{0, 0, -3}, 1}));
  EXPECT_TRUE(float_exact(f, Point{0, 0, -3})) << "a point needs no normalisation";
  // An unnormalised axis normal: |n| = 2.
  f = box_frustum();
  f.planes[kLeft] = Plane{{2, 0, 0}, 8};
  EXPECT_FALSE(float_exact(f, Sphere{{0, 0, -3}, 1}));
  // A degenerate plane (all space) rounds nothing.
  f = box_frustum();
  f.planes[kFar] = Plane{{0, 0, 0}, 1};
  EXPECT_TRUE(float_exact(f, Sphere{{0, 0, -3}, 1}));
}

TEST(FloatExact, ObbsNeedExactCornersAndProjections) {
  const CaseFrustum f = box_frustum();
  const glm::mat3 identity(1.0f);
  EXPECT_TRUE(float_exact(f, Obb{{0, 0, -3}, identity, {1, 0.5f, 0.25f}}));
  // Axes swapped and negated: still exact.
  const glm::mat3 swapped(glm::vec3(0, 1, 0), glm::vec3(-1, 0, 0), glm::vec3(0, 0, 1));
  EXPECT_TRUE(float_exact(f, Obb{{0, 0, -3}, swapped, {1, 0.5f, 0.25f}}));
  // A 45-degree axis: 0.70710677f * h rounds somewhere.
  const float c = 0.70710677f;
  const glm::mat3 turned(glm::vec3(c, c, 0), glm::vec3(-c, c, 0), glm::vec3(0, 0, 1));
  EXPECT_FALSE(float_exact(f, Obb{{0, 0, -3}, turned, {1.3f, 0.7f, 0.25f}}));
}

TEST(FloatExact, MatrixCasesNeedExactRowSums) {
  // glm::frustum(-1, 1, -1, 1, 1, 3): entries 1, 1, -2, -1, -3 (OpenGL depth), all small integers.
  const CaseFrustum f = frustum_spec(off_axis_projection(-1, 1, -1, 1, 1, 3), DepthConvention{});
  EXPECT_TRUE(float_exact(f, Aabb{{-0.5f, -0.5f, -2}, {0.5f, 0.5f, -1.5f}}));
  // A near plane of 0.1: 2n/(r-l) = 0.1f and -(f+n)/(f-n) round; r4 + r3 adds them.
  const CaseFrustum g = frustum_spec(off_axis_projection(-0.1f, 0.1f, -0.1f, 0.1f, 0.1f, 3), DepthConvention{});
  EXPECT_FALSE(float_exact(g, Aabb{{-0.5f, -0.5f, -2}, {0.5f, 0.5f, -1.5f}}));
}

TEST(FloatExact, TheTouchFamilysBoxesPointsAndObbsAreFloatExact) {
  // Its spheres touch planes whose normals are not unit (x = z has |n| = sqrt 2): the sphere test
  // normalises, which rounds, so they keep the allowance.
  int exact = 0, n = 0, spheres = 0;
  for (int i = 0; i < 400; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::touch, 1, std::uint64_t(i));
    if (std::holds_alternative<Sphere>(g.volume)) {
      ++spheres;
      continue;
    }
    ++n;
    const bool e = float_exact(g.frustum, g.volume);
    exact += e;
    if (!e) ADD_FAILURE() << "touch case " << i << " rounds: " << format_frustum(g.frustum) << " " << format_volume(g.volume);
  }
  EXPECT_EQ(exact, n);
  EXPECT_GT(spheres, 10);
}

TEST(FloatExact, TheContactFamilyIsFloatExactThroughout) {
  int kinds[4] = {0, 0, 0, 0}, matrices = 0;
  for (int i = 0; i < 1000; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::contact, 3, std::uint64_t(i));
    EXPECT_TRUE(float_exact(g.frustum, g.volume))
        << "contact case " << i << " rounds: " << format_frustum(g.frustum) << " " << format_volume(g.volume);
    ++kinds[g.volume.index()];
    matrices += g.frustum.matrix.has_value();
  }
  for (int k = 0; k < 4; ++k) EXPECT_GT(kinds[k], 50) << "volume kind " << k;
  EXPECT_GT(matrices, 200);
}

// Soundness: where the rule says nothing rounds, a correct float test is exactly as right as in
// exact arithmetic. The n/p-vertex, point and sphere tests are conservative in exact arithmetic
// (A&M §3.1): on a float-exact case none may make a false reject or a false inside.
TEST(FloatExact, CorrectFloatTestsMakeNoForbiddenErrorOnFloatExactCases) {
  int exact_cases = 0;
  const bool ok = rc::check("no forbidden error where nothing rounds", [&] {
    const gen::Distribution d = *rc::gen::element(gen::Distribution::touch, gen::Distribution::ulp, gen::Distribution::contact);
    const gen::GenCase g = *gen::case_of(d);
    if (!float_exact(g.frustum, g.volume)) return;
    ++exact_cases;
    const Visibility truth = oracle::truth(g.frustum, g.volume);
    Visibility v = Visibility::intersecting;
    if (const Aabb* b = std::get_if<Aabb>(&g.volume)) v = pn_vertex(g.frustum.planes, *b);
    else if (const Point* p = std::get_if<Point>(&g.volume)) v = point_plane_test(g.frustum.planes, *p);
    else if (const Sphere* s = std::get_if<Sphere>(&g.volume)) v = sphere_plane_test(g.frustum.planes, *s);
    else return;
    RC_ASSERT(!(v == Visibility::outside && truth != Visibility::outside));
    RC_ASSERT(!(v == Visibility::inside && truth != Visibility::inside));
  });
  EXPECT_TRUE(ok);
  EXPECT_GT(exact_cases, 600);
}

}  // namespace
}  // namespace cullproof

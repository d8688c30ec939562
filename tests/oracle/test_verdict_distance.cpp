// How far a verdict lies from being the truth (oracle::distance_to_verdict): one hand-made case
// for every (verdict, truth) pair, for boxes, balls, points and an OBB, each distance derived by
// hand in its comment. Most are chosen where the distance to the boundary (what the oracle's
// Result::distance measures) is far smaller than the distance to the verdict given, which is what
// the judge must forgive no more than.
#include "oracle_test_util.hpp"

#include <cmath>
#include <limits>

namespace cullproof::oracle::test {
namespace {

// The distance must be a lower bound (never above the exact value) and tight.
void expect_distance(const CaseFrustum& f, const Volume& v, Visibility verdict, Visibility truth, VerdictShift shift,
                     double exact) {
  SCOPED_TRACE("volume " + format_volume(v) + ", verdict " + std::string(to_string(verdict)));
  const VerdictDistance d = distance_to_verdict(f, v, verdict);
  EXPECT_EQ(d.truth, truth);
  EXPECT_EQ(d.shift, shift) << to_string(d.shift);
  EXPECT_LE(d.distance, exact * (1 + 1e-15));
  EXPECT_NEAR(d.distance, exact, 1e-12 * exact);
}

// ---- verdict outside ---------------------------------------------------------------------------

TEST(VerdictDistance, OutsideForAStraddlingBoxIsItsDepth) {
  // x ∈ [0.25, 1.0625]: 0.0625 beyond the right plane, 0.75 within it. Outside is right once the
  // planes move in by the depth max_B min_j s_j = s_right(0.25, 0, 0) = 0.75; the boundary is
  // only 0.0625 away (the protrusion).
  const Aabb b{{0.25f, -0.125f, -0.125f}, {1.0625f, 0.125f, 0.125f}};
  expect_distance(cube(), b, Visibility::outside, Visibility::intersecting, VerdictShift::to_outside, 0.75);
  EXPECT_DOUBLE_EQ(classify(cube(), b).distance, 0.0625);
}

TEST(VerdictDistance, OutsideForABoxInsideIsItsDepthNotItsClearance) {
  // x ∈ [0.5, 0.875]: 0.125 clear of the right plane, yet its point (0.5, 0, 0) is 0.5 from
  // every plane: the planes must move in by 0.5 before the box misses the frustum.
  const Aabb b{{0.5f, -0.125f, -0.125f}, {0.875f, 0.125f, 0.125f}};
  expect_distance(cube(), b, Visibility::outside, Visibility::inside, VerdictShift::to_outside, 0.5);
  EXPECT_DOUBLE_EQ(classify(cube(), b).distance, 0.125);
}

TEST(VerdictDistance, OutsideForABallIsItsDepth) {
  // Ball at (0.875, 0, 0), r = 0.5, straddles x = 1. Its point (0.375, 0, 0) has
  // min(1 - x, 1 + x, 1, 1) = 0.625, and no point of the ball has 1 - x larger.
  const Sphere s{{0.875f, 0, 0}, 0.5f};
  expect_distance(cube(), s, Visibility::outside, Visibility::intersecting, VerdictShift::to_outside, 0.625);
  // Ball at the centre, r = 0.5: the centre is 1 from every plane.
  expect_distance(cube(), Sphere{{0, 0, 0}, 0.5f}, Visibility::outside, Visibility::inside, VerdictShift::to_outside, 1.0);
}

TEST(VerdictDistance, OutsideForAPointIsItsNearestPlane) {
  expect_distance(cube(), Point{0.5f, 0, 0}, Visibility::outside, Visibility::inside, VerdictShift::to_outside, 0.5);
}

// ---- verdict inside ----------------------------------------------------------------------------

TEST(VerdictDistance, InsideForABoxOutsideIsItsProtrusionNotItsGap) {
  // x ∈ [1 + 2^-7, 1.5]: 2^-7 from touching the cube, 0.5 from lying in it.
  const Aabb b{{1.0078125f, -0.125f, -0.125f}, {1.5f, 0.125f, 0.125f}};
  expect_distance(cube(), b, Visibility::inside, Visibility::outside, VerdictShift::to_inside, 0.5);
  EXPECT_DOUBLE_EQ(classify(cube(), b).distance, 0.0078125);
}

TEST(VerdictDistance, InsideForAStraddlingBoxIsHowFarItProtrudes) {
  // x ∈ [0.9375, 1.5]: penetrates by 0.0625, protrudes by 0.5.
  const Aabb b{{0.9375f, -0.125f, -0.125f}, {1.5f, 0.125f, 0.125f}};
  expect_distance(cube(), b, Visibility::inside, Visibility::intersecting, VerdictShift::to_inside, 0.5);
  EXPECT_DOUBLE_EQ(classify(cube(), b).distance, 0.0625);
}

TEST(VerdictDistance, InsideForABallIsItsProtrusion) {
  // Ball at (2, 0, 0), r = 0.5: 0.5 from the cube, and its far side x = 2.5 is 1.5 beyond x = 1.
  expect_distance(cube(), Sphere{{2, 0, 0}, 0.5f}, Visibility::inside, Visibility::outside, VerdictShift::to_inside, 1.5);
  // Ball at (0.875, 0, 0), r = 0.5: reaches x = 1.375.
  expect_distance(cube(), Sphere{{0.875f, 0, 0}, 0.5f}, Visibility::inside, Visibility::intersecting,
                  VerdictShift::to_inside, 0.375);
}

TEST(VerdictDistance, InsideForARotatedObbIsItsFarthestCorner) {
  // A cube of half-size 0.25 turned 45 degrees about z, centred at (1.5, 0, 0): its corners reach
  // x = 1.5 + 0.25 (a0 + a1) with the float axes a0 = (c, c, 0), a1 = (-c, c, 0), c = float(sqrt(1/2)).
  const float c = float(std::sqrt(0.5));
  const Obb o{{1.5f, 0, 0}, glm::mat3(glm::vec3(c, c, 0), glm::vec3(-c, c, 0), glm::vec3(0, 0, 1)), {0.25f, 0.25f, 0.25f}};
  expect_distance(cube(), o, Visibility::inside, Visibility::outside, VerdictShift::to_inside, 0.5 + 0.5 * double(c));
}

// ---- verdict intersecting ----------------------------------------------------------------------

TEST(VerdictDistance, IntersectingForABoxOutsideIsThePlaneShiftThatMeetsIt) {
  // Off the corner x = y = 1: the planes x <= 1 and y <= 1 moved out by 0.25 reach the box's corner
  // (1.25, 1.25); the Euclidean gap is 0.25 sqrt 2 (a shift of the volume needs that much).
  const Aabb b{{1.25f, 1.25f, -0.125f}, {1.5f, 1.5f, 0.125f}};
  expect_distance(cube(), b, Visibility::intersecting, Visibility::outside, VerdictShift::to_meeting, 0.25);
  EXPECT_NEAR(classify(cube(), b).distance, 0.25 * std::sqrt(2.0), 1e-15);
}

TEST(VerdictDistance, IntersectingForABallOutsideIsThePlaneShiftThatMeetsIt) {
  // Ball at (2, 2, 0), r = 0.5: the planes moved out by t meet it when its point nearest the
  // diagonal, (2, 2) - 0.5 (1, 1)/sqrt 2, has x = y = 1 + t: t = 1 - 0.5/sqrt 2.
  expect_distance(cube(), Sphere{{2, 2, 0}, 0.5f}, Visibility::intersecting, Visibility::outside,
                  VerdictShift::to_meeting, 1.0 - 0.5 / std::sqrt(2.0));
  // Straight out along x: ball at (2, 0, 0) is 0.5 from x = 1.
  expect_distance(cube(), Sphere{{2, 0, 0}, 0.5f}, Visibility::intersecting, Visibility::outside,
                  VerdictShift::to_meeting, 0.5);
}

TEST(VerdictDistance, IntersectingForAPointOutsideIsItsFarthestPlane) {
  // (1.5, 1.25, 0): 0.5 beyond x = 1 and 0.25 beyond y = 1; both planes must move 0.5.
  expect_distance(cube(), Point{1.5f, 1.25f, 0}, Visibility::intersecting, Visibility::outside, VerdictShift::to_meeting, 0.5);
}

TEST(VerdictDistance, IntersectingForAVolumeInsideIsItsClearance) {
  expect_distance(cube(), Aabb{{0.5f, -0.125f, -0.125f}, {0.875f, 0.125f, 0.125f}}, Visibility::intersecting,
                  Visibility::inside, VerdictShift::to_leaving, 0.125);
  expect_distance(cube(), Sphere{{0, 0, 0.25f}, 0.5f}, Visibility::intersecting, Visibility::inside,
                  VerdictShift::to_leaving, 0.25);
}

// ---- the same measure whatever the planes' form ------------------------------------------------

TEST(VerdictDistance, UnnormalisedPlanesAndMatricesMeasureTheSame) {
  Frustum f = cube_frustum();
  f[kRight] = Plane{{-4, 0, 0}, 4};  // x <= 1, four times over
  const Aabb b{{0.5f, -0.125f, -0.125f}, {0.875f, 0.125f, 0.125f}};
  expect_distance(frustum_spec(f), b, Visibility::outside, Visibility::inside, VerdictShift::to_outside, 0.5);
  expect_distance(frustum_spec(f), b, Visibility::intersecting, Visibility::inside, VerdictShift::to_leaving, 0.125);
  // The identity as an OpenGL clip matrix: F = [-1, 1]^3 again, taken end to end.
  const CaseFrustum m = frustum_spec(glm::mat4(1.0f), DepthConvention{DepthRange::negative_one_to_one, false});
  expect_distance(m, b, Visibility::outside, Visibility::inside, VerdictShift::to_outside, 0.5);
  expect_distance(m, Sphere{{2, 2, 0}, 0.5f}, Visibility::intersecting, Visibility::outside, VerdictShift::to_meeting,
                  1.0 - 0.5 / std::sqrt(2.0));
}

TEST(VerdictDistance, PlanesOfTinyCoefficientsMeasureAsTheUnitOnes) {
  // The cube with every coefficient scaled by 2^-54 (|n| near 5.6e-17): the same distances. A
  // normal's zero components must weigh nothing beside such a plane.
  Frustum f = cube_frustum();
  for (int k = 0; k < kPlaneCount; ++k) f[k] = Plane{f[k].n * 0x1p-54f, f[k].d * 0x1p-54f};
  expect_distance(frustum_spec(f), Sphere{{2, 2, 0}, 0.5f}, Visibility::intersecting, Visibility::outside,
                  VerdictShift::to_meeting, 1.0 - 0.5 / std::sqrt(2.0));
  expect_distance(frustum_spec(f), Sphere{{0.875f, 0, 0}, 0.5f}, Visibility::outside, Visibility::intersecting,
                  VerdictShift::to_outside, 0.625);
  expect_distance(frustum_spec(f), Aabb{{1.25f, 1.25f, -0.125f}, {1.5f, 1.5f, 0.125f}}, Visibility::intersecting,
                  Visibility::outside, VerdictShift::to_meeting, 0.25);
}

TEST(VerdictDistance, TheRightVerdictIsAtZeroAndNoShiftHelpsAnEmptyOrUnboundedFrustum) {
  const VerdictDistance right = distance_to_verdict(cube(), Aabb{{2, 2, 2}, {3, 3, 3}}, Visibility::outside);
  EXPECT_EQ(right.distance, 0.0);
  EXPECT_EQ(right.shift, VerdictShift::none);
  Frustum empty = cube_frustum();
  empty[kFar] = Plane{{0, 0, 0}, -1};  // contains nothing
  EXPECT_EQ(distance_to_verdict(frustum_spec(empty), Point{0, 0, 0}, Visibility::inside).distance,
            std::numeric_limits<double>::infinity());
  Frustum all;
  for (int k = 0; k < kPlaneCount; ++k) all[k] = Plane{{0, 0, 0}, 1};  // every plane holds all space
  EXPECT_EQ(distance_to_verdict(frustum_spec(all), Sphere{{0, 0, 0}, 1}, Visibility::outside).distance,
            std::numeric_limits<double>::infinity());
  // An infinite far plane takes no part: the depth of the centred ball is still 1.
  Frustum open = cube_frustum();
  open[kFar] = Plane{{0, 0, 0}, 1};
  expect_distance(frustum_spec(open), Sphere{{0, 0, 0}, 0.5f}, Visibility::outside, Visibility::inside,
                  VerdictShift::to_outside, 1.0);
}

TEST(VerdictDistance, InvalidInputIsRefused) {
  EXPECT_THROW(distance_to_verdict(cube(), Sphere{{0, 0, 0}, -1.0f}, Visibility::outside), ValidationError);
}

}  // namespace
}  // namespace cullproof::oracle::test

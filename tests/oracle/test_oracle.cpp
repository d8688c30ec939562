// Hand-made exact cases for the oracle. Every expected truth is derived by hand in the comment
// next to it; every coordinate is a float that is exactly the number written.
#include "oracle_test_util.hpp"

#include "cullproof/io/case_io.hpp"

#include <glm/ext/matrix_clip_space.hpp>

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

namespace cullproof::oracle::test {
namespace {

const float kOneUp = std::nextafter(1.0f, 2.0f);    // 1 + 2^-23
const float kOneDown = std::nextafter(1.0f, 0.0f);  // 1 - 2^-24

// The cube with its right plane replaced by x + y <= 1 (n = (-1,-1,0), d = 1).
CaseFrustum cube_cut_xy() {
  Frustum f = cube_frustum();
  f[kRight] = Plane{{-1, -1, 0}, 1};
  return frustum_spec(f);
}

// The cube with its right plane replaced by x + y + z <= 1.
CaseFrustum cube_cut_xyz() {
  Frustum f = cube_frustum();
  f[kRight] = Plane{{-1, -1, -1}, 1};
  return frustum_spec(f);
}

TEST(OracleTouching, BoxTouchesRightPlaneAtAFace) {
  // Box x ∈ [1,2] shares its face x = 1 with the cube's face: B ∩ F is that square, not empty,
  // and B is not inside (x = 2 > 1). Touching from outside is intersecting (docs/semantics.md).
  const Result r = expect_truth(cube(), box({1, -0.5f, -0.5f}, {2, 0.5f, 0.5f}), Visibility::intersecting);
  // Penetration along the right normal is max_B (1 - x) = 0.
  EXPECT_EQ(r.distance, 0.0);
  EXPECT_EQ(r.distance_kind, DistanceKind::margin);
}

TEST(OracleTouching, BoxTouchesObliquePlaneAtAnEdge) {
  // Plane x + y <= 1; the box [0.5,1]x[0.5,1]x[-0.5,0.5] has x + y >= 1 with equality only on
  // its edge x = y = 0.5, which lies in every other cube plane: intersecting.
  expect_truth(cube_cut_xy(), box({0.5f, 0.5f, -0.5f}, {1, 1, 0.5f}), Visibility::intersecting);
}

TEST(OracleTouching, BoxTouchesObliquePlaneAtAVertex) {
  // Plane x + y + z <= 1; the box [0.25,1]x[0.25,1]x[0.5,1] has x + y + z >= 1 with equality
  // only at its corner (0.25, 0.25, 0.5), inside the cube: intersecting.
  expect_truth(cube_cut_xyz(), box({0.25f, 0.25f, 0.5f}, {1, 1, 1}), Visibility::intersecting);
}

TEST(OracleTouching, BoxOneUlpBeyondAFaceIsOutside) {
  // min.x = 1 + 2^-23 > 1: every point violates x <= 1. Distance is exactly 2^-23.
  const Result r = expect_truth(cube(), box({kOneUp, -0.5f, -0.5f}, {2, 0.5f, 0.5f}), Visibility::outside);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -23));
  EXPECT_EQ(r.distance_kind, DistanceKind::euclidean);
}

TEST(OracleTouching, BoxOneUlpAcrossAFaceIsIntersecting) {
  // min.x = 1 - 2^-24 < 1: the slab x ∈ [1 - 2^-24, 1] of B is in F; x = 2 is not.
  const Result r = expect_truth(cube(), box({kOneDown, -0.5f, -0.5f}, {2, 0.5f, 0.5f}), Visibility::intersecting);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -24));  // penetration 1 - (1 - 2^-24)
}

TEST(OracleTouching, BoxOneUlpPastAVertexIsOutside) {
  // x + y + z at the corner is 0.25 + 0.25 + (0.5 + 2^-24) > 1 (0.5's ulp is 2^-24).
  expect_truth(cube_cut_xyz(), box({0.25f, 0.25f, std::nextafter(0.5f, 1.0f)}, {1, 1, 1}), Visibility::outside);
}

TEST(OracleTouching, BoxOneUlpIntoAVertexIsIntersecting) {
  expect_truth(cube_cut_xyz(), box({0.25f, 0.25f, std::nextafter(0.5f, 0.0f)}, {1, 1, 1}),
               Visibility::intersecting);
}

TEST(OracleContainment, BoxContainingTheFrustumIsIntersecting) {
  // [-2,2]^3 ⊇ F: B ∩ F = F ≠ ∅ and B ⊄ F.
  const Result r = expect_truth(cube(), box({-2, -2, -2}, {2, 2, 2}), Visibility::intersecting);
  // Protrusion is 1 (x = 2 is 1 beyond x <= 1), penetration 3 (max over B of 1 + x).
  EXPECT_EQ(r.distance, 1.0);
  EXPECT_EQ(r.witness.penetration, 3.0);
  EXPECT_EQ(r.witness.protrusion, 1.0);
}

TEST(OracleContainment, FrustumContainingTheBoxIsInside) {
  const Result r = expect_truth(cube(), box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}), Visibility::inside);
  EXPECT_EQ(r.distance, 0.5);  // clearance to every face
  EXPECT_EQ(r.distance_kind, DistanceKind::clearance);
}

TEST(OracleContainment, BoxEqualToTheFrustumIsInsideTouchingFromInside) {
  // B = F: B ⊆ F holds (closed sets), so inside; clearance 0.
  const Result r = expect_truth(cube(), box({-1, -1, -1}, {1, 1, 1}), Visibility::inside);
  EXPECT_EQ(r.distance, 0.0);
}

TEST(OracleContainment, BoxOneUlpTooBigIsIntersecting) {
  expect_truth(cube(), box({-1, -1, -1}, {1, 1, kOneUp}), Visibility::intersecting);
}

TEST(OracleEdges, ObbSeparatedOnlyByAnEdgeDirectionIsOutside) {
  // OBB with axes (1,1,0), (-1,1,0), (0,0,1), half 0.5, centre (2,1.5,0): its vertices in xy are
  // (1,1.5), (2,0.5), (3,1.5), (2,2.5), so every point has x + y >= 2.5, while F (the cube)
  // has x + y <= 2. No single plane separates: min x over B is 1 and min y is 0.5.
  // Distance: from F's edge point (1,1,0) to the line x + y = 2.5, (2.5 - 2)/sqrt(2).
  Obb o;
  o.center = {2, 1.5f, 0};
  o.axes = glm::mat3(glm::vec3(1, 1, 0), glm::vec3(-1, 1, 0), glm::vec3(0, 0, 1));
  o.half = {0.5f, 0.5f, 0.5f};
  const Result r = expect_truth(cube(), o, Visibility::outside);
  EXPECT_NEAR(r.distance, 0.5 / std::sqrt(2.0), 1e-15);
  // Moved to centre (2,1,0): vertex (1,1) is on F's edge: touching, intersecting.
  o.center = {2, 1, 0};
  expect_truth(cube(), o, Visibility::intersecting);
}

TEST(OracleEdges, ObbEdgeTouchesAFace) {
  // Same axes, centre (2,0,0): leftmost vertex (1,0) extended along z is an edge on x = 1.
  Obb o;
  o.center = {2, 0, 0};
  o.axes = glm::mat3(glm::vec3(1, 1, 0), glm::vec3(-1, 1, 0), glm::vec3(0, 0, 1));
  o.half = {0.5f, 0.5f, 0.5f};
  expect_truth(cube(), o, Visibility::intersecting);
  // One ulp of 2 (2^-22) further right: the edge is at x = 1 + 2^-22 > 1.
  o.center.x = std::nextafter(2.0f, 3.0f);
  const Result r = expect_truth(cube(), o, Visibility::outside);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -22));
}

TEST(OracleInfinite, InfiniteFarPlaneContainsAllSpace) {
  // glm::infinitePerspective: the far plane is r4 - r3 with equal first three entries, so
  // n == 0 and d > 0. A box 10^6 in front of the camera on the view axis is inside (the side
  // planes are |x|, |y| <= k|z| with k ≈ 1 and the near plane is z <= -1).
  const glm::mat4 P = glm::infinitePerspective(glm::radians(90.0f), 1.0f, 1.0f);
  const CaseFrustum f = frustum_spec(P, DepthConvention{});
  EXPECT_TRUE(f.planes[kFar].is_degenerate());
  EXPECT_GT(f.planes[kFar].d, 0.0f);
  const Aabb far_box = box({-1, -1, -1e6f - 1}, {1, 1, -1e6f + 1});
  expect_truth(f, far_box, Visibility::inside);
  expect_truth(f, Point{0, 0, -1e30f}, Visibility::inside);
  // The same box against a finite far plane at 100 is outside (it is beyond the far plane).
  const CaseFrustum finite = frustum_spec(glm::perspective(glm::radians(90.0f), 1.0f, 1.0f, 100.0f), DepthConvention{});
  expect_truth(finite, far_box, Visibility::outside);
  // Behind the camera is outside for both (z > -1 violates the near plane).
  expect_truth(f, box({-1, -1, 1}, {1, 1, 2}), Visibility::outside);
}

TEST(OracleInfinite, SphereInInfiniteFrustum) {
  const CaseFrustum f = frustum_spec(glm::infinitePerspective(glm::radians(90.0f), 1.0f, 1.0f), DepthConvention{});
  expect_truth(f, Sphere{{0, 0, -1e20f}, 1e3f}, Visibility::inside);
  expect_truth(f, Sphere{{0, 0, 10}, 1}, Visibility::outside);
}

// Orthographic projection of the slab x,y ∈ [-1,1], z ∈ [-3,-1] with exactly representable
// entries: x_clip = x, y_clip = y, w = 1 and
//   [-1,1] (glm::orthoRH_NO(-1,1,-1,1,1,3)):  z_clip = -z - 2
//   [0,1]  (glm::orthoRH_ZO(-1,1,-1,1,1,3)):  z_clip = -z/2 - 1/2
// Reversed-Z ([0,1], near at depth 1): z' = w - z_clip = z/2 + 3/2; the region is the same.
glm::mat4 reversed(const glm::mat4& p) {
  glm::mat4 r(1.0f);
  r[2][2] = -1.0f;
  r[3][2] = 1.0f;
  return r * p;
}

TEST(OracleMatrix, OrthographicDepthConventionsGiveTheSameSlab) {
  const CaseFrustum no = frustum_spec(glm::orthoRH_NO(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 3.0f), DepthConvention{});
  const CaseFrustum zo = frustum_spec(glm::orthoRH_ZO(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 3.0f),
                                      DepthConvention{DepthRange::zero_to_one, false});
  const CaseFrustum rz = frustum_spec(reversed(glm::orthoRH_ZO(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 3.0f)),
                                      DepthConvention{DepthRange::zero_to_one, true});
  for (const CaseFrustum* f : {&no, &zo, &rz}) {
    // A point on the near plane z = -1 is inside (closed half-space); 1 ulp nearer the camera
    // (z = -(1 - 2^-24)) it is outside.
    expect_truth(*f, Point{0, 0, -1}, Visibility::inside);
    expect_truth(*f, Point{0, 0, -kOneDown}, Visibility::outside);
    // On the far plane z = -3: inside; a box z ∈ [-4,-3] touches it from outside.
    expect_truth(*f, Point{0.5f, -1, -3}, Visibility::inside);
    expect_truth(*f, box({-0.5f, -0.5f, -4}, {0.5f, 0.5f, -3}), Visibility::intersecting);
    expect_truth(*f, box({-0.5f, -0.5f, -4}, {0.5f, 0.5f, std::nextafter(-3.0f, -4.0f)}), Visibility::outside);
    expect_truth(*f, box({-1, -1, -3}, {1, 1, -1}), Visibility::inside);
  }
  // The reversed matrix really is reversed: near is r3 there, far r4 - r3.
  EXPECT_EQ(rz.depth.reversed_z, true);
}

TEST(OracleMatrix, ReversedZPerspective) {
  // Camera at the origin looking down -z, near 1, far 100 (view_projection reverses depth).
  PerspectiveCamera cam;
  cam.fovy_degrees = 90.0f;
  cam.near_dist = 1.0f;
  cam.far_dist = 100.0f;
  const DepthConvention rz{DepthRange::zero_to_one, true};
  const CaseFrustum f = frustum_spec(view_projection(cam, rz), rz);
  expect_truth(f, Point{0, 0, -50}, Visibility::inside);    // between near and far
  expect_truth(f, Point{0, 0, -0.5f}, Visibility::outside);  // in front of the near plane
  expect_truth(f, Point{0, 0, -200}, Visibility::outside);   // beyond the far plane
  // Reversed-Z with an infinite far plane: the far plane is r3 with r3 = (0,0,0,near) > 0.
  cam.far_dist = INFINITY;
  const CaseFrustum inf = frustum_spec(view_projection(cam, rz), rz);
  expect_truth(inf, Point{0, 0, -1e30f}, Visibility::inside);
  expect_truth(inf, Point{0, 0, -0.5f}, Visibility::outside);
}

TEST(OracleDegenerate, FlatBoxAcrossAPlaneIsIntersecting) {
  // A square at z = 0 with x ∈ [0.5, 1.5]: the part x <= 1 is in F.
  expect_truth(cube(), box({0.5f, -0.5f, 0}, {1.5f, 0.5f, 0}), Visibility::intersecting);
  // The same square at x ∈ [1 + 2^-23, 2]: outside.
  expect_truth(cube(), box({kOneUp, -0.5f, 0}, {2, 0.5f, 0}), Visibility::outside);
  // A flat square lying in the face x = 1: inside (every point satisfies x <= 1).
  expect_truth(cube(), box({1, -0.5f, -0.5f}, {1, 0.5f, 0.5f}), Visibility::inside);
}

TEST(OracleDegenerate, SegmentBoxes) {
  // Segment along x from 0 to 2 at y = z = 0: crosses x = 1.
  expect_truth(cube(), box({0, 0, 0}, {2, 0, 0}), Visibility::intersecting);
  // Segment from (1,1,-1) to (1,1,1): F's edge, inside.
  expect_truth(cube(), box({1, 1, -1}, {1, 1, 1}), Visibility::inside);
  // Segment parallel to that edge, 1 ulp away in x: outside.
  expect_truth(cube(), box({kOneUp, 1, -1}, {kOneUp, 1, 1}), Visibility::outside);
}

TEST(OracleDegenerate, PointBoxOnACornerIsInside) {
  // A box with min == max at F's corner (1,1,1): a point of F.
  expect_truth(cube(), box({1, 1, 1}, {1, 1, 1}), Visibility::inside);
  Obb o;
  o.center = {1, 1, 1};
  o.half = {0, 0, 0};
  expect_truth(cube(), o, Visibility::inside);
}

TEST(OraclePoint, PointOnAPlaneIsInside) {
  expect_truth(cube(), Point{1, 0, 0}, Visibility::inside);
  expect_truth(cube_cut_xyz(), Point{0.25f, 0.25f, 0.5f}, Visibility::inside);
  const Result r = expect_truth(cube(), Point{kOneUp, 0, 0}, Visibility::outside);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -23));
}

TEST(OracleSphere, ZeroRadiusSphereIsAPoint) {
  expect_truth(cube(), Sphere{{1, 0, 0}, 0}, Visibility::inside);
  const Result r = expect_truth(cube(), Sphere{{kOneUp, 0, 0}, 0}, Visibility::outside);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -23));
}

TEST(OracleSphere, TouchingAFaceFromOutside) {
  // Centre (2,0,0), radius 1: the ball meets x <= 1 only at (1,0,0).
  expect_truth(cube(), Sphere{{2, 0, 0}, 1}, Visibility::intersecting);
  // Radius 1 - 2^-24: distance from the ball to F is exactly 2^-24.
  const Result r = expect_truth(cube(), Sphere{{2, 0, 0}, kOneDown}, Visibility::outside);
  EXPECT_EQ(r.distance, std::ldexp(1.0, -24));
}

TEST(OracleSphere, TouchingFromInsideIsInside) {
  const Result r = expect_truth(cube(), Sphere{{0, 0, 0}, 1}, Visibility::inside);
  EXPECT_EQ(r.distance, 0.0);
  expect_truth(cube(), Sphere{{0, 0, 0}, kOneUp}, Visibility::intersecting);
}

TEST(OracleSphere, NearAnEdgeOnlyTheCornerDistanceDecides) {
  // Centre (2,2,0): distance to each of the planes x = 1, y = 1 is 1, to F (its edge at
  // (1,1,z)) sqrt(2) ≈ 1.41421. Radius 1.5 reaches F; radius 1.4 (float 1.39999998) does not,
  // although it crosses both planes.
  expect_truth(cube(), Sphere{{2, 2, 0}, 1.5f}, Visibility::intersecting);
  const Result r = expect_truth(cube(), Sphere{{2, 2, 0}, 1.4f}, Visibility::outside);
  EXPECT_NEAR(r.distance, std::sqrt(2.0) - double(1.4f), 1e-15);
}

TEST(OracleEmpty, EmptyHalfSpacePutsEverythingOutside) {
  // n == 0, d < 0 contains nothing, so F is empty: every volume is outside, even one that
  // contains the rest of the frustum; the distance to the empty set is +infinity.
  Frustum f = cube_frustum();
  f[kFar] = Plane{{0, 0, 0}, -1};
  const CaseFrustum cf = frustum_spec(f);
  for (const Volume& v : {Volume{box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f})}, Volume{Point{0, 0, 0}},
                          Volume{Sphere{{0, 0, 0}, 5}}}) {
    const Result r = expect_truth(cf, v, Visibility::outside);
    EXPECT_TRUE(std::isinf(r.distance));
    EXPECT_EQ(r.witness.multipliers[kFar].exact, "1");
    EXPECT_TRUE(to_json(r).at("distance").is_null());
  }
  // n == 0, d > 0 contains all space: the same box is inside.
  f[kFar] = Plane{{0, 0, 0}, 1};
  expect_truth(frustum_spec(f), box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 3}), Visibility::intersecting);
  expect_truth(frustum_spec(f), box({-0.5f, -0.5f, -50}, {0.5f, 0.5f, 0.5f}), Visibility::inside);
}

TEST(OracleEmpty, ContradictoryPlanesMakeAnEmptyFrustum) {
  // x >= 1 and x <= 0: no point satisfies both; the certificate combines the two planes.
  Frustum f = cube_frustum();
  f[kLeft] = Plane{{1, 0, 0}, -1};
  f[kRight] = Plane{{-1, 0, 0}, 0};
  for (const Volume& v : {Volume{box({-5, -5, -5}, {5, 5, 5})}, Volume{Sphere{{0, 0, 0}, 100}}}) {
    const Result r = expect_truth(frustum_spec(f), v, Visibility::outside);
    EXPECT_TRUE(std::isinf(r.distance));
  }
}

TEST(OracleWitness, PointWitnessIsExactAndInBoth) {
  const Result r = classify(cube(), box({kOneDown, -0.5f, -0.5f}, {2, 0.5f, 0.5f}));
  ASSERT_EQ(r.witness.kind, Witness::Kind::point);
  for (const Rational& x : r.witness.point) EXPECT_FALSE(x.exact.empty());
  // x is in [1 - 2^-24, 1].
  const double x = r.witness.point[0].approx;
  EXPECT_GE(x, double(kOneDown));
  EXPECT_LE(x, 1.0);
  // Not inside: the corner (2, *, *) violates the right plane x <= 1.
  EXPECT_EQ(r.witness.violated_plane, kRight);
  ASSERT_TRUE(r.witness.outside_corner.has_value());
  EXPECT_EQ((*r.witness.outside_corner)[0].exact, "2");
  // The corpus files' form.
  const nlohmann::json j = to_json(r.witness);
  EXPECT_EQ(j.at("kind"), "point");
  EXPECT_EQ(j.at("point").size(), 3u);
  EXPECT_EQ(j.at("point_approx").at(0).get<double>(), x);
  EXPECT_EQ(j.at("violated_plane"), kRight);
  EXPECT_EQ(j.at("outside_corner").at(0), "2");
  EXPECT_TRUE(j.contains("penetration") && j.contains("protrusion"));
}

TEST(OracleWitness, SeparatingPlaneWitness) {
  const Result r = classify(cube(), box({kOneUp, -0.5f, -0.5f}, {2, 0.5f, 0.5f}));
  ASSERT_EQ(r.witness.kind, Witness::Kind::separating_plane);
  // Only the right plane x <= 1 separates: its multiplier is positive, the others zero.
  for (int k = 0; k < 6; ++k) EXPECT_EQ(r.witness.multipliers[std::size_t(k)].exact == "0", k != kRight) << k;
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j.at("truth"), "outside");
  EXPECT_EQ(j.at("distance").get<double>(), std::ldexp(1.0, -23));
  EXPECT_EQ(j.at("witness").at("kind"), "separating_plane");
  EXPECT_EQ(j.at("witness").at("multipliers").size(), 6u);
  EXPECT_EQ(j.at("witness").at("plane_approx").size(), 4u);
  // Without a witness the verdict is the same and the witness empty.
  const Result bare = classify(cube(), box({kOneUp, -0.5f, -0.5f}, {2, 0.5f, 0.5f}), Options{true, false, false});
  EXPECT_EQ(bare.truth, Visibility::outside);
  EXPECT_EQ(bare.witness.kind, Witness::Kind::none);
  EXPECT_TRUE(to_json(bare.witness).empty());
}

TEST(OracleApi, InvalidInputIsRejected) {
  EXPECT_THROW(classify(cube(), box({1, 0, 0}, {0, 1, 1})), ValidationError);
  EXPECT_THROW(classify(cube(), Sphere{{0, 0, 0}, -1}), ValidationError);
  glm::mat4 m(1.0f);
  m[1][1] = NAN;
  EXPECT_THROW(classify(frustum_spec(m, DepthConvention{}), Point{0, 0, 0}), ValidationError);
  EXPECT_THROW(classify_independent(frustum_spec(m, DepthConvention{}), Point{0, 0, 0}), ValidationError);
}

TEST(OracleApi, StatsCountFilterDecisionsAndFallbacks) {
  reset_stats();
  classify(cube(), box({-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}));  // easy inside: filtered
  // A ball touching a face from outside: the filter cannot prove that the one common point
  // (1,0,0) exists, so this goes to the exact QP.
  classify(cube(), Sphere{{2, 0, 0}, 1});
  const Stats s = stats();
  EXPECT_EQ(s.calls, 2u);
  EXPECT_EQ(s.filtered + s.fallbacks, s.calls);
  EXPECT_GE(s.filtered, 1u);
  EXPECT_GE(s.fallbacks, 1u);
  EXPECT_GT(s.exact_lp + s.closest_pairs, 0u);
  EXPECT_DOUBLE_EQ(s.fallback_fraction(), double(s.fallbacks) / 2.0);
}

// An outside volume's distance: the closest pair found in double and proven exactly where F is
// bounded, the exact QP where it is not (here: no far plane), the same exact value as the QP
// alone either way.
TEST(OracleDistance, TheClosestPairFoundInDoubleIsTheQpsOptimum) {
  Options qp_only;
  qp_only.closest_in_double = false;
  struct Expected {
    Volume v;
    double distance;
  };
  // The cube [-1,1]^3: a box beyond a corner at (1,1,1) + (1,2,2), a box beyond an edge, beside a
  // face, a point, and a ball beyond a corner.
  const std::vector<Expected> cases = {
      {box({2, 3, 3}, {4, 4, 4}), 3.0},
      {box({3, 4, -0.5f}, {5, 6, 0.25f}), std::sqrt(13.0)},
      {box({1.5f, -8, -8}, {2, 8, 8}), 0.5},
      {Point{1, 5, 1}, 4.0},
      {Sphere{{3, 3, 2}, 1}, 2.0},
  };
  for (const Expected& e : cases) {
    SCOPED_TRACE(format_volume(e.v));
    reset_stats();
    const Result fast = classify(frustum_spec(cube_frustum()), e.v);
    EXPECT_EQ(stats().exact_lp, 0u) << "no QP solved";
    EXPECT_GE(stats().closest_pairs, 1u);
    const Result qp = classify(frustum_spec(cube_frustum()), e.v, qp_only);
    ASSERT_EQ(fast.truth, Visibility::outside);
    EXPECT_EQ(fast.distance, qp.distance);
    EXPECT_NEAR(fast.distance, e.distance, 4e-16 * e.distance);
  }
  // Without a far plane F is unbounded: its search is cut to a box about B, the pair proven the same.
  Frustum open = cube_frustum();
  open[kFar] = Plane{{0, 0, 0}, 1};
  reset_stats();
  const Volume beyond = box({2, 3, -9}, {4, 4, -8});
  const Result r = classify(frustum_spec(open), beyond);
  EXPECT_EQ(stats().exact_lp, 0u);
  EXPECT_EQ(r.distance, std::sqrt(5.0));
  EXPECT_EQ(r.distance, classify(frustum_spec(open), beyond, qp_only).distance);
  // A box one float step beyond the face x <= 1 of a frustum reaching to x = -2^40 lies too near
  // for double to tell the planes active at the pair apart: the QP decides.
  Frustum long_box = cube_frustum();
  long_box[kLeft] = Plane{{1, 0, 0}, 0x1p40f};
  reset_stats();
  const float just = 1.0f + 0x1p-23f;
  const Result near = classify(frustum_spec(long_box), box({just, -0.5f, -0.5f}, {2, 0.5f, 0.5f}));
  EXPECT_EQ(stats().closest_pairs, 0u);
  EXPECT_GT(stats().exact_lp, 0u);
  EXPECT_EQ(near.distance, double(0x1p-23f));
}

TEST(OracleApi, TwoThreadsAgreeWithOneThread) {
  std::vector<std::pair<CaseFrustum, Volume>> cases;
  for (int i = 0; i < 64; ++i) {
    const float s = 0.5f + float(i) / 64.0f;
    cases.emplace_back(cube(), box({s, -0.5f, -0.5f}, {s + 1, 0.5f, 0.5f}));
    cases.emplace_back(cube_cut_xyz(), Sphere{{s, s, s}, s / 2});
  }
  std::vector<Visibility> expected;
  for (const auto& [f, v] : cases) expected.push_back(classify(f, v).truth);
  // Both threads run the filter, the exact LP/QP route and the distance QP at the same time.
  std::atomic<int> mismatches{0};
  auto work = [&] {
    Options exact_only;
    exact_only.filter = false;
    for (int round = 0; round < 4; ++round)
      for (std::size_t i = 0; i < cases.size(); ++i) {
        if (classify(cases[i].first, cases[i].second).truth != expected[i]) ++mismatches;
        if (classify(cases[i].first, cases[i].second, exact_only).truth != expected[i]) ++mismatches;
      }
  };
  std::thread a(work), b(work);
  a.join();
  b.join();
  EXPECT_EQ(mismatches.load(), 0);
}

}  // namespace
}  // namespace cullproof::oracle::test

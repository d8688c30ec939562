// Certified-exact culling on hand-made cases whose truth is known by construction: touching
// faces, edges and corners from either side, one unit in the last place away, the ends of the
// float range (coordinates near FLT_MAX, subnormal distances), matrix frusta whose float
// extraction differs from the exact planes; and the margins re-derived from the error model.
// The oracle checks every family in test_exact_certified_property.
#include "cullproof/simd/exact_certified.hpp"
#include "cullproof/simd/exact_certified_batch.hpp"
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/methods/methods.hpp"

#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace cullproof;
using V = Visibility;

namespace {

// glm::frustum(-1, 1, -1, 1, 1, 3): |x|, |y| <= -z, z in [-3, -1]; exact integer planes.
CaseFrustum integer_frustum() { return frustum_spec(frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3))); }

// The same frustum with its far plane at infinity (all space).
CaseFrustum open_frustum() {
  CaseFrustum f = integer_frustum();
  f.planes[kFar] = Plane{glm::vec3(0.0f), 1.0f};
  return f;
}

// The box [0, 1]^3 as six unit planes.
CaseFrustum unit_cube() {
  Frustum f;
  f[kLeft] = {{1, 0, 0}, 0};
  f[kRight] = {{-1, 0, 0}, 1};
  f[kBottom] = {{0, 1, 0}, 0};
  f[kTop] = {{0, -1, 0}, 1};
  f[kNear] = {{0, 0, 1}, 0};
  f[kFar] = {{0, 0, -1}, 1};
  return frustum_spec(f);
}

float up1(float x) { return std::nextafter(x, std::numeric_limits<float>::infinity()); }
float down1(float x) { return std::nextafter(x, -std::numeric_limits<float>::infinity()); }

struct Checked {
  V verdict;
  ExactStage stage;
};
Checked aabb(const CaseFrustum& cf, const Aabb& b) {
  const ExactCertifiedFrustum f = prepare_exact_certified(cf);
  Checked c{};
  c.verdict = exact_certified_aabb(f, b, &c.stage);
  // The OBB with the same geometry must agree (when to_obb's float centre and half-extents
  // describe the box exactly).
  const Obb o = to_obb(b);
  bool same = true;
  for (int i = 0; i < 3; ++i)
    same = same && double(o.center[i]) - double(o.half[i]) == double(b.min[i]) &&
           double(o.center[i]) + double(o.half[i]) == double(b.max[i]);
  if (same) {
    EXPECT_EQ(exact_certified_obb(f, o), c.verdict) << "obb-exact-certified on the same box";
  }
  return c;
}
Checked sphere(const CaseFrustum& cf, const Sphere& s) {
  const ExactCertifiedFrustum f = prepare_exact_certified(cf);
  Checked c{};
  c.verdict = exact_certified_sphere(f, s, &c.stage);
  return c;
}

}  // namespace

TEST(ExactCertified, ClearCasesAreDecidedByThePlaneStage) {
  const CaseFrustum f = integer_frustum();
  EXPECT_EQ(aabb(f, Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}}).verdict, V::inside);
  EXPECT_EQ(aabb(f, Aabb{{-0.5f, -0.5f, -10}, {0.5f, 0.5f, -5}}).verdict, V::outside);
  const Checked straddle = aabb(f, Aabb{{-0.5f, -0.5f, -2.5f}, {5, 0.5f, -1.5f}});
  EXPECT_EQ(straddle.verdict, V::intersecting);
  EXPECT_EQ(straddle.stage, ExactStage::planes);  // one plane crossed, its p-vertex inside
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -2}, 0.25f}).verdict, V::inside);
  EXPECT_EQ(sphere(f, Sphere{{0, 0, 5}, 1}).verdict, V::outside);
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -2}, 0.75f}).verdict, V::inside);  // 1 from near and far, sqrt 2 from the sides
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -2}, 1.25f}).verdict, V::intersecting);
}

// Touching is decided exactly: from outside it is intersecting, from inside inside.
TEST(ExactCertified, TouchingFromOutsideIsIntersecting) {
  const CaseFrustum f = integer_frustum();
  const Checked face = aabb(f, Aabb{{-0.5f, -0.5f, -1}, {0.5f, 0.5f, 0}});  // shares the face z = -1
  EXPECT_EQ(face.verdict, V::intersecting);
  EXPECT_EQ(face.stage, ExactStage::exact);
  EXPECT_EQ(aabb(f, Aabb{{3, 3, -4}, {4, 4, -3}}).verdict, V::intersecting);       // the corner (3, 3, -3)
  EXPECT_EQ(aabb(f, Aabb{{2, -0.5f, -2}, {2.5f, 0.5f, -1.5f}}).verdict, V::intersecting);  // an edge on x = -z
  EXPECT_EQ(aabb(f, Aabb{{2, 2, -2}, {2.5f, 2.5f, -1.5f}}).verdict, V::intersecting);   // a vertex on x = y = -z
  const Checked tangent = sphere(f, Sphere{{0, 0, -0.5f}, 0.5f});                       // tangent to z = -1
  EXPECT_EQ(tangent.verdict, V::intersecting);
  EXPECT_EQ(tangent.stage, ExactStage::exact);
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -3.5f}, 0.5f}).verdict, V::intersecting);  // tangent to the far plane
}

TEST(ExactCertified, TouchingFromInsideIsInside) {
  const CaseFrustum f = integer_frustum();
  const Checked near = aabb(f, Aabb{{-0.5f, -0.5f, -2}, {0.5f, 0.5f, -1}});
  EXPECT_EQ(near.verdict, V::inside);
  EXPECT_EQ(near.stage, ExactStage::exact);
  // Along an edge of the left plane x = z: min x equals max z.
  EXPECT_EQ(aabb(f, Aabb{{-2, -0.5f, -2.5f}, {-1.5f, 0.5f, -2}}).verdict, V::inside);
  // Filling the frustum's bounding box at the far face: the corner (3, 3, -3) lies on three planes.
  EXPECT_EQ(aabb(f, Aabb{{-1, -1, -3}, {1, 1, -1}}).verdict, V::inside);
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -1.5f}, 0.5f}).verdict, V::inside);  // tangent to near from inside
  EXPECT_EQ(sphere(unit_cube(), Sphere{{0.5f, 0.5f, 0.5f}, 0.5f}).verdict, V::inside);  // touches all six faces
}

// One unit in the last place from touching: far above the cascade's double margins (2^-50 of
// the magnitudes), so the float stages decide it, and the answer is exact.
TEST(ExactCertified, OneUlpFromTouching) {
  const CaseFrustum f = integer_frustum();
  EXPECT_EQ(aabb(f, Aabb{{-0.5f, -0.5f, down1(-1)}, {0.5f, 0.5f, 0}}).verdict, V::intersecting);
  const Checked apart = aabb(f, Aabb{{-0.5f, -0.5f, up1(-1)}, {0.5f, 0.5f, 0}});
  EXPECT_EQ(apart.verdict, V::outside);
  EXPECT_NE(apart.stage, ExactStage::exact);
  EXPECT_EQ(aabb(f, Aabb{{up1(3), 3, -4}, {4, 4, -3}}).verdict, V::outside);
  EXPECT_EQ(aabb(f, Aabb{{-0.5f, -0.5f, -2}, {0.5f, 0.5f, up1(-1)}}).verdict, V::intersecting);  // pokes out
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -0.5f}, down1(0.5f)}).verdict, V::outside);
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -0.5f}, up1(0.5f)}).verdict, V::intersecting);
}

// Near a frustum edge and corner no single plane separates (n/p tests keep these); a
// combination of two or three planes does. For an AABB that needs planes whose normals differ in
// sign along some axis (else their common p-vertex is a common point): here the far plane z >= -3
// and the left plane x >= z, or the right and top planes x, y <= -z with the far plane.
TEST(ExactCertified, SeparatedOnlyByACombinationOfPlanes) {
  const CaseFrustum f = integer_frustum();
  const Checked edge = aabb(f, Aabb{{-3.3f, -0.1f, -3.3f}, {-3.05f, 0.1f, -2.95f}});
  EXPECT_EQ(edge.verdict, V::outside);
  EXPECT_EQ(edge.stage, ExactStage::axes);
  EXPECT_EQ(aabb(f, Aabb{{-3.3f, -0.1f, -3.3f}, {-3.0f, 0.1f, -2.95f}}).verdict, V::intersecting);  // touches the edge
  const Checked corner = aabb(f, Aabb{{3.05f, 3.05f, -3.3f}, {3.3f, 3.3f, -2.95f}});
  EXPECT_EQ(corner.verdict, V::outside);
  EXPECT_EQ(corner.stage, ExactStage::axes);
  // A ball by the corner (3, 3, -3), within r of each of its three planes, farther than r from it.
  const Checked ball = sphere(f, Sphere{{3.05f, 3.05f, -2.95f}, 0.08f});
  EXPECT_EQ(ball.verdict, V::outside);
  EXPECT_EQ(ball.stage, ExactStage::axes);
  EXPECT_EQ(sphere(f, Sphere{{3.05f, 3.05f, -2.95f}, 0.09f}).verdict, V::intersecting);
}

// An AABB's separating axes other than the planes are the same for every box: the frame lists
// them as combinations of two planes (an edge against a box axis) and three (a corner against a
// box face), and when the list is complete a box that every one of them leaves on its inner side
// meets the frustum, with no witness point to find.
TEST(ExactCertified, TheFramesCombinationsDecideEdgesAndCorners) {
  const ExactCertifiedFrustum f = prepare_exact_certified(integer_frustum());
  EXPECT_TRUE(f.comb_complete);
  ASSERT_GT(f.comb_count, 0);
  ASSERT_LE(f.comb_count, ExactCertifiedFrustum::kCombinations);
  for (int j = 0; j < f.count; ++j) {  // a single plane is no combination
    EXPECT_EQ(f.comb_in[std::size_t(1) << j][0], 0u);
    EXPECT_EQ(f.comb_in[std::size_t(1) << j][1], 0u);
  }
  // Left x >= z and far z >= -3 differ in sign along z; their combination is x >= -3.
  int left = -1, far = -1;
  for (int j = 0; j < f.count; ++j) {
    if (f.plane[std::size_t(j)].index == kLeft) left = j;
    if (f.plane[std::size_t(j)].index == kFar) far = j;
  }
  const std::uint64_t pair = f.comb_in[(1u << left) | (1u << far)][0];
  ASSERT_NE(pair, 0u);
  const auto& c = f.comb[std::size_t(__builtin_ctzll(pair))];
  EXPECT_GT(c.cx, 0.0);
  EXPECT_EQ(c.cy, 0.0);
  EXPECT_EQ(c.cz, 0.0);
  EXPECT_EQ(c.d, 3.0 * c.cx);
  // A box about the edge point (-3, 0, -3): both planes cut it, their p-vertices differ.
  ExactStage stage{};
  EXPECT_EQ(exact_certified_aabb(f, Aabb{{-3.1f, -0.1f, -3.1f}, {-2.9f, 0.1f, -2.9f}}, &stage), V::intersecting);
  EXPECT_EQ(stage, ExactStage::axes);
  EXPECT_EQ(exact_certified_aabb(f, Aabb{{-3.3f, -0.1f, -3.3f}, {-3.05f, 0.1f, -2.95f}}, &stage), V::outside);
  EXPECT_EQ(stage, ExactStage::axes);
  // A frame with no interior point (near beyond far) lists combinations but is not complete.
  CaseFrustum inverted = integer_frustum();
  std::swap(inverted.planes[kNear].d, inverted.planes[kFar].d);
  inverted.planes[kNear].d = -4.0f;
  EXPECT_FALSE(prepare_exact_certified(inverted).comb_complete);
}

// The ends of the float range: coordinates near FLT_MAX (products overflow float, not double),
// and distances below the smallest normal float.
TEST(ExactCertified, HugeCoordinates) {
  const float big = FLT_MAX;
  const CaseFrustum f = integer_frustum();
  EXPECT_EQ(aabb(f, Aabb{{-big, -big, -big}, {big, big, big}}).verdict, V::intersecting);  // holds the frustum
  EXPECT_EQ(sphere(f, Sphere{{0, 0, -2}, big}).verdict, V::intersecting);
  EXPECT_EQ(sphere(f, Sphere{{big, big, big}, big}).verdict, V::outside);
  const CaseFrustum open = open_frustum();
  // Deep in the infinite frustum: inside; touching its lateral edge at x = y = -z = 3e38: intersecting.
  EXPECT_EQ(aabb(open, Aabb{{-1e37f, -1e37f, -3e38f}, {1e37f, 1e37f, -2e38f}}).verdict, V::inside);
  EXPECT_EQ(aabb(open, Aabb{{3e38f, 3e38f, -3e38f}, {big, big, -2e38f}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(open, Aabb{{up1(3e38f), 3e38f, -3e38f}, {big, big, -2e38f}}).verdict, V::outside);
  EXPECT_EQ(sphere(open, Sphere{{0, 0, -big}, 1e38f}).verdict, V::inside);
  // Planes with huge coefficients: the same half-spaces scaled by 2^100.
  Frustum scaled = integer_frustum().planes;
  for (Plane& p : scaled.planes) p.n *= 0x1p100f, p.d *= 0x1p100f;
  EXPECT_EQ(aabb(frustum_spec(scaled), Aabb{{-0.5f, -0.5f, -1}, {0.5f, 0.5f, 0}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(frustum_spec(scaled), Aabb{{-0.5f, -0.5f, up1(-1)}, {0.5f, 0.5f, 0}}).verdict, V::outside);
}

TEST(ExactCertified, SubnormalDistances) {
  const float tiny = std::numeric_limits<float>::denorm_min();  // 2^-149
  const CaseFrustum cube = unit_cube();
  EXPECT_EQ(aabb(cube, Aabb{{-1, 0.25f, 0.25f}, {-tiny, 0.75f, 0.75f}}).verdict, V::outside);
  EXPECT_EQ(aabb(cube, Aabb{{-1, 0.25f, 0.25f}, {0, 0.75f, 0.75f}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(cube, Aabb{{tiny, 0.25f, 0.25f}, {0.5f, 0.75f, 0.75f}}).verdict, V::inside);
  EXPECT_EQ(aabb(cube, Aabb{{-tiny, 0.25f, 0.25f}, {0.5f, 0.75f, 0.75f}}).verdict, V::intersecting);
  EXPECT_EQ(sphere(cube, Sphere{{-2 * tiny, 0.5f, 0.5f}, tiny}).verdict, V::outside);
  EXPECT_EQ(sphere(cube, Sphere{{-tiny, 0.5f, 0.5f}, tiny}).verdict, V::intersecting);
  EXPECT_EQ(sphere(cube, Sphere{{tiny, 0.5f, 0.5f}, tiny}).verdict, V::inside);
  // A subnormal box at the corner (0, 0, 0), touching it from outside.
  EXPECT_EQ(aabb(cube, Aabb{{-tiny, -tiny, -tiny}, {0, 0, 0}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(cube, Aabb{{-2 * tiny, -2 * tiny, -2 * tiny}, {-tiny, 0, 0}}).verdict, V::outside);
  // Planes whose coefficients are subnormal: x >= 0 as (2^-149, 0, 0, 0).
  Frustum f = cube.planes;
  f[kLeft] = {{tiny, 0, 0}, 0};
  EXPECT_EQ(aabb(frustum_spec(f), Aabb{{-1, 0.25f, 0.25f}, {-tiny, 0.75f, 0.75f}}).verdict, V::outside);
  EXPECT_EQ(aabb(frustum_spec(f), Aabb{{-1, 0.25f, 0.25f}, {0, 0.75f, 0.75f}}).verdict, V::intersecting);
}

// A matrix frustum is judged on its exact planes (Gribb-Hartmann row sums in exact arithmetic),
// not on the float-rounded ones. Rows r1 = (1, 0, 0, 0), r2 = (0, 1, 0, 0), r3 = (0, 0, -2^-30, 4),
// r4 = (0, 0, -1, 0), depth [0, 1]: the far plane r4 - r3 = (0, 0, -1 + 2^-30, -4) rounds in float
// to (0, 0, -1, -4), z <= -4, on which the point (0, 0, -4) lies; exactly it is
// z <= -4 / (1 - 2^-30) < -4, and the point is outside.
TEST(ExactCertified, MatrixFrustaAreJudgedOnTheirExactPlanes) {
  glm::mat4 m(0.0f);
  auto set_row = [&](int i, glm::vec4 r) {
    for (int c = 0; c < 4; ++c) m[c][i] = r[c];
  };
  set_row(0, {1, 0, 0, 0});
  set_row(1, {0, 1, 0, 0});
  set_row(2, {0, 0, -0x1p-30f, 4});
  set_row(3, {0, 0, -1, 0});
  const CaseFrustum cf = frustum_spec(m, {DepthRange::zero_to_one, false});
  ASSERT_EQ(cf.planes[kFar].n.z, -1.0f);  // the float extraction rounded
  ASSERT_EQ(cf.planes[kFar].d, -4.0f);
  EXPECT_EQ(aabb(cf, Aabb{{0, 0, -4}, {0, 0, -4}}).verdict, V::outside);
  EXPECT_EQ(aabb(cf, Aabb{{-1, -1, -5}, {1, 1, -4}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(cf, Aabb{{-1, -1, -6}, {1, 1, -5}}).verdict, V::inside);
  EXPECT_EQ(sphere(cf, Sphere{{0, 0, -3}, 1}).verdict, V::outside);
}

// The array forms give the scalar cascade's verdicts, volume by volume: on boxes and balls around
// the integer frustum with coordinates on a grid of quarters (many touch a face, an edge or a
// corner exactly, inside or out), in arrays of every length up to 300 (whole SIMD vectors, tails,
// several chunks).
TEST(ExactCertified, ArrayFormsEqualTheScalarCascade) {
  const ExactCertifiedFrustum f = prepare_exact_certified(integer_frustum());
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> q(-16, 16), size(0, 8);
  for (std::size_t n : {std::size_t(1), std::size_t(7), std::size_t(64), std::size_t(65), std::size_t(300)}) {
    std::vector<Aabb> boxes;
    std::vector<Sphere> balls;
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3 lo(q(rng) * 0.25f, q(rng) * 0.25f, -std::abs(q(rng)) * 0.25f);
      const glm::vec3 hi = lo + glm::vec3(size(rng), size(rng), size(rng)) * 0.25f;
      boxes.push_back(Aabb{lo, hi});
      balls.push_back(Sphere{lo, size(rng) * 0.25f});
    }
    std::vector<V> vb(n), vs(n);
    exact_certified_aabbs(f, boxes.data(), n, vb.data());
    exact_certified_spheres(f, balls.data(), n, vs.data());
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(vb[i], exact_certified_aabb(f, boxes[i])) << "box " << i << " of " << n;
      EXPECT_EQ(vs[i], exact_certified_sphere(f, balls[i])) << "ball " << i << " of " << n;
    }
  }
}

// Frusta that are not frusta: planes that hold nothing together, a plane that holds nothing
// (n == 0, d < 0), every plane holding all space.
TEST(ExactCertified, EmptyAndAllSpaceFrusta) {
  Frustum apart = unit_cube().planes;
  apart[kNear] = {{0, 0, 1}, -2};  // z >= 2 and z <= 1: empty
  EXPECT_EQ(aabb(frustum_spec(apart), Aabb{{-4, -4, -4}, {4, 4, 4}}).verdict, V::outside);
  EXPECT_EQ(sphere(frustum_spec(apart), Sphere{{0.5f, 0.5f, 1.5f}, 4}).verdict, V::outside);
  Frustum touching = unit_cube().planes;
  touching[kNear] = {{0, 0, 1}, -1};  // z >= 1 and z <= 1: the square z = 1, no interior
  EXPECT_EQ(aabb(frustum_spec(touching), Aabb{{-4, -4, -4}, {4, 4, 4}}).verdict, V::intersecting);
  EXPECT_EQ(aabb(frustum_spec(touching), Aabb{{-4, -4, -4}, {4, 4, 0.5f}}).verdict, V::outside);
  EXPECT_EQ(aabb(frustum_spec(touching), Aabb{{0.25f, 0.25f, 1}, {0.5f, 0.5f, 1}}).verdict, V::inside);
  EXPECT_EQ(sphere(frustum_spec(touching), Sphere{{0.5f, 0.5f, 2}, 1}).verdict, V::intersecting);
  Frustum nothing = unit_cube().planes;
  nothing[kFar] = {glm::vec3(0.0f), -1};
  EXPECT_EQ(aabb(frustum_spec(nothing), Aabb{{0.25f, 0.25f, 0.25f}, {0.5f, 0.5f, 0.5f}}).verdict, V::outside);
  Frustum all;
  for (Plane& p : all.planes) p = {glm::vec3(0.0f), 1};
  EXPECT_EQ(aabb(frustum_spec(all), Aabb{{-FLT_MAX, -FLT_MAX, -FLT_MAX}, {FLT_MAX, FLT_MAX, FLT_MAX}}).verdict, V::inside);
  EXPECT_EQ(sphere(frustum_spec(all), Sphere{{0, 0, 0}, FLT_MAX}).verdict, V::inside);
}

// The batch forms and the registry: every method claims certified-exact with no tolerance.
TEST(ExactCertified, MethodsAreRegistered) {
  for (const char* name : {"aabb-exact-certified", "obb-exact-certified", "sphere-exact-certified",
                           "aabb-batch-exact-certified", "sphere-batch-exact-certified"}) {
    const Method* m = find_builtin(name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->claim, Claim::certified_exact) << name;
    EXPECT_EQ(m->tolerance, 0.0) << name;
  }
  EXPECT_TRUE(find_builtin("aabb-batch-exact-certified")->has_batch());
  EXPECT_TRUE(find_builtin("sphere-batch-exact-certified")->has_batch());
}

// ---- The margins, re-derived from the error model ------------------------------------------------
//
// Each constant of ExactMargins must cover what the derivation in exact_certified.cpp says the
// computation can err by, computed here from u alone (in long double, 64-bit significand).

namespace {

using L = long double;
constexpr L u = L(ExactMargins::u);
L gamma(int k) { return k * u / (1 - k * u); }

}  // namespace

TEST(ExactCertifiedMargins, UnitRoundoffIsDoubles) { EXPECT_EQ(ExactMargins::u, std::ldexp(1.0, -53)); }

TEST(ExactCertifiedMargins, BoxPlaneStage) {
  // AABB in centre-extent form: v = fl(n'.c + D +- sum |n'_i h_i|), a seven-term inner product
  // (gamma_7) of terms summing to at most A' M (1 + u) + |D|, with c and h rounded once (u A' M)
  // and the coefficients' own error (u (A' M + |d'|)). T = fl(t_box X) >= kBox u (1 - u) A' X.
  const L k = ExactMargins::kBox;
  const L on_m = gamma(7) * (1 + u) + 2 * u;
  EXPECT_LE(on_m, 9.0002L * u);
  EXPECT_GE(k * u * (1 - u), on_m);
  // delta = kBox u |d'| with |D| <= |d'| (1 + kBox u)(1 + 2u).
  EXPECT_GE(k * u * (1 - gamma(7)), gamma(7) * (1 + k * u) * (1 + 2 * u) + u);
  // OBB: s = fl(n'.c) (gamma_3), rad = sum |fl(n'.e_i)| (gamma_3 each, gamma_2 to add them),
  // two more additions (gamma_2), the coefficients (u); e_i = h_i u_i is exact.
  const L obb_x = gamma(3) + gamma(2) + gamma(2) + u;
  EXPECT_LE(obb_x, 8.0002L * u);
  EXPECT_GE(k * u * (1 - u), obb_x);
}

TEST(ExactCertifiedMargins, SpherePlaneStage) {
  // The computed norm: a sum of three squares (gamma_3), a square root (half of it, then u), and
  // the coefficients' own error (u): relative to the computed norm.
  const L alpha = std::max((1 + u) * std::sqrt(1 + gamma(3)) - 1, 1 - (1 - u) * std::sqrt(1 - gamma(3)));
  const L norm_err = (alpha + u) / (1 - alpha);
  EXPECT_LE(norm_err, 3.501L * u);
  // rho = fl(r norm): within (u (1 + norm_err) + norm_err) r norm of r |n|; norm <= (1 + alpha) A'.
  const L rho_err = (u * (1 + norm_err) + norm_err) * (1 + alpha);
  EXPECT_LE(rho_err, 4.502L * u * (1 + u));
  // A five-term sum: the A' M part, the r A' part, the |d'| part.
  const L on_m = gamma(5) + u;
  const L on_r = gamma(5) * (1 + rho_err) * (1 + alpha) + rho_err;
  const L k = ExactMargins::kSphere, kd = ExactMargins::kSphereOffset;
  EXPECT_LE(on_r, 9.503L * u);
  // T = fl(t_sphere fl(M + r)) >= kSphere u (1 - u)^2 A' (M + r).
  EXPECT_GE(k * u * (1 - u) * (1 - u), std::max(on_m, on_r));
  EXPECT_GE(kd * u * (1 - gamma(5)), gamma(5) * (1 + kd * u) * (1 + 2 * u) + u);
}

TEST(ExactCertifiedMargins, BoxRows) {
  // AABB: centre value (gamma_4 (1 + u) + 2u), half-extents (3u + u^2), evaluation gamma_4.
  const L aabb = gamma(4) * (1 + u) + 2 * u + (3 * u + u * u) + gamma(4) * (1 + 7 * u);
  // OBB: centre value (gamma_4 + u), axis terms (gamma_3 + u, e_i exact), evaluation gamma_4.
  const L obb = gamma(4) + u + (gamma(3) + u) * (1 + u) + gamma(4) * (1 + 7 * u);
  EXPECT_LE(aabb, 13.03L * u);
  EXPECT_LE(obb, 13.03L * u);
  EXPECT_GE(L(ExactMargins::kRow) * u, std::max(aabb, obb));
}

TEST(ExactCertifiedMargins, BoxFarkas) {
  // Coefficient errors (at most 9.0003 u W: the AABB's centre value and half-extents) plus the
  // evaluation of psi (at most m + 3 <= 9 roundings on any term, m <= 6 rows), against the weight
  // sum lambda_j W_j computed with gamma_6.
  const L coeff = gamma(4) * (1 + u) + 2 * u + (3 * u + u * u);
  const L need = coeff + gamma(9) * (1 + 11 * u);
  EXPECT_LE(need, 20.03L * u);
  EXPECT_GE(L(ExactMargins::kFarkasBox) * u * (1 - gamma(6)), need);
}

TEST(ExactCertifiedMargins, WitnessPointsAndDistances) {
  // A plane at a double point: the four-term sum and the coefficients.
  EXPECT_GE(L(ExactMargins::kPoint) * u, gamma(4) + u);
  // sum (x_i - c_i)^2: a difference, a square, a three-term sum of positive terms.
  const L rel = (1 + u) * (1 + u) * (1 + u) * (1 + gamma(2)) - 1;
  EXPECT_LE(rel, 5.0001L * u);
  // The check fl(q (1 + kDistance u)) <= r^2 implies the true squared distance <= r^2.
  EXPECT_GE((1 + L(ExactMargins::kDistance) * u) * (1 - u) * (1 - rel), 1.0L);
}

TEST(ExactCertifiedMargins, SphereFarkas) {
  // The combined plane at the centre: each centre value within (gamma_4 + u) W, the sum of at
  // most three products gamma_3; the weight computed with gamma_3.
  const L centre = gamma(4) + u + gamma(3) * (1 + 6 * u);
  EXPECT_GE(L(ExactMargins::kFarkasCentre) * u * (1 - gamma(3)), centre);
  // The combined normal: per component gamma_3 + u of sum lambda |n'|, in the 1-norm.
  EXPECT_GE(L(ExactMargins::kFarkasNormal) * u * (1 - gamma(3)), gamma(3) + u);
}

TEST(ExactCertifiedMargins, Combinations) {
  // A multiplier of three planes: the difference of two products of rounded coefficients (each
  // within u, so a product within 2u + u^2), evaluated with gamma_2.
  EXPECT_GE(L(ExactMargins::kMultiplier) * u, 2 * u + u * u + gamma(2));
  // The combination at a box: the coefficients (u), C and D as three-term sums (gamma_3), c and h
  // rounded (2u, X part only), the seven-term evaluation (gamma_7 on terms grown by gamma_3); all
  // on magnitudes grown by (1 + u). The multipliers' own error is charged at 2 dl >= (1 + u) dl.
  const L on_x = (u + gamma(3) + 2 * u + gamma(7) * (1 + gamma(3))) * (1 + u);
  const L on_d = (u + gamma(3) + gamma(7) * (1 + gamma(3))) * (1 + u);
  EXPECT_LE(on_x, 13.02L * u);
  EXPECT_LE(on_d, 11.02L * u);
  EXPECT_GE(L(ExactMargins::kCombination) * u, std::max(on_x, on_d));
}

TEST(ExactCertifiedMargins, TheSlackCoversTheBoundsOwnRounding) {
  // A bound computed with at most 2^10 roundings errs by at most (1 + u)^1024 - 1 < kSlack.
  EXPECT_LT(std::pow(1 + u, 1024.0L) - 1, L(ExactMargins::kSlack));
}

// ---- The AABB array form's float pass ----------------------------------------------------------

namespace {

TEST(FloatPassMargins, FromTheErrorModel) {
  using F = FloatPassMargins;
  const L uf = std::ldexp(1.0L, -24);
  const auto g = [&](int k) { return k * uf / (1 - k * uf); };
  EXPECT_EQ(L(F::u), uf);
  // A value fl(C.x + D): three products and the offset, gamma_4 in any order, fused or not.
  EXPECT_GE(L(F::kEval) * uf, g(4));
  // The threshold fl(fl(t X) + delta): two roundings, each a factor of at least 1 - u.
  EXPECT_GE((1 + L(F::kWiden)) * (1 - uf) * (1 - uf), 1.0L);
  // Absolute underflow: three products and the threshold's product, each at most 2^-150 (half
  // the smallest subnormal), rounded up with the rest.
  EXPECT_GE(L(F::kUnderflow), 4 * std::ldexp(1.0L, -150) * (1 + L(F::kWiden)));
  EXPECT_EQ(L(F::kSubnormal), std::ldexp(1.0L, -150));  // rounding to float: u |x| plus this
  // Below kRoom, no partial sum of at most four terms (each grown by at most (1 + u)^4) reaches FLT_MAX.
  EXPECT_LT(L(F::kRoom) * std::pow(1 + uf, 8.0L), L(FLT_MAX));
}

// An exact dyadic number m 2^e (every float, double, sum and product of them is one).
struct Q {
  boost::multiprecision::cpp_int m;
  int e = 0;
  Q() = default;
  explicit Q(double x) {
    int ex = 0;
    const double fr = std::frexp(x, &ex);
    m = static_cast<long long>(std::ldexp(fr, 53));
    e = ex - 53;
  }
  friend Q operator+(const Q& a, const Q& b) {
    Q r;
    r.e = std::min(a.e, b.e);
    r.m = (a.m << (a.e - r.e)) + (b.m << (b.e - r.e));
    return r;
  }
  friend Q operator-(const Q& a) { Q r = a; r.m = -r.m; return r; }
  friend Q operator-(const Q& a, const Q& b) { return a + -b; }
  friend Q operator*(const Q& a, const Q& b) { Q r; r.m = a.m * b.m; r.e = a.e + b.e; return r; }
  friend bool operator<=(const Q& a, const Q& b) { return (b - a).m >= 0; }
  friend bool operator>=(const Q& a, const Q& b) { return b <= a; }
  friend Q abs(const Q& a) { Q r = a; if (r.m < 0) r.m = -r.m; return r; }
  friend std::ostream& operator<<(std::ostream& os, const Q& a) { return os << std::ldexp(a.m.convert_to<double>(), a.e); }
};

// Each float item against the double combination it was rounded from, (C, D) scaled by the
// item's power of two r: at the box's vertex the kernel takes, the exact r (C.p + D) and the
// float value (fused and unfused) differ by at most the threshold less the double part
// r (k1 X + k0), on boxes drawn near the item's plane at magnitudes from 1 to 2^20.
TEST(ExactCertifiedFloatPass, EachThresholdBoundsItsItemsRounding) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  Frustum far_off = integer_frustum().planes;  // the frustum moved 2^14 along x: large |d|
  for (int k = 0; k < 6; ++k) far_off[k].d -= far_off[k].n.x * 16384.0f;
  const CaseFrustum frusta[] = {integer_frustum(), frustum_spec(far_off),
                                frustum_spec(frustum_from_matrix(off_axis_projection(-0.7f, 1.3f, -1.1f, 0.4f, 0.5f, 700.0f)))};
  int checked = 0;
  for (const CaseFrustum& cf : frusta) {
    const ExactCertifiedFrustum f = prepare_exact_certified(cf);
    ASSERT_GT(f.float_planes, 0);
    for (int q = 0; q < f.float_count; ++q) {
      const ExactCertifiedFrustum::FloatItem& it = f.float_item[std::size_t(q)];
      if (!std::isfinite(it.t)) continue;
      double C[3], D, k1, k0;
      if (q < f.count) {
        const ExactCertifiedPlane& p = f.plane[std::size_t(q)];
        C[0] = p.nx, C[1] = p.ny, C[2] = p.nz, D = p.d;
        k1 = 0x1p-53 * p.a * (1 + 0x1p-40), k0 = 0x1p-53 * p.ad * (1 + 0x1p-40);
      } else {
        const ExactCertifiedFrustum::Combination& c = f.comb[std::size_t(q - f.count)];
        C[0] = c.cx, C[1] = c.cy, C[2] = c.cz, D = c.d, k1 = c.k1, k0 = c.k0;
      }
      const float Cf[3] = {it.cx, it.cy, it.cz};
      int big = 0;
      for (int i = 1; i < 3; ++i)
        if (std::abs(C[i]) > std::abs(C[big])) big = i;
      if (C[big] == 0.0) continue;
      const double r = std::ldexp(1.0, std::ilogb(double(Cf[big]) / C[big] * (1 + 0x1p-20)));
      for (int trial = 0; trial < 400; ++trial) {
        // A point on the plane C.x + D = 0 (solved for the largest component), moved a little,
        // and a box around it of random extent.
        const float scale = std::ldexp(1.0f, int(rng() % 21));
        double x[3] = {unit(rng) * scale, unit(rng) * scale, unit(rng) * scale};
        x[big] = -(D + C[(big + 1) % 3] * x[(big + 1) % 3] + C[(big + 2) % 3] * x[(big + 2) % 3]) / C[big];
        Aabb b;
        for (int i = 0; i < 3; ++i) {
          const float e = std::ldexp(std::abs(unit(rng)), -int(rng() % 30)) * scale;
          b.min[i] = float(x[i]) - e, b.max[i] = float(x[i]) + e;
        }
        const float X = std::max({std::abs(b.min.x), std::abs(b.min.y), std::abs(b.min.z), std::abs(b.max.x),
                                  std::abs(b.max.y), std::abs(b.max.z)});
        if (!(X <= f.float_x_safe)) continue;
        for (const bool top : {true, false}) {  // the vertex maximising C.x, and the one minimising it
          float p[3];
          for (int i = 0; i < 3; ++i) p[i] = (it.max[std::size_t(i)] != 0) == top ? b.max[i] : b.min[i];
          Q exact = Q(D);
          for (int i = 0; i < 3; ++i) exact = exact + Q(C[i]) * Q(double(p[i]));
          exact = exact * Q(r);
          const Q room = Q(r) * (Q(k1) * Q(double(X)) + Q(k0));
          // The threshold fused or rounded twice, the value fused or not: each pair must hold.
          const Q thetas[2] = {Q(double(std::fma(it.t, X, it.delta))), Q(double(it.t * X + it.delta))};
          const float fused = std::fma(Cf[2], p[2], std::fma(Cf[1], p[1], std::fma(Cf[0], p[0], it.d)));
          const float plain = ((Cf[0] * p[0] + Cf[1] * p[1]) + Cf[2] * p[2]) + it.d;
          for (const Q& theta : thetas)
            for (const float v : {fused, plain}) {
              EXPECT_LE(abs(Q(double(v)) - exact), theta - room) << "item " << q << " trial " << trial;
              ++checked;
            }
        }
      }
    }
  }
  EXPECT_GT(checked, 100000);
}

}  // namespace

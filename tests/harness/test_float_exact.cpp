// Float-exactness (gen::float_exact): hand-made cases on each side of the rule, and the rule's
// soundness against a correct float test: on a float-exact case the n/p-vertex, point and sphere
// tests make no error their exact-arithmetic claim forbids, so no allowance is needed there.
#include "cullproof/io/case_io.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace cullproof {
namespace {

using gen::float_exact;

// The rule as first written, in Boost.Multiprecision integers of 2^-400 (slow, and plainly
// exact): the reference the double-expansion implementation must agree with everywhere.
namespace reference {
using Int = boost::multiprecision::cpp_int;

constexpr int kLowest = -400;  // below every exponent a float product can have

// The exact value of a double that is a float or a product of two floats, as an Int of 2^kLowest.
Int exact(double x) {
  if (x == 0.0) return Int(0);
  int e = 0;
  const double f = std::frexp(x, &e);                        // x = f * 2^e, 0.5 <= |f| < 1
  const auto m = static_cast<std::int64_t>(std::ldexp(f, 53));  // x = m * 2^(e - 53), exactly
  Int v = m;
  v <<= unsigned(e - 53 - kLowest);
  return v;
}

// Whether the value v * 2^kLowest is exactly a finite float.
bool is_float(const Int& v) {
  if (v == 0) return true;
  const Int a = abs(v);
  const unsigned low = boost::multiprecision::lsb(a);
  const unsigned high = boost::multiprecision::msb(a);
  if (high - low >= 24) return false;                     // more than 24 significant bits
  const int low_exp = int(low) + kLowest, high_exp = int(high) + kLowest;
  return low_exp >= -149 && high_exp <= 127;              // not below the subnormals, not infinite
}

// Whether every sum of two or more of the terms (each already a float) is a float: every partial
// sum of any evaluation order is one of these.
bool sums_are_floats(const std::vector<Int>& terms) {
  const std::size_t n = terms.size();
  for (std::uint32_t mask = 1; mask < (1u << n); ++mask) {
    if ((mask & (mask - 1)) == 0) continue;  // a single term
    Int s = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (mask & (1u << i)) s += terms[i];
    if (!is_float(s)) return false;
  }
  return true;
}

// The terms of n.x + d (+ extra), or false when a product n_i x_i is not a float.
bool plane_terms(const Plane& p, const glm::vec3& x, std::vector<Int>& out) {
  out.clear();
  for (int i = 0; i < 3; ++i) {
    out.push_back(exact(double(p.n[i]) * double(x[i])));
    if (!is_float(out.back())) return false;
  }
  out.push_back(exact(double(p.d)));
  return true;
}

bool plane_exact_at(const Plane& p, const glm::vec3& x) {
  std::vector<Int> t;
  return plane_terms(p, x, t) && sums_are_floats(t);
}

bool unit_normal(const Plane& p) {
  Int s = 0;
  for (int i = 0; i < 3; ++i) s += exact(double(p.n[i]) * double(p.n[i]));
  return s == exact(1.0);
}

// n . u for a plane normal and an OBB axis, if it rounds nothing.
bool exact_dot(const glm::vec3& n, const glm::vec3& u, Int& out) {
  std::vector<Int> t;
  for (int i = 0; i < 3; ++i) {
    t.push_back(exact(double(n[i]) * double(u[i])));
    if (!is_float(t.back())) return false;
  }
  if (!sums_are_floats(t)) return false;
  out = t[0] + t[1] + t[2];
  return true;
}

bool obb_exact(const std::array<Plane, kPlaneCount>& planes, const Obb& b) {
  // The corners c + sum_i (+-h_i) u_i, coordinate by coordinate.
  std::array<std::array<Int, 3>, 3> hu{};  // hu[i][k] = h_i * u_ik
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      hu[i][k] = exact(double(b.half[i]) * double(b.axes[i][k]));
      if (!is_float(hu[i][k])) return false;
    }
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 x;
    for (int k = 0; k < 3; ++k) {
      std::vector<Int> t = {exact(double(b.center[k]))};
      for (int i = 0; i < 3; ++i) t.push_back((corner >> i & 1) ? Int(-hu[i][k]) : hu[i][k]);
      if (!sums_are_floats(t)) return false;
      Int s = t[0] + t[1] + t[2] + t[3];
      // s is a float: recover it (its value is exact in double).
      x[k] = float(std::ldexp(s.convert_to<double>(), kLowest));
    }
    for (const Plane& p : planes)
      if (!plane_exact_at(p, x)) return false;
  }
  // The projected form: s = n.c + d against r = sum_i h_i |n . u_i|.
  for (const Plane& p : planes) {
    std::vector<Int> centre;
    if (!plane_terms(p, b.center, centre) || !sums_are_floats(centre)) return false;
    std::vector<Int> r;
    for (int i = 0; i < 3; ++i) {
      Int d;
      if (!exact_dot(p.n, b.axes[i], d)) return false;
      const double dn = std::abs(std::ldexp(d.convert_to<double>(), kLowest));
      r.push_back(exact(double(b.half[i]) * dn));
      if (!is_float(r.back())) return false;
    }
    if (!sums_are_floats(r)) return false;
    const Int s = centre[0] + centre[1] + centre[2] + centre[3], rr = r[0] + r[1] + r[2];
    if (!is_float(s - rr) || !is_float(s + rr)) return false;
  }
  return true;
}

// The Gribb-Hartmann row sums the extraction takes (r4 +- r1, r4 +- r2, r4 - r3, and r4 + r3 for
// the [-1, 1] depth range; a [0, 1] range takes r3 itself), exact in float, so that the planes
// the case gives a culler are the exact planes.
bool extraction_exact(const CaseFrustum& f) {
  if (!f.matrix) return true;
  const glm::mat4& m = *f.matrix;
  for (int c = 0; c < 4; ++c) {  // column-major: m[c][r] is row r of column c
    const Int r4 = exact(double(m[c][3]));
    for (int r = 0; r < 3; ++r) {
      const Int rk = exact(double(m[c][r]));
      if (!is_float(r4 - rk)) return false;
      const bool plus_used = r < 2 || f.depth.range == DepthRange::negative_one_to_one;
      if (plus_used && !is_float(r4 + rk)) return false;
    }
  }
  return true;
}

bool reference_float_exact(const CaseFrustum& f, const Volume& v) {
  if (!extraction_exact(f)) return false;
  const std::array<Plane, kPlaneCount>& planes = f.planes.planes;
  return std::visit(
      [&](const auto& x) -> bool {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) {
          for (const Plane& p : planes)
            if (!plane_exact_at(p, x)) return false;
          return true;
        } else if constexpr (std::is_same_v<T, Sphere>) {
          for (const Plane& p : planes) {
            if (p.n == glm::vec3(0.0f)) continue;  // contains all space or nothing: nothing rounds
            if (!unit_normal(p)) return false;
            std::vector<Int> t;
            if (!plane_terms(p, x.center, t)) return false;
            t.push_back(exact(double(x.radius)));
            if (!sums_are_floats(t)) return false;
          }
          return true;
        } else if constexpr (std::is_same_v<T, Aabb>) {
          for (int c = 0; c < 8; ++c) {
            const glm::vec3 corner((c & 1) ? x.max.x : x.min.x, (c & 2) ? x.max.y : x.min.y, (c & 4) ? x.max.z : x.min.z);
            for (const Plane& p : planes)
              if (!plane_exact_at(p, corner)) return false;
          }
          return true;
        } else {
          return obb_exact(planes, x);
        }
      },
      v);
}

}  // namespace reference

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

// The implementation agrees with the reference on every family's cases and on any case at all
// (where most sums round), and on cases whose coordinates are rescaled toward the float range's
// ends (subnormal products, sums beyond the largest float).
TEST(FloatExact, AgreesWithTheIntegerReferenceEverywhere) {
  int exact = 0, n = 0;
  for (gen::Distribution d : gen::parse_distributions("all"))
    for (std::uint64_t i = 0; i < 300; ++i) {
      const gen::GenCase g = gen::draw_case(d, 7, i);
      const bool e = float_exact(g.frustum, g.volume);
      EXPECT_EQ(e, reference::reference_float_exact(g.frustum, g.volume))
          << gen::to_string(d) << " case " << i << ": " << format_frustum(g.frustum) << " " << format_volume(g.volume);
      exact += e;
      ++n;
    }
  EXPECT_GT(exact, n / 10);
  const bool ok = rc::check("float_exact agrees with the reference", [](const gen::GenCase& g, int scale) {
    const float k = std::ldexp(1.0f, *rc::gen::inRange(-140, 110));
    auto scaled = [&](Volume v) {
      std::visit([&](auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) x *= k;
        else if constexpr (std::is_same_v<T, Sphere>) x.center *= k, x.radius *= k;
        else if constexpr (std::is_same_v<T, Aabb>) x.min *= k, x.max *= k;
        else x.center *= k, x.half *= k;
      }, v);
      return v;
    };
    RC_ASSERT(float_exact(g.frustum, g.volume) == reference::reference_float_exact(g.frustum, g.volume));
    const Volume v = scale % 2 ? scaled(g.volume) : g.volume;
    try {
      validate(v, "volume");  // no coordinate scaled past the largest float
    } catch (const ValidationError&) {
      return;
    }
    RC_ASSERT(float_exact(g.frustum, v) == reference::reference_float_exact(g.frustum, v));
  });
  EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace cullproof

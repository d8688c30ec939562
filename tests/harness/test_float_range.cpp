// The whole float range: the huge and subnormal families reach what they are for, measured on
// the campaign's own draws (seed 1). Each fraction is printed; each must be reached often
// enough to be exercised by every run:
//  - huge: the float evaluations a culler makes overflow: max - min of a box, min + max (its
//    centre) or an OBB's corners, n.x + d at a vertex, and the Gribb-Hartmann row sums of a clip
//    matrix;
//  - subnormal: plane coefficients, matrix entries and extents are subnormal, distances to a
//    face are, and the products n_i x_i of a plane test underflow.
// And the extraction a culler is given stays finite where the row sums overflow, the oracle agrees
// with the independent exact method there, and the test helper leaves huge out by default.
#include "cullproof/gen/generators.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <type_traits>
#include <variant>
#include <vector>

using namespace cullproof;

namespace {

constexpr int kCases = 2000;
constexpr double kMin = double(std::numeric_limits<float>::min());  // 2^-126

bool finite(float x) { return std::isfinite(x); }
bool finite(const glm::vec3& v) { return finite(v.x) && finite(v.y) && finite(v.z); }
bool subnormal(double x) { return x != 0.0 && std::abs(x) < kMin; }

// The points a plane test evaluates: a point, a sphere's centre, a box's corners (an OBB's from
// its float centre, axes and half-extents, as a culler computes them; a corner that overflows is
// left out, it is counted apart).
std::vector<glm::vec3> vertices(const Volume& v, bool& corner_overflow) {
  std::vector<glm::vec3> out;
  corner_overflow = false;
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) {
          out.push_back(x);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          out.push_back(x.center);
        } else if constexpr (std::is_same_v<T, Aabb>) {
          for (int i = 0; i < 8; ++i)
            out.emplace_back((i & 1) ? x.max.x : x.min.x, (i & 2) ? x.max.y : x.min.y, (i & 4) ? x.max.z : x.min.z);
        } else {
          for (int i = 0; i < 8; ++i) {
            glm::vec3 c = x.center;
            for (int a = 0; a < 3; ++a) c += (((i >> a) & 1) ? x.half[a] : -x.half[a]) * x.axes[a];
            if (finite(c)) out.push_back(c);
            else corner_overflow = true;
          }
        }
      },
      v);
  return out;
}

struct Tally {
  int cases = 0, of_kind = 0, matrices = 0;
  int counted[8] = {};
  void add(int k, bool b) { counted[k] += b; }
  double rate(int k, int of) const { return of ? double(counted[k]) / double(of) : 0.0; }
};

void print(const char* family, const char* what, double rate) {
  std::printf("[%s] %-58s %5.1f%%\n", family, what, 100.0 * rate);
}

}  // namespace

TEST(FloatRange, HugeOverflowsWhatItIsFor) {
  enum { kAny, kExtent, kCentre, kPlaneSum, kRowSum };
  Tally t;
  int boxes = 0, volumes_with_centre = 0;
  for (int i = 0; i < kCases; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::huge, 1, std::uint64_t(i));
    ASSERT_TRUE(is_valid(g.volume)) << i;
    ASSERT_TRUE(is_valid(g.frustum.planes)) << "case " << i << ": the planes a culler is given are finite";
    ++t.cases;
    bool extent = false, centre = false, plane_sum = false, row_sum = false;
    if (const Aabb* b = std::get_if<Aabb>(&g.volume)) {
      ++boxes;
      extent = !finite(b->max - b->min);
      centre = !finite(b->min + b->max);
    }
    bool corner_overflow = false;
    const std::vector<glm::vec3> at = vertices(g.volume, corner_overflow);
    if (const Sphere* s = std::get_if<Sphere>(&g.volume)) centre = !finite(s->center + s->radius) || !finite(s->center - s->radius);
    if (std::holds_alternative<Obb>(g.volume)) centre = corner_overflow;
    volumes_with_centre += !std::holds_alternative<Point>(g.volume);
    for (const Plane& p : g.frustum.planes.planes)
      for (const glm::vec3& x : at) plane_sum = plane_sum || !std::isfinite(p.eval(x));
    if (g.frustum.matrix) {
      ++t.matrices;
      const glm::mat4& m = *g.frustum.matrix;
      const glm::vec4 r4 = matrix_row(m, 3);
      for (int k = 0; k < 3; ++k) {
        const glm::vec4 r = matrix_row(m, k);
        row_sum = row_sum || !finite(glm::vec3(r4 + r)) || !std::isfinite(r4.w + r.w) || !finite(glm::vec3(r4 - r)) ||
                  !std::isfinite(r4.w - r.w);
      }
    }
    t.add(kExtent, extent);
    t.add(kCentre, centre);
    t.add(kPlaneSum, plane_sum);
    t.add(kRowSum, row_sum);
    t.add(kAny, extent || centre || plane_sum || row_sum);
  }
  print("huge", "some float evaluation overflows", t.rate(kAny, t.cases));
  print("huge", "AABB max - min overflows (of AABB cases)", t.rate(kExtent, boxes));
  print("huge", "centre or corner overflows (of AABB, sphere, OBB cases)", t.rate(kCentre, volumes_with_centre));
  print("huge", "n.x + d at a vertex overflows", t.rate(kPlaneSum, t.cases));
  print("huge", "a Gribb-Hartmann row sum overflows (of matrix cases)", t.rate(kRowSum, t.matrices));
  EXPECT_GE(t.rate(kAny, t.cases), 0.5);
  EXPECT_GE(t.rate(kExtent, boxes), 0.05);
  EXPECT_GE(t.rate(kCentre, volumes_with_centre), 0.05);
  EXPECT_GE(t.rate(kPlaneSum, t.cases), 0.2);
  EXPECT_GE(t.rate(kRowSum, t.matrices), 0.2);
  EXPECT_GE(t.matrices, kCases / 10);
}

TEST(FloatRange, SubnormalUnderflowsWhatItIsFor) {
  enum { kAny, kCoefficient, kExtent, kDistance, kProduct };
  Tally t;
  for (int i = 0; i < kCases; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::subnormal, 1, std::uint64_t(i));
    ASSERT_TRUE(is_valid(g.volume)) << i;
    ASSERT_TRUE(is_valid(g.frustum.planes)) << i;
    ++t.cases;
    bool coefficient = false, extent = false, distance = false, product = false;
    for (const Plane& p : g.frustum.planes.planes)
      for (float c : {p.n.x, p.n.y, p.n.z, p.d}) coefficient = coefficient || subnormal(c);
    if (g.frustum.matrix)
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) coefficient = coefficient || subnormal((*g.frustum.matrix)[c][r]);
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, Sphere>) {
            extent = subnormal(x.radius);
          } else if constexpr (std::is_same_v<T, Aabb>) {
            for (int a = 0; a < 3; ++a) extent = extent || subnormal(double(x.max[a]) - double(x.min[a]));
          } else if constexpr (std::is_same_v<T, Obb>) {
            for (int a = 0; a < 3; ++a) extent = extent || subnormal(x.half[a]);
          }
        },
        g.volume);
    bool unused = false;
    for (const Plane& p : g.frustum.planes.planes) {
      if (p.is_degenerate()) continue;
      const glm::dvec3 n(p.n);
      for (const glm::vec3& x : vertices(g.volume, unused)) {
        // Products of two floats are exact in double: one that is not 0 but below 2^-126
        // underflows in float.
        for (int k = 0; k < 3; ++k) product = product || subnormal(n[k] * double(x[k]));
        distance = distance || subnormal((glm::dot(n, glm::dvec3(x)) + double(p.d)) / glm::length(n));
      }
    }
    t.add(kCoefficient, coefficient);
    t.add(kExtent, extent);
    t.add(kDistance, distance);
    t.add(kProduct, product);
    t.add(kAny, coefficient || extent || distance || product);
  }
  print("subnormal", "some coefficient, extent, distance or product is subnormal", t.rate(kAny, t.cases));
  print("subnormal", "a plane coefficient or matrix entry is subnormal", t.rate(kCoefficient, t.cases));
  print("subnormal", "an extent (max - min, radius, half-extent) is subnormal", t.rate(kExtent, t.cases));
  print("subnormal", "a vertex lies at a subnormal distance from a face plane", t.rate(kDistance, t.cases));
  print("subnormal", "a product n_i x_i of a plane test underflows", t.rate(kProduct, t.cases));
  EXPECT_GE(t.rate(kAny, t.cases), 0.8);
  EXPECT_GE(t.rate(kCoefficient, t.cases), 0.2);
  EXPECT_GE(t.rate(kExtent, t.cases), 0.2);
  EXPECT_GE(t.rate(kDistance, t.cases), 0.2);
  EXPECT_GE(t.rate(kProduct, t.cases), 0.5);
}

TEST(FloatRange, ExtractionStaysFiniteWhereTheRowSumsOverflow) {
  // A perspective projection with a translation near FLT_MAX: the side planes' row sums
  // r4 +- rk overflow float in d. Each comes out halved (the same half-space), and exactly
  // half, since every entry is a normal float and the halves' sums are floats here.
  glm::mat4 m(0.0f);
  m[0][0] = 1.0f, m[1][1] = 1.0f, m[2][2] = -1.0f, m[2][3] = -1.0f;
  m[3][3] = 0x1p127f, m[3][0] = 0x1.8p127f, m[3][1] = -0x1.8p127f, m[3][2] = -0x1p126f;
  ASSERT_FALSE(std::isfinite(matrix_row(m, 3).w + matrix_row(m, 0).w)) << "the left row sum overflows";
  const Frustum f = frustum_from_matrix(m, {});
  EXPECT_TRUE(is_valid(f)) << "every plane finite";
  const glm::vec4 r4 = matrix_row(m, 3);
  for (int k = 0; k < 4; ++k) {
    const glm::vec4 rk = matrix_row(m, k / 2);
    EXPECT_TRUE(gribb_hartmann_halves(r4, rk)) << plane_name(k);
    const double sign = (k % 2) ? -1.0 : 1.0;
    for (int c = 0; c < 4; ++c) {
      const double got = c < 3 ? double(f[k].n[c]) : double(f[k].d);
      EXPECT_EQ(got, (double(r4[c]) + sign * double(rk[c])) * 0.5) << plane_name(k) << " coefficient " << c;
    }
  }
  // The near plane's rows stay below FLT_MAX: extracted as it always was.
  EXPECT_FALSE(gribb_hartmann_halves(r4, matrix_row(m, 2)));
  EXPECT_EQ(f[kNear].d, r4.w + matrix_row(m, 2).w);
}

TEST(FloatRange, TheOracleAgreesWithTheIndependentMethod) {
  // The oracle is rational: the ends of the float range are exact for it too. Its truth (and its
  // self-checked certificate) against the independent exact method, which shares no code with it,
  // on 300 cases of each family; its distance is a number (no NaN from a double that overflowed).
  for (gen::Distribution d : {gen::Distribution::huge, gen::Distribution::subnormal})
    for (int i = 0; i < 300; ++i) {
      const gen::GenCase g = gen::draw_case(d, 1, std::uint64_t(i));
      const oracle::Result r = oracle::classify(g.frustum, g.volume);
      EXPECT_EQ(r.truth, oracle::classify_independent(g.frustum, g.volume)) << gen::to_string(d) << " case " << i;
      EXPECT_FALSE(std::isnan(r.distance)) << gen::to_string(d) << " case " << i;
    }
}

TEST(FloatRange, TheTestHelperAsksForHugeByName) {
  // The helper's default: every family but huge (cullproof/gtest/gtest.hpp says why), subnormal in it.
  const std::vector<gen::Distribution> all = gen::parse_distributions("all"), def = gen::no_overflow_distributions();
  EXPECT_EQ(def.size() + 1, all.size());
  EXPECT_EQ(std::count(def.begin(), def.end(), gen::Distribution::huge), 0);
  EXPECT_EQ(std::count(def.begin(), def.end(), gen::Distribution::subnormal), 1);
}

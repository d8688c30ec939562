// The emulated arithmetic (src/gpu/arithmetic.cpp) computes what it says, on the device: a fused
// a * b + c equal to std::fma, bit for bit, where contraction is allowed and nowhere else;
// subnormal operands and results flushed; inversesqrt, division, sqrt and length at the farthest
// float their error bound allows, each way; mediump values at 16 bits; half storage rounded to
// nearest even, or outward so that the stored volume contains the case's.
#include "vulkan.hpp"  // the library's private side: compile_glsl, emulate_arithmetic, Pipeline, float_kernel_head

#include <glm/gtc/quaternion.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <random>
#include <string>
#include <vector>

namespace cullproof::gpu {
namespace {

const std::shared_ptr<Device>& device() {
  static const std::shared_ptr<Device> d = open_device();
  return d;
}

std::uint32_t bits(float x) {
  std::uint32_t w;
  std::memcpy(&w, &x, 4);
  return w;
}
float from_bits(std::uint32_t w) {
  float x;
  std::memcpy(&x, &w, 4);
  return x;
}

// `count` invocations of `body` (which reads x[] and writes y[i] for invocation i) under `a`.
std::vector<float> run(const std::string& body, const std::vector<float>& x, std::uint32_t count, const Arithmetic& a) {
  const std::string source = float_kernel_head(64) + R"GLSL(
float f(uint i);
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  y[i] = floatBitsToUint(f(i));
}
)GLSL" + body;
  Pipeline p(device(), emulate_arithmetic(compile_glsl(source, "test shader"), a));
  std::vector<std::uint32_t> in, out;
  for (float v : x) in.push_back(bits(v));
  std::lock_guard<std::mutex> lock(device()->mutex());
  p.dispatch({0.0f, 0.0f, 0.0f, 0.0f}, in, count, out);
  std::vector<float> r;
  for (std::uint32_t i = 0; i < count; ++i) r.push_back(from_bits(out[i]));
  return r;
}

Arithmetic contract() {
  Arithmetic a;
  a.contract = true;
  return a;
}

// Triples whose products and sums round: random, near cancellation, the probe's (1 + 2^-23)(1 - 2^-23) - 1,
// one that rounding twice (to double, then to float) gets wrong, and subnormal, huge and
// signed-zero cases.
std::vector<float> triples(std::size_t n) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-4.0f, 4.0f);
  std::uniform_int_distribution<int> e(-140, 120);
  std::vector<float> x;
  const float eps = std::ldexp(1.0f, -23);
  for (float v : {1.0f + eps, 1.0f - eps, -1.0f, std::ldexp(1.0f, -75), std::ldexp(1.0f, -75), 0.0f, 3.0f, 5.0f, -15.0f,
                  -0.0f, 1.0f, 0.0f, 3e38f, 2.0f, -3e38f})
    x.push_back(v);
  // (64 + 2^-9)(1 - 2^-15) = 64 - 2^-24; + (2^30 + 128), whose last bit is odd: just below the
  // midpoint 2^30 + 192, so 2^30 + 128; a double sum rounds to the midpoint, and then to even.
  x.insert(x.end(), {64.0f + std::ldexp(1.0f, -9), 1.0f - std::ldexp(1.0f, -15), std::ldexp(1.0f, 30) + 128.0f});
  while (x.size() < 3 * n) {
    const float a = std::ldexp(u(rng), e(rng) / 2), b = std::ldexp(u(rng), e(rng) / 2);
    const float c = (rng() % 2) ? -float(double(a) * double(b)) * (1.0f + u(rng) * 1e-6f) : std::ldexp(u(rng), e(rng));
    x.insert(x.end(), {a, b, c});
  }
  return x;
}

TEST(EmulatedArithmetic, ContractionFusesExactlyAsFmaWhereAllowed) {
  const std::size_t n = 20000;
  const std::vector<float> x = triples(n);
  const std::string body = "float f(uint i) { return x[3u * i] * x[3u * i + 1u] + x[3u * i + 2u]; }\n";
  const std::vector<float> fused = run(body, x, n, contract());
  const std::vector<float> device_only = run(body, x, n, {});
  std::size_t differs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float want = std::fma(x[3 * i], x[3 * i + 1], x[3 * i + 2]);
    ASSERT_EQ(bits(fused[i]), bits(want)) << "fma(" << x[3 * i] << ", " << x[3 * i + 1] << ", " << x[3 * i + 2] << ")";
    differs += bits(device_only[i]) != bits(want);
  }
  EXPECT_EQ(device_only[0], 0.0f);  // rounded twice: the probe's case
  EXPECT_EQ(fused[0], -std::ldexp(1.0f, -46));
  EXPECT_EQ(fused[5], std::ldexp(1.0f, 30) + 128.0f);
  EXPECT_EQ(float(double(x[15]) * double(x[16]) + double(x[17])), std::ldexp(1.0f, 30) + 256.0f);  // rounded twice
  EXPECT_GT(differs, n / 20) << "the triples should tell a fused result from a rounded one";
}

TEST(EmulatedArithmetic, ContractionFusesSubtractionsVectorsDotsAndStoredProducts) {
  const std::size_t n = 4000;
  const std::vector<float> x = triples(n);
  // c - a * b; a product kept in a variable, added in another statement; a vec3 a * s + c; a dot.
  const std::string body = R"GLSL(
float f(uint i) {
  float a = x[3u * i], b = x[3u * i + 1u], c = x[3u * i + 2u];
  uint k = i % 4u;
  if (k == 0u) return c - a * b;
  if (k == 1u) { float m = a * b; float s = m + c; return s; }
  if (k == 2u) return (vec3(a, 1.0, 2.0) * b + vec3(c, 0.0, 0.0)).x;
  return dot(vec2(a, 1.0), vec2(b, c));
}
)GLSL";
  const std::vector<float> r = run(body, x, n, contract());
  for (std::size_t i = 0; i < n; ++i) {
    const float a = x[3 * i], b = x[3 * i + 1], c = x[3 * i + 2];
    const float want = i % 4 == 0 ? std::fma(-a, b, c) : i % 4 == 3 ? std::fma(1.0f, c, a * b) : std::fma(a, b, c);
    ASSERT_EQ(bits(r[i]), bits(want)) << "case " << i % 4 << ": " << a << ", " << b << ", " << c;
  }
}

TEST(EmulatedArithmetic, NoContractionWherePreciseForbidsIt) {
  const std::size_t n = 4000;
  const std::vector<float> x = triples(n);
  const std::string body =
      "float f(uint i) { precise float r = x[3u * i] * x[3u * i + 1u] + x[3u * i + 2u]; return r; }\n";
  const std::vector<float> r = run(body, x, n, contract());
  for (std::size_t i = 0; i < n; ++i) {
    const float want = x[3 * i] * x[3 * i + 1] + x[3 * i + 2];  // -ffp-contract=off: rounded twice
    ASSERT_EQ(bits(r[i]), bits(want));
  }
}

TEST(EmulatedArithmetic, FlushingFlushesSubnormalOperandsAndResults) {
  Arithmetic a;
  a.flush = true;
  const float tiny = std::ldexp(1.0f, -140), small = std::ldexp(1.0f, -70);
  const std::vector<float> x{tiny, 1.0f, small, -tiny, 2.0f};
  const std::string body = R"GLSL(
float f(uint i) {
  if (i == 0u) return x[0] * x[1];                  // a subnormal operand: 0
  if (i == 1u) return x[2] * x[2];                  // a subnormal result: 0
  if (i == 2u) return x[3] < 0.0 ? 1.0 : 0.0;       // compared as -0: not below zero
  if (i == 3u) return x[3] + x[4];                  // 2
  return x[2] * x[1];                               // a normal product: kept
}
)GLSL";
  const std::vector<float> flushed = run(body, x, 5, a), kept = run(body, x, 5, {});
  EXPECT_EQ(flushed[0], 0.0f);
  EXPECT_EQ(flushed[1], 0.0f);
  EXPECT_EQ(flushed[2], 0.0f);
  EXPECT_EQ(flushed[3], 2.0f);
  EXPECT_EQ(flushed[4], small);
  EXPECT_EQ(kept[0], tiny);  // lavapipe keeps subnormals (what the variant exists to go beyond)
  EXPECT_EQ(kept[1], std::ldexp(1.0f, -140));
  EXPECT_EQ(kept[2], 1.0f);
}

// ulp(x) as the Vulkan specification defines it, for a positive x in float range.
long double ulp(long double x) {
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  if (x == std::ldexp(0.5L, e)) e -= 1;  // a power of two: the spacing below it
  return std::ldexp(1.0L, std::max(e - 24, -149));
}

TEST(EmulatedArithmetic, ErrorBoundsGiveTheFarthestFloatAllowedEachWay) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.5f, 1.0f);
  std::uniform_int_distribution<int> e(-100, 100);
  std::vector<float> x;
  for (float v : {1.0f, 4.0f, 0.25f, 2.0f, 3.0f}) x.insert(x.end(), {v, 3.0f});
  while (x.size() < 2 * 3000) x.insert(x.end(), {std::ldexp(u(rng), e(rng)), std::ldexp(u(rng), e(rng) / 2)});
  const std::uint32_t n = std::uint32_t(x.size() / 2);
  const std::string body = R"GLSL(
float f(uint i) {
  float a = x[2u * (i / 4u)], b = x[2u * (i / 4u) + 1u];
  uint k = i % 4u;
  if (k == 0u) return inversesqrt(a);
  if (k == 1u) return a / b;
  if (k == 2u) return sqrt(a);
  return length(vec2(a, b));
}
)GLSL";
  for (int direction : {-1, +1}) {
    Arithmetic a;
    a.bounds = direction;
    const std::vector<float> r = run(body, x, 4 * n, a);
    for (std::uint32_t i = 0; i < 4 * n; ++i) {
      const long double p = x[2 * (i / 4)], q = x[2 * (i / 4) + 1];
      const int k = int(i % 4);
      // The exact value, and for the inherited bounds the range their formula allows.
      if (k == 0 || k == 1) {
        const long double exact = k == 0 ? 1.0L / std::sqrt(p) : p / q;
        if (exact > std::numeric_limits<float>::max() || exact < std::numeric_limits<float>::min()) continue;  // out of range
        const long double reach = (k == 0 ? 2.0L : 2.5L) * ulp(exact);
        const long double got = r[i];
        ASSERT_LE(std::fabs(got - exact), reach) << "k " << k << " of " << p << ", " << q;
        // The farthest: one step further is out of reach.
        const long double further = std::nextafter(r[i], direction > 0 ? INFINITY : 0.0f);
        ASSERT_GT(std::fabs(further - exact), reach) << "k " << k << " of " << p << ", " << q;
        ASSERT_TRUE(direction > 0 ? got >= exact : got <= exact);
      } else {
        // length's dot product overflows or flushes as the formula it inherits from does: not
        // what is measured here.
        const long double sum = p * p + q * q;
        if (k == 3 && (sum > std::numeric_limits<float>::max() || q * q < std::numeric_limits<float>::min())) continue;
        const long double exact = k == 2 ? std::sqrt(p) : std::sqrt(p * p + q * q);
        ASSERT_TRUE(direction > 0 ? r[i] >= exact * (1 - 1e-7L) : r[i] <= exact * (1 + 1e-7L))
            << "k " << k << " of " << p << ", " << q;
        ASSERT_LE(std::fabs(r[i] - exact) / exact, 6.0L * std::ldexp(1.0L, -23)) << "k " << k;
      }
    }
  }
}

TEST(EmulatedArithmetic, HalfStorageRoundsToNearestEven) {
  EXPECT_EQ(round_to_half(1.0f), 1.0f);
  EXPECT_EQ(round_to_half(1.0f + std::ldexp(1.0f, -11)), 1.0f);                        // a tie: to even
  EXPECT_EQ(round_to_half(1.0f + 3 * std::ldexp(1.0f, -11)), 1.0f + std::ldexp(1.0f, -9));  // a tie: to even
  EXPECT_EQ(round_to_half(1.0f + std::ldexp(1.0f, -11) + std::ldexp(1.0f, -20)), 1.0f + std::ldexp(1.0f, -10));
  EXPECT_EQ(round_to_half(65504.0f), 65504.0f);
  EXPECT_EQ(round_to_half(65519.0f), 65504.0f);
  EXPECT_EQ(round_to_half(65520.0f), INFINITY);
  EXPECT_EQ(round_to_half(-std::ldexp(1.0f, -25)), -0.0f);                   // half the least subnormal: to even, 0
  EXPECT_EQ(round_to_half(std::ldexp(3.0f, -26)), std::ldexp(1.0f, -24));    // 0.75 of it: up
  EXPECT_EQ(round_to_half(0.1f), 0.0999755859375f);
}

TEST(EmulatedArithmetic, RelaxedPrecisionComputesMediumpAtSixteenBits) {
  // mediump: what is stored in a relaxed variable is quantized to half precision, and so is each
  // relaxed operation's result (its operands already are); a highp product beside it is untouched.
  const std::size_t n = 20000;
  const std::vector<float> x = triples(n);
  Arithmetic relaxed;
  relaxed.relaxed = true;
  const std::string mediump = R"GLSL(
float f(uint i) {
  mediump float a = x[3u * i], b = x[3u * i + 1u], c = x[3u * i + 2u];
  mediump float r = a * b + c;
  return r;
}
)GLSL";
  const std::string highp = "float f(uint i) { return x[3u * i] * x[3u * i + 1u] + x[3u * i + 2u]; }\n";
  const std::vector<float> sixteen = run(mediump, x, n, relaxed), on_device = run(mediump, x, n, {});
  const std::vector<float> untouched = run(highp, x, n, relaxed);
  std::size_t differs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float a = round_to_half(x[3 * i]), b = round_to_half(x[3 * i + 1]), c = round_to_half(x[3 * i + 2]);
    const float want = round_to_half(round_to_half(a * b) + c);
    ASSERT_EQ(bits(sixteen[i]), bits(want)) << x[3 * i] << " * " << x[3 * i + 1] << " + " << x[3 * i + 2];
    ASSERT_EQ(bits(untouched[i]), bits(x[3 * i] * x[3 * i + 1] + x[3 * i + 2])) << i;
    differs += bits(on_device[i]) != bits(want);
  }
  EXPECT_GT(differs, n / 2) << "lavapipe computes mediump at 32 bits: the variant must change it";
}

// A binary16 value (or an infinity): at most 65504 in magnitude, a multiple of its binade's spacing
// (11 significant bits; 2^-24 below 2^-14).
bool is_half(double h) {
  if (std::isinf(h) || h == 0.0) return true;
  if (std::fabs(h) > 65504.0) return false;
  int e = 0;
  std::frexp(h, &e);
  const double units = std::ldexp(h, -std::max(e - 11, -24));
  return units == std::trunc(units);
}

// The spacing of the halves in the binade of h (finite, not 0).
double half_spacing(double h) {
  int e = 0;
  std::frexp(h, &e);
  return std::ldexp(1.0, std::max(e - 11, -24));
}

TEST(EmulatedArithmetic, HalfStorageRoundsDownAndUpToTheHalvesAroundAValue) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int> exponent(-30, 18);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  for (int i = 0; i < 200000; ++i) {
    float x = float(std::ldexp(mantissa(rng), exponent(rng))) * ((rng() & 1) ? -1.0f : 1.0f);
    if (i % 8 == 0) x = round_to_half(x);  // halves themselves, infinities among them
    if (std::isinf(x)) continue;
    const double down = round_to_half(double(x), -1), up = round_to_half(double(x), +1), nearest = round_to_half(double(x), 0);
    ASSERT_TRUE(is_half(down) && is_half(up)) << x;
    ASSERT_TRUE(down <= x && x <= up) << x << ": " << down << ", " << up;
    ASSERT_TRUE(nearest == down || nearest == up) << x;
    ASSERT_EQ(nearest, double(round_to_half(x))) << x;
    if (is_half(x)) {
      ASSERT_TRUE(down == x && up == x) << x;
    } else if (std::isfinite(down) && std::isfinite(up)) {
      ASSERT_LE(up - down, half_spacing(std::max(std::fabs(down), std::fabs(up)))) << x;  // no half between
    } else {
      ASSERT_GT(std::fabs(x), 65504.0f) << x;
      ASSERT_EQ(x > 0 ? down : up, std::copysign(65504.0, x)) << x;
    }
  }
  EXPECT_EQ(round_to_half(70000.0, -1), 65504.0);
  EXPECT_EQ(round_to_half(70000.0, +1), INFINITY);
  EXPECT_EQ(round_to_half(-70000.0, -1), -INFINITY);
  EXPECT_EQ(round_to_half(-70000.0, +1), -65504.0);
  EXPECT_EQ(round_to_half(1e-10, +1), std::ldexp(1.0, -24));
  EXPECT_EQ(round_to_half(1e-10, -1), 0.0);
  EXPECT_EQ(round_to_half(1.0 + std::ldexp(1.0, -20), +1), 1.0 + std::ldexp(1.0, -10));
}

// Random volumes at magnitudes from 2^-30 to 2^18 (beyond the halves' range, 65504, at the top).
struct RandomVolumes {
  std::mt19937_64 rng{12};
  float coordinate(int lo = -30, int hi = 18) {
    const int e = std::uniform_int_distribution<int>(lo, hi)(rng);
    return float(std::ldexp(std::uniform_real_distribution<double>(-2.0, 2.0)(rng), e));
  }
  glm::vec3 point(int lo = -30, int hi = 18) { return {coordinate(lo, hi), coordinate(lo, hi), coordinate(lo, hi)}; }
  glm::mat3 rotation() {
    std::normal_distribution<float> g;
    const glm::quat q = glm::normalize(glm::quat(g(rng), g(rng), g(rng), g(rng)));
    return glm::mat3_cast(q);
  }
};

TEST(EmulatedArithmetic, HalfOutwardStorageContainsTheVolumeAndGrowsItLittle) {
  RandomVolumes r;
  const auto absolute = [](const glm::vec3& v) { return std::fabs(v.x) + std::fabs(v.y) + std::fabs(v.z); };
  for (int i = 0; i < 20000; ++i) {
    // A sphere: the stored one holds the case's, by its centre's move and radius in long double.
    const Sphere s{r.point(), std::fabs(r.coordinate())};
    const Sphere t = std::get<Sphere>(stored_volume(s, HalfStorage::outward));
    long double moved = 0;
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(is_half(t.center[k]) && std::isfinite(t.center[k])) << t.center[k];
      moved += (static_cast<long double>(s.center[k]) - t.center[k]) * (static_cast<long double>(s.center[k]) - t.center[k]);
    }
    ASSERT_TRUE(is_half(t.radius)) << t.radius;
    ASSERT_GE(static_cast<long double>(t.radius), std::sqrt(moved) + s.radius) << i;
    if (absolute(s.center) + s.radius < 1000.0f) {
      ASSERT_LE(t.radius, s.radius + std::ldexp(1.0f, -9) * (absolute(s.center) + s.radius) + std::ldexp(1.0f, -23)) << i;
    }

    // A box: its bounds rounded down and up.
    glm::vec3 lo = r.point(), hi = lo;
    for (int k = 0; k < 3; ++k) hi[k] = lo[k] + std::fabs(r.coordinate());
    const Aabb b = std::get<Aabb>(stored_volume(Aabb{lo, hi}, HalfStorage::outward));
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(is_half(b.min[k]) && is_half(b.max[k]));
      ASSERT_TRUE(b.min[k] <= lo[k] && hi[k] <= b.max[k]) << i;
    }

    // An OBB: every corner of the case's, in the stored axes' coordinates (long double, Cramer's
    // rule), lies within the stored half extents.
    const Obb o{r.point(), r.rotation(), glm::abs(r.point(-20, 12))};
    const Obb u = std::get<Obb>(stored_volume(o, HalfStorage::outward));
    using L = long double;
    const auto at = [&](int row, int col) { return static_cast<L>(u.axes[col][row]); };
    const auto det3 = [](const L m[3][3]) {
      return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
             m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    for (int k = 0; k < 3; ++k) {
      ASSERT_TRUE(is_half(u.half[k]) && is_half(u.center[k])) << i;
      for (int j = 0; j < 3; ++j) ASSERT_TRUE(is_half(u.axes[k][j])) << i;
    }
    L m[3][3];
    for (int row = 0; row < 3; ++row)
      for (int col = 0; col < 3; ++col) m[row][col] = at(row, col);
    const L det = det3(m);
    ASSERT_NE(det, 0.0L);
    for (int corner = 0; corner < 8; ++corner) {
      L x[3];
      for (int row = 0; row < 3; ++row) {
        x[row] = static_cast<L>(o.center[row]) - u.center[row];
        for (int k = 0; k < 3; ++k)
          x[row] += ((corner >> k) & 1 ? 1 : -1) * static_cast<L>(o.half[k]) * static_cast<L>(o.axes[k][row]);
      }
      for (int k = 0; k < 3; ++k) {
        L n[3][3];
        for (int row = 0; row < 3; ++row)
          for (int col = 0; col < 3; ++col) n[row][col] = col == k ? x[row] : m[row][col];
        const L along = det3(n) / det;
        ASSERT_LE(std::fabs(along), static_cast<L>(u.half[k]) * (1 + 1e-15L)) << "obb " << i << ", corner " << corner << ", axis " << k;
      }
    }
    if (absolute(o.center) + absolute(o.half) < 1000.0f) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_LE(u.half[k], o.half[k] + std::ldexp(1.0f, -7) * (absolute(o.center) + absolute(o.half)) + std::ldexp(1.0f, -23))
            << i;
      }
    }
  }
  // Exact halves are stored as they are; a point cannot be stored outward.
  const Sphere exact{glm::vec3(1.0f, -2.0f, 0.5f), 3.0f};
  EXPECT_EQ(std::get<Sphere>(stored_volume(exact, HalfStorage::outward)).radius, 3.0f);
  EXPECT_THROW(stored_volume(Point(1.0f, 2.0f, 3.0f), HalfStorage::outward), std::invalid_argument);
  // To nearest, every float is rounded alone: a sphere may lose what its rounding moved.
  const Sphere near = std::get<Sphere>(stored_volume(Sphere{glm::vec3(0.1f), 0.1f}, HalfStorage::nearest));
  EXPECT_EQ(near.radius, round_to_half(0.1f));
  EXPECT_EQ(near.center.x, round_to_half(0.1f));
}

TEST(EmulatedArithmetic, VariantsAreNamedAndParsedBack) {
  for (const Arithmetic& a : all_arithmetic()) EXPECT_EQ(parse_arithmetic(to_string(a)), a) << to_string(a);
  EXPECT_EQ(to_string(parse_arithmetic("half+contract")), "contract+half");
  EXPECT_THROW(parse_arithmetic("fused"), std::invalid_argument);
  EXPECT_THROW(parse_arithmetic("bounds-low+bounds-high"), std::invalid_argument);
  EXPECT_THROW(parse_arithmetic("half+half-outward"), std::invalid_argument);
  EXPECT_EQ(to_string(parse_arithmetic("half-outward+flush")), "flush+half-outward");
  EXPECT_EQ(to_string(parse_arithmetic("half+relaxed")), "relaxed+half");
  EXPECT_THROW(parse_arithmetic(""), std::invalid_argument);
}

}  // namespace
}  // namespace cullproof::gpu

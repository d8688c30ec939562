// Float-exactness of a case (see gen::float_exact in cullproof/gen/generators.hpp).
//
// Every quantity is a sum of terms that are floats or products of two floats. A product of two
// floats is exact in double (48 significant bits, exponents from -298 to 256), and a sum of
// doubles is held exactly as a nonoverlapping expansion (Shewchuk's Two-Sum and Grow-Expansion),
// so every question is answered in double arithmetic without rounding: a sum is a float when the
// float nearest its estimate, subtracted from it exactly, leaves zero.
//
// Source: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust Geometric
// Predicates", Discrete & Computational Geometry 18, 1997, §2 (Two-Sum, Grow-Expansion).
#include "cullproof/gen/generators.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <variant>

namespace cullproof::gen {

namespace {

// An exact sum of up to kMax doubles: nonoverlapping components, zeros dropped (Grow-Expansion
// never needs more components than terms added).
class Sum {
 public:
  static constexpr int kMax = 8;
  Sum() = default;
  Sum(std::initializer_list<double> terms) {
    for (double t : terms) add(t);
  }
  void add(double b) {
    double q = b;
    int k = 0;
    for (int i = 0; i < n_; ++i) {
      const double s = q + c_[i];
      const double bv = s - q;
      const double err = (q - (s - bv)) + (c_[i] - bv);  // Two-Sum: q + c_i = s + err exactly
      if (err != 0.0) c_[k++] = err;
      q = s;
    }
    if (q != 0.0) c_[k++] = q;
    n_ = k;
  }
  void add(const Sum& o) {
    for (int i = 0; i < o.n_; ++i) add(o.c_[i]);
  }
  Sum negated() const {
    Sum r = *this;
    for (int i = 0; i < r.n_; ++i) r.c_[i] = -r.c_[i];
    return r;
  }
  bool is_zero() const { return n_ == 0; }
  // Whether the exact value is a finite float: the float nearest the estimate (the components
  // summed, smallest first, within a few units in the last place of double of the value) is the
  // value itself when the value is a float.
  bool is_float() const {
    if (n_ == 0) return true;
    double estimate = 0.0;
    for (int i = 0; i < n_; ++i) estimate += c_[i];
    const float f = static_cast<float>(estimate);
    if (!std::isfinite(f)) return false;
    Sum rest = *this;
    rest.add(-static_cast<double>(f));
    return rest.is_zero();
  }
  // The value, when it is a float (is_float()).
  float as_float() const {
    double estimate = 0.0;
    for (int i = 0; i < n_; ++i) estimate += c_[i];
    return static_cast<float>(estimate);
  }

 private:
  std::array<double, kMax> c_{};
  int n_ = 0;
};

// The product of two floats, exact in double.
double product(float a, float b) { return double(a) * double(b); }

// Whether a double (exactly a float or a product of two) is a finite float.
bool is_float(double x) { return double(static_cast<float>(x)) == x; }

// A sufficient test for sums_are_floats, without a sum: every term an integer multiple of 2^low
// (the least of their lowest set bits; low >= -149, a float's least unit) and their magnitudes
// summing to less than 2^(low + 24) and to no more than the largest float. Every sum of some of
// them is then a multiple of 2^low below 2^24 such units: a float. False says nothing.
template <std::size_t N>
bool sums_fit_a_float(const std::array<double, N>& terms) {
  int low = std::numeric_limits<int>::max();
  double total = 0.0;
  for (const double x : terms) {
    if (x == 0.0) continue;
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const int e = int((bits >> 52) & 0x7ff);
    if (e == 0 || e == 0x7ff) return false;  // a subnormal double or not finite: the full test decides
    const std::uint64_t mantissa = (bits & ((std::uint64_t(1) << 52) - 1)) | (std::uint64_t(1) << 52);
    low = std::min(low, e - 1075 + __builtin_ctzll(mantissa));
    total += std::fabs(x);
  }
  if (low == std::numeric_limits<int>::max()) return true;  // every term zero
  if (low < -149) return false;
  // `total` may round below the magnitudes' true sum, by far less than this margin.
  const double bound = total * (1.0 + 0x1p-40);
  if (!(bound <= double(std::numeric_limits<float>::max()))) return false;
  if (low + 24 > 128) return true;  // 2^(low + 24) is past the largest float, which bounds the sum
  const std::uint64_t limit_bits = std::uint64_t(low + 24 + 1023) << 52;  // 2^(low + 24), a normal double
  double limit;
  std::memcpy(&limit, &limit_bits, sizeof limit);
  return bound < limit;
}

// Whether every sum of two or more of the terms (each already a float) is a float: every partial
// sum of any evaluation order is one of these.
template <std::size_t N>
bool sums_are_floats(const std::array<double, N>& terms) {
  if (sums_fit_a_float(terms)) return true;
  for (std::uint32_t mask = 1; mask < (1u << N); ++mask) {
    if ((mask & (mask - 1)) == 0) continue;  // a single term
    Sum s;
    for (std::size_t i = 0; i < N; ++i)
      if (mask & (1u << i)) s.add(terms[i]);
    if (!s.is_float()) return false;
  }
  return true;
}

// The terms of n.x + d, or false when a product n_i x_i is not a float.
bool plane_terms(const Plane& p, const glm::vec3& x, std::array<double, 4>& out) {
  for (int i = 0; i < 3; ++i) {
    out[std::size_t(i)] = product(p.n[i], x[i]);
    if (!is_float(out[std::size_t(i)])) return false;
  }
  out[3] = double(p.d);
  return true;
}

bool plane_exact_at(const Plane& p, const glm::vec3& x) {
  std::array<double, 4> t;
  return plane_terms(p, x, t) && sums_are_floats(t);
}

bool unit_normal(const Plane& p) {
  Sum s{product(p.n[0], p.n[0]), product(p.n[1], p.n[1]), product(p.n[2], p.n[2]), -1.0};
  return s.is_zero();
}

// n . u for a plane normal and an OBB axis, if it rounds nothing.
bool exact_dot(const glm::vec3& n, const glm::vec3& u, float& out) {
  std::array<double, 3> t;
  for (int i = 0; i < 3; ++i) {
    t[std::size_t(i)] = product(n[i], u[i]);
    if (!is_float(t[std::size_t(i)])) return false;
  }
  if (!sums_are_floats(t)) return false;
  out = Sum{t[0], t[1], t[2]}.as_float();
  return true;
}

bool obb_exact(const std::array<Plane, kPlaneCount>& planes, const Obb& b) {
  // The corners c + sum_i (+-h_i) u_i, coordinate by coordinate.
  std::array<std::array<double, 3>, 3> hu{};  // hu[i][k] = h_i * u_ik
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      hu[std::size_t(i)][std::size_t(k)] = product(b.half[i], b.axes[i][k]);
      if (!is_float(hu[std::size_t(i)][std::size_t(k)])) return false;
    }
  for (int corner = 0; corner < 8; ++corner) {
    glm::vec3 x;
    for (int k = 0; k < 3; ++k) {
      std::array<double, 4> t{double(b.center[k]), 0, 0, 0};
      for (int i = 0; i < 3; ++i) {
        const double h = hu[std::size_t(i)][std::size_t(k)];
        t[std::size_t(i + 1)] = (corner >> i & 1) ? -h : h;
      }
      if (!sums_are_floats(t)) return false;
      x[k] = Sum{t[0], t[1], t[2], t[3]}.as_float();
    }
    for (const Plane& p : planes)
      if (!plane_exact_at(p, x)) return false;
  }
  // The projected form: s = n.c + d against r = sum_i h_i |n . u_i|.
  for (const Plane& p : planes) {
    std::array<double, 4> centre;
    if (!plane_terms(p, b.center, centre) || !sums_are_floats(centre)) return false;
    std::array<double, 3> r;
    for (int i = 0; i < 3; ++i) {
      float d;
      if (!exact_dot(p.n, b.axes[i], d)) return false;
      r[std::size_t(i)] = product(b.half[i], std::abs(d));
      if (!is_float(r[std::size_t(i)])) return false;
    }
    if (!sums_are_floats(r)) return false;
    const Sum s{centre[0], centre[1], centre[2], centre[3]};
    const Sum rr{r[0], r[1], r[2]};
    Sum minus = s, plus = s;
    minus.add(rr.negated());
    plus.add(rr);
    if (!minus.is_float() || !plus.is_float()) return false;
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
    const double r4 = m[c][3];
    for (int r = 0; r < 3; ++r) {
      const double rk = m[c][r];
      if (!Sum{r4, -rk}.is_float()) return false;
      const bool plus_used = r < 2 || f.depth.range == DepthRange::negative_one_to_one;
      if (plus_used && !Sum{r4, rk}.is_float()) return false;
    }
  }
  return true;
}

}  // namespace

bool float_exact(const CaseFrustum& f, const Volume& v) {
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
            std::array<double, 4> t;
            if (!plane_terms(p, x.center, t)) return false;
            const std::array<double, 5> with_radius{t[0], t[1], t[2], t[3], double(x.radius)};
            if (!sums_are_floats(with_radius)) return false;
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

}  // namespace cullproof::gen

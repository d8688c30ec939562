// Float-exactness of a case (see gen::float_exact in cullproof/gen/generators.hpp).
//
// Every quantity is a sum of terms that are floats or products of two floats, so it is a dyadic
// rational m * 2^e with e >= -298 (the product of two smallest subnormals): it is held exactly as
// an integer multiple of 2^kLowest in a Boost.Multiprecision integer, and "is a float" is decided
// on that integer (at most 24 significant bits, lowest bit at or above 2^-149, below 2^128).
#include "cullproof/gen/generators.hpp"

#include <boost/multiprecision/cpp_int.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <variant>
#include <vector>

namespace cullproof::gen {

namespace {

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

}  // namespace cullproof::gen

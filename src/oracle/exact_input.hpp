// Internal (not installed): the case geometry as exact numbers of any field type T, built from
// the float values without rounding. Shared by the oracle's exact route and its interval filter;
// the independent method (independent.cpp) deliberately does not use it.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <array>
#include <cmath>
#include <string>
#include <variant>

namespace cullproof::oracle::detail {

/// Four plane coefficients (a, b, c, d): inside when a x + b y + c z + d >= 0.
template <class T>
using Coeffs = std::array<T, 4>;

/// The six planes of f in the plane order of docs/semantics.md, exactly: as given, or Gribb–Hartmann row sums of
/// the float matrix entries formed in T (exact when T is an exact type; an enclosure when T is
/// an interval type). `conv` maps a float to T losslessly.
template <class T, class Conv>
std::array<Coeffs<T>, 6> exact_planes(const CaseFrustum& f, Conv conv) {
  std::array<Coeffs<T>, 6> out;
  if (!f.matrix) {
    for (int j = 0; j < 6; ++j) {
      const Plane& p = f.planes[j];
      out[static_cast<std::size_t>(j)] = Coeffs<T>{conv(p.n.x), conv(p.n.y), conv(p.n.z), conv(p.d)};
    }
    return out;
  }
  const glm::mat4& m = *f.matrix;
  // Row i of a column-major GLM matrix is (m[0][i], m[1][i], m[2][i], m[3][i]).
  auto row = [&](int i) {
    return Coeffs<T>{conv(m[0][i]), conv(m[1][i]), conv(m[2][i]), conv(m[3][i])};
  };
  auto add = [](const Coeffs<T>& a, const Coeffs<T>& b) {
    return Coeffs<T>{a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]};
  };
  auto sub = [](const Coeffs<T>& a, const Coeffs<T>& b) {
    return Coeffs<T>{a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]};
  };
  const Coeffs<T> r1 = row(0), r2 = row(1), r3 = row(2), r4 = row(3);
  out[kLeft] = add(r4, r1);
  out[kRight] = sub(r4, r1);
  out[kBottom] = add(r4, r2);
  out[kTop] = sub(r4, r2);
  const Coeffs<T> lower = f.depth.range == DepthRange::negative_one_to_one ? add(r4, r3) : r3;
  const Coeffs<T> upper = sub(r4, r3);
  out[kNear] = f.depth.reversed_z ? upper : lower;
  out[kFar] = f.depth.reversed_z ? lower : upper;
  return out;
}

/// A box as a parallelepiped c + Σ t_i e_i, |t_i| <= 1 (e_i = h_i u_i; AABB: c = (min+max)/2,
/// e_i = (max_i - min_i)/2 along axis i; a point has e = 0). Exact in T for dyadic-exact T.
template <class T>
struct BoxT {
  std::array<T, 3> c;
  std::array<std::array<T, 3>, 3> e;  ///< e[i] is the i-th half-edge vector
};

/// The box (or point) v in T. `half` is T(1/2).
template <class T, class Conv>
BoxT<T> exact_box(const Volume& v, Conv conv, const T& half) {
  BoxT<T> b;
  const T zero = conv(0.0f);
  if (const auto* p = std::get_if<Point>(&v)) {
    for (int k = 0; k < 3; ++k) b.c[k] = conv((*p)[k]);
    for (auto& ei : b.e) ei = {zero, zero, zero};
  } else if (const auto* a = std::get_if<Aabb>(&v)) {
    for (int k = 0; k < 3; ++k) {
      b.c[k] = (conv(a->min[k]) + conv(a->max[k])) * half;
      for (int i = 0; i < 3; ++i) b.e[i][k] = i == k ? (conv(a->max[k]) - conv(a->min[k])) * half : zero;
    }
  } else if (const auto* o = std::get_if<Obb>(&v)) {
    for (int k = 0; k < 3; ++k) b.c[k] = conv(o->center[k]);
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) b.e[i][k] = conv(o->half[i]) * conv(o->axes[i][k]);
  }
  return b;
}

/// Validates the case: throws ValidationError naming the field, or the bad matrix entry.
/// (cullproof::validate checks with the cheap is_valid first and builds names only on failure.)
inline void validate_case(const CaseFrustum& f, const Volume& v) {
  if (f.matrix) {
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite((*f.matrix)[c][r]))
          throw ValidationError("frustum.matrix[" + std::to_string(4 * c + r) + "]: not finite");
  } else {
    validate(f.planes, "frustum");
  }
  validate(v, "volume");
}

}  // namespace cullproof::oracle::detail

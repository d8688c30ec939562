// Internal: a frustum as a convex polyhedron (vertices, extreme rays, edges) and OBB helpers
// shared by Hoff's test, the separating-axis test and the reverse test. Float, as a float
// culler holds them; the own tests (hoff-exact, sat-exact, pn-vertex-reverse) run the same
// operations in double where a case's magnitudes leave float's comfortable range (see
// float_range_ok below), so the helpers they use are templates on the number type T.
#pragma once

#include "cullproof/core/exact.hpp"
#include "cullproof/core/geometry.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace cullproof::exact_detail {

template <class T>
using Vec3 = glm::vec<3, T, glm::defaultp>;

/// The frustum's vertices and, when the far plane is "all space", the rays of its lateral edges.
template <class T>
struct FrustumHullT {
  bool empty = false;                      ///< a plane with n == 0, d < 0: nothing is inside
  std::vector<Vec3<T>> vertices;           ///< 8 corners (bounded) or the 4 near corners
  std::vector<Vec3<T>> rays;               ///< lateral edge directions (unbounded; largest component in [0.5, 1), not unit), else empty
  std::vector<std::pair<int, int>> edges;  ///< vertex index pairs (bounded edges)
  std::vector<std::pair<int, int>> ray_edges;  ///< (vertex index, ray index)
  double magnitude = 0.0;                  ///< the largest vertex coordinate magnitude (double, before rounding to T)
};
using FrustumHull = FrustumHullT<float>;

/// Whether the eight corner triples of `f` (double) are the vertices of the polytope: each
/// satisfies every plane to within 1e-6 of the magnitudes involved.
bool has_frustum_topology(const Frustum& f, const std::vector<glm::dvec3>& corners);
/// Vertices/rays of a frustum with frustum topology (left/right x bottom/top x near/far), in T.
/// The far plane may be "all space". nullopt when another plane is degenerate, triples do not
/// meet, or the six planes do not have frustum topology (a computed corner lies outside another
/// plane by more than rounding: e.g. nearly parallel side planes that cross before the far
/// plane, so the polytope's vertices are not the eight corner triples). Instantiated for float
/// and double.
template <class T>
std::optional<FrustumHullT<T>> frustum_hull_as(const Frustum& f);
inline std::optional<FrustumHull> frustum_hull(const Frustum& f) { return frustum_hull_as<float>(f); }

/// Whether float keeps every value of the own exact tests finite and away from underflow for
/// this frustum and box: each plane's largest normal component within [2^-80, 2^80], |d| and
/// that component times the box's magnitude at most 2^100, the box's coordinates and extents at
/// most 2^40, its axes' components within [2^-20, 2^20]. Their largest products are then far
/// inside float's range. The frustum's vertices are checked once built (hull_range_ok). Outside
/// that range the tests run in double, whose range holds every product and quotient of three
/// floats (the largest, 2^384, and the smallest, 2^-447, are within [2^-1022, 2^1023]).
bool float_range_ok(const Frustum& f, const Obb& b) noexcept;
/// The frustum's part of float_range_ok: its vertices' coordinates at most 2^40, each plane's
/// largest normal component times them at most 2^100, and the scene (vertices and box) not all
/// below 2^-40, where the products of two coordinates (edge directions by vertices) would be
/// subnormal.
bool hull_range_ok(const Frustum& f, const Obb& b, double hull_magnitude) noexcept;

/// What a test run in float returns when the frustum's vertices leave float's range: run it again
/// in double.
inline constexpr int kRedo = -1;

/// dot(n, x) + d in T, in Plane::eval's order (((n_x x + n_y y) + n_z z) + d).
template <class T>
T plane_eval(const Plane& p, const Vec3<T>& x) noexcept {
  return T(p.n.x) * x.x + T(p.n.y) * x.y + T(p.n.z) * x.z + T(p.d);
}

template <class T>
Vec3<T> vec_as(const glm::vec3& v) noexcept {
  return Vec3<T>(T(v.x), T(v.y), T(v.z));
}

/// The eight corners of an OBB, index bits: bit k set = +h_k along u_k.
template <class T>
std::array<Vec3<T>, 8> obb_corners_as(const Obb& b) noexcept {
  std::array<Vec3<T>, 8> c;
  const Vec3<T> center = vec_as<T>(b.center), u0 = vec_as<T>(b.axes[0]), u1 = vec_as<T>(b.axes[1]),
                u2 = vec_as<T>(b.axes[2]);
  for (int i = 0; i < 8; ++i) {
    const T s0 = (i & 1) ? T(b.half.x) : -T(b.half.x);
    const T s1 = (i & 2) ? T(b.half.y) : -T(b.half.y);
    const T s2 = (i & 4) ? T(b.half.z) : -T(b.half.z);
    c[static_cast<std::size_t>(i)] = center + s0 * u0 + s1 * u1 + s2 * u2;
  }
  return c;
}
inline std::array<glm::vec3, 8> obb_corners(const Obb& b) noexcept { return obb_corners_as<float>(b); }

/// Half-length of the OBB's projection on `axis` (sum h_i |u_i . axis|).
template <class T>
T obb_radius_as(const Obb& b, const Vec3<T>& axis) noexcept {
  return T(b.half.x) * std::abs(glm::dot(vec_as<T>(b.axes[0]), axis)) +
         T(b.half.y) * std::abs(glm::dot(vec_as<T>(b.axes[1]), axis)) +
         T(b.half.z) * std::abs(glm::dot(vec_as<T>(b.axes[2]), axis));
}
inline float obb_radius(const Obb& b, const glm::vec3& axis) noexcept { return obb_radius_as<float>(b, axis); }

/// Whether all eight OBB corners are inside every plane (evaluation in T, closed).
template <class T>
bool all_corners_inside_as(const Frustum& f, const std::array<Vec3<T>, 8>& corners) noexcept {
  for (const Plane& p : f.planes)
    for (const Vec3<T>& v : corners)
      if (plane_eval(p, v) < T(0)) return false;
  return true;
}
inline bool all_corners_inside(const Frustum& f, const std::array<glm::vec3, 8>& corners) noexcept {
  return all_corners_inside_as<float>(f, corners);
}

}  // namespace cullproof::exact_detail

namespace cullproof::exact_detail {

/// Does the closed segment [a, b] meet the closed face of the OBB on axis k, side s (+1/-1)?
/// Float: the segment is cut with the face plane, the cut point compared with the face's
/// half-extents (closed). A segment lying in the face plane is clipped against the rectangle.
bool segment_hits_obb_face(const glm::vec3& a, const glm::vec3& b, const Obb& box, int k, float s) noexcept;

/// Is p inside the OBB (|(p - c) . u_k| <= h_k for each axis; axes taken as orthonormal)?
bool point_in_obb(const glm::vec3& p, const Obb& box) noexcept;

/// Whether the segment a + t (b - a), t in [0, 1], given in coordinates where the face is the
/// rectangle |x_j| <= h_j, |x_l| <= h_l of its plane, has a point in that rectangle (Liang–Barsky
/// clipping). Used for a segment lying in a face's plane.
template <class T>
bool clip_segment_to_rect_as(T a_j, T d_j, T h_j, T a_l, T d_l, T h_l) noexcept {
  T t0 = T(0), t1 = T(1);
  const T pa[2] = {a_j, a_l}, pd[2] = {d_j, d_l}, h[2] = {h_j, h_l};
  for (int m = 0; m < 2; ++m)
    for (T side : {T(1), T(-1)}) {
      // side * (pa + t pd) <= h
      const T num = h[m] - side * pa[m], den = side * pd[m];
      if (den == T(0)) {
        if (num < T(0)) return false;
      } else if (den > T(0)) {
        t1 = std::min(t1, num / den);
      } else {
        t0 = std::max(t0, num / den);
      }
    }
  return t0 <= t1;
}
inline bool clip_segment_to_rect(float a_j, float d_j, float h_j, float a_l, float d_l, float h_l) noexcept {
  return clip_segment_to_rect_as<float>(a_j, d_j, h_j, a_l, d_l, h_l);
}

/// Does the closed segment [a, b] meet frustum face `face` (the part of plane `face` that
/// satisfies the other five planes)? In T.
template <class T>
bool segment_hits_frustum_face_as(const Vec3<T>& a, const Vec3<T>& b, const Frustum& f, int face) noexcept {
  const Plane& p = f[face];
  const T da = plane_eval(p, a), db = plane_eval(p, b);
  if ((da > T(0) && db > T(0)) || (da < T(0) && db < T(0))) return false;
  auto in_others = [&](const Vec3<T>& x) {
    for (int i = 0; i < kPlaneCount; ++i)
      if (i != face && plane_eval(f[i], x) < T(0)) return false;
    return true;
  };
  if (da == T(0) && db == T(0)) {
    // In the face plane: clip the segment against the other five half-spaces.
    T t0 = T(0), t1 = T(1);
    for (int i = 0; i < kPlaneCount; ++i) {
      if (i == face) continue;
      const T ea = plane_eval(f[i], a), eb = plane_eval(f[i], b);
      if (ea < T(0) && eb < T(0)) return false;
      if (ea < T(0)) t0 = std::max(t0, ea / (ea - eb));
      else if (eb < T(0)) t1 = std::min(t1, ea / (ea - eb));
    }
    return t0 <= t1;
  }
  const T t = da / (da - db);
  return in_others(a + t * (b - a));
}
inline bool segment_hits_frustum_face(const glm::vec3& a, const glm::vec3& b, const Frustum& f, int face) noexcept {
  return segment_hits_frustum_face_as<float>(a, b, f, face);
}

/// Hoff's first two stages: 6-bit outcodes of the eight corners, built plane by
/// plane in the order near, left, right, bottom, top, far with a trivial reject as soon as the AND
/// of the codes is non-zero; then a trivial accept if any code is zero (`inside` when all are).
/// Sets *stage when it decides; nullopt when neither stage decides. In T.
template <class T>
std::optional<Visibility> hoff_trivial_stages_as(const Frustum& f, const std::array<Vec3<T>, 8>& v,
                                                 HoffStage* stage) noexcept {
  auto end = [&](HoffStage s, Visibility r) {
    if (stage) *stage = s;
    return r;
  };
  unsigned code[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  static constexpr int kOrder[6] = {kNear, kLeft, kRight, kBottom, kTop, kFar};
  for (int plane : kOrder) {
    unsigned all = ~0u;
    for (int i = 0; i < 8; ++i) {
      if (plane_eval(f[plane], v[static_cast<std::size_t>(i)]) < T(0)) code[i] |= 1u << plane;
      all &= code[i];
    }
    if (all != 0u) return end(HoffStage::trivial_reject, Visibility::outside);
  }
  bool every_zero = true, some_zero = false;
  for (unsigned c : code) {
    every_zero = every_zero && c == 0u;
    some_zero = some_zero || c == 0u;
  }
  if (some_zero) return end(HoffStage::trivial_accept, every_zero ? Visibility::inside : Visibility::intersecting);
  return std::nullopt;
}
inline std::optional<Visibility> hoff_trivial_stages(const Frustum& f, const std::array<glm::vec3, 8>& corners,
                                                     HoffStage* stage) noexcept {
  return hoff_trivial_stages_as<float>(f, corners, stage);
}

/// Outcode of a point: bit i set when the point is outside plane i (eval < 0).
inline unsigned outcode(const Frustum& f, const glm::vec3& p) noexcept {
  unsigned c = 0;
  for (int i = 0; i < kPlaneCount; ++i)
    if (f[i].eval(p) < 0.0f) c |= 1u << i;
  return c;
}

}  // namespace cullproof::exact_detail

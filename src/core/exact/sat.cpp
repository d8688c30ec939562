// Exact float test by separating axes, OBB (and AABB) against a frustum.
//
// Source: the separating axis theorem for convex polyhedra (Gottschalk, Lin, Manocha, "OBBTree",
// SIGGRAPH 1996, §4; Eberly, "Intersection of Convex Objects: The Method of Separating Axes",
// 2001): two convex polyhedra are disjoint iff their projections on some axis are disjoint, and
// it suffices to try the face normals of both and the cross products of an edge direction of
// one with an edge direction of the other.
// Claim: exact (float errors only within rounding distance of the boundary).
//
// Axes: the box's three face normals (u_j x u_l, so a box whose float axes are not orthonormal
// is still the parallelepiped it is), the frustum's six plane normals, and u_k x e for each box
// edge direction u_k and each frustum edge direction e (12 edges; with an infinite far plane the
// 4 lateral edges are rays). Near-parallel pairs (|u_k x e| <= 1e-6 |u_k||e|) are skipped:
// skipping an axis can only miss a separation (a false intersect), never invent one, so the
// test stays conservative. Projections: the box by its support function c.a +- sum h_i |u_i.a|,
// the frustum by its vertices, a ray making the range unbounded on its side. Closed sets:
// separated only when the ranges are strictly apart, so touching is intersecting.
// The whole float range: where the case's magnitudes leave float's comfortable range
// (float_range_ok, hull_range_ok: coordinates beyond 2^40, coefficients beyond 2^80 or below
// 2^-80, a scene smaller than 2^-40), the same operations run in double. In float, a box from
// -3e38 to 3e38 has corners and projections that overflow (it came out inside), and a scene of
// subnormal size has edge cross products that underflow to zero (a separating axis lost, or a
// projection of rounding noise taken for a separation).
#include "cullproof/core/exact.hpp"

#include "hull.hpp"

#include <cmath>
#include <limits>
#include <type_traits>

namespace cullproof {

using namespace exact_detail;

namespace {

// `skip_ray`: a ray lying along the axis's own frustum edge (its projection is zero in exact
// arithmetic; rounding would make it +-tiny and the range unbounded on a random side).
template <class T>
bool separated_on(const Vec3<T>& a, const FrustumHullT<T>& h, const Obb& b, int skip_ray = -1) {
  if (a.x == T(0) && a.y == T(0) && a.z == T(0)) return false;
  T fmin = std::numeric_limits<T>::infinity(), fmax = -fmin;
  for (const Vec3<T>& p : h.vertices) {
    const T x = glm::dot(p, a);
    fmin = std::min(fmin, x);
    fmax = std::max(fmax, x);
  }
  for (std::size_t i = 0; i < h.rays.size(); ++i) {
    if (int(i) == skip_ray) continue;
    const T x = glm::dot(h.rays[i], a);
    if (x > T(0)) fmax = std::numeric_limits<T>::infinity();
    if (x < T(0)) fmin = -std::numeric_limits<T>::infinity();
  }
  const T c = glm::dot(vec_as<T>(b.center), a), r = obb_radius_as<T>(b, a);
  return fmax < c - r || c + r < fmin;
}

// 1 separated, 0 not, nullopt: not a frustum; kRedo: the float run found vertices beyond its range.
template <class T>
std::optional<int> sat_separated_in(const Frustum& f, const Obb& b) {
  // Frustum face normals first: they need no polyhedron (a degenerate all-space far plane has
  // none). The frustum lies in the plane's half-space by definition, so on this axis its range
  // starts at -d exactly: the box is separated when it lies wholly outside the plane. (Projecting
  // the vertices and rays instead would make the range unbounded whenever a ray lying in the
  // plane rounds to a negative dot.) The far side of each axis is checked with the polyhedron.
  for (const Plane& p : f.planes) {
    if (p.is_degenerate()) {
      if (p.d < 0.0f) return 1;  // contains nothing
      continue;
    }
    if (plane_eval(p, vec_as<T>(b.center)) + obb_radius_as<T>(b, vec_as<T>(p.n)) < T(0)) return 1;
  }
  const auto hull = frustum_hull_as<T>(f);
  if (!hull) return std::nullopt;
  if (hull->empty) return 1;
  if (std::is_same_v<T, float> && !hull_range_ok(f, b, hull->magnitude)) return kRedo;
  for (const Plane& p : f.planes)
    if (!p.is_degenerate() && separated_on<T>(vec_as<T>(p.n), *hull, b)) return 1;
  // Box face normals.
  const Vec3<T> axes[3] = {vec_as<T>(b.axes[0]), vec_as<T>(b.axes[1]), vec_as<T>(b.axes[2])};
  for (int k = 0; k < 3; ++k)
    if (separated_on<T>(glm::cross(axes[(k + 1) % 3], axes[(k + 2) % 3]), *hull, b)) return 1;
  // Edge x edge.
  std::vector<Vec3<T>> dirs;
  std::vector<int> ray_of;  // the ray index a direction comes from, or -1
  for (const auto& [i, j] : hull->edges) {
    dirs.push_back(hull->vertices[static_cast<std::size_t>(j)] - hull->vertices[static_cast<std::size_t>(i)]);
    ray_of.push_back(-1);
  }
  for (std::size_t r = 0; r < hull->rays.size(); ++r) {
    dirs.push_back(hull->rays[r]);
    ray_of.push_back(int(r));
  }
  for (int k = 0; k < 3; ++k)
    for (std::size_t e = 0; e < dirs.size(); ++e) {
      const Vec3<T> a = glm::cross(axes[k], dirs[e]);
      if (glm::length(a) <= T(1e-6f) * glm::length(axes[k]) * glm::length(dirs[e])) continue;
      if (separated_on<T>(a, *hull, b, ray_of[e])) return 1;
    }
  return 0;
}

std::optional<bool> separated(const Frustum& f, const Obb& b, bool wide) {
  std::optional<int> r = wide ? sat_separated_in<double>(f, b) : sat_separated_in<float>(f, b);
  if (r && *r == kRedo) r = sat_separated_in<double>(f, b);
  if (!r) return std::nullopt;
  return *r == 1;
}

}  // namespace

std::optional<bool> sat_separated(const Frustum& f, const Obb& b) { return separated(f, b, !float_range_ok(f, b)); }

std::optional<Visibility> sat_classify(const Frustum& f, const Obb& b) {
  // A box with every corner inside every plane cannot be separated: answer before building the
  // polyhedron (the common case for visible boxes). Otherwise the separating-axis search.
  const bool wide = !float_range_ok(f, b);
  bool all_space_or_planes = true;
  for (const Plane& p : f.planes) all_space_or_planes = all_space_or_planes && !(p.is_degenerate() && p.d < 0.0f);
  if (all_space_or_planes &&
      (wide ? all_corners_inside_as<double>(f, obb_corners_as<double>(b)) : all_corners_inside(f, obb_corners(b))))
    return Visibility::inside;
  const std::optional<bool> sep = separated(f, b, wide);
  if (!sep) return std::nullopt;
  return *sep ? Visibility::outside : Visibility::intersecting;
}

}  // namespace cullproof

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
#include "cullproof/exact.hpp"

#include "hull.hpp"

#include <cmath>
#include <limits>

namespace cullproof {

using namespace exact_detail;

namespace {

// `skip_ray`: a ray lying along the axis's own frustum edge (its projection is zero in exact
// arithmetic; rounding would make it +-tiny and the range unbounded on a random side).
bool separated_on(const glm::vec3& a, const FrustumHull& h, const Obb& b, int skip_ray = -1) {
  if (a.x == 0.0f && a.y == 0.0f && a.z == 0.0f) return false;
  float fmin = std::numeric_limits<float>::infinity(), fmax = -fmin;
  for (const glm::vec3& p : h.vertices) {
    const float x = glm::dot(p, a);
    fmin = std::min(fmin, x);
    fmax = std::max(fmax, x);
  }
  for (std::size_t i = 0; i < h.rays.size(); ++i) {
    if (int(i) == skip_ray) continue;
    const float x = glm::dot(h.rays[i], a);
    if (x > 0.0f) fmax = std::numeric_limits<float>::infinity();
    if (x < 0.0f) fmin = -std::numeric_limits<float>::infinity();
  }
  const float c = glm::dot(b.center, a), r = obb_radius(b, a);
  return fmax < c - r || c + r < fmin;
}

}  // namespace

std::optional<bool> sat_separated(const Frustum& f, const Obb& b) {
  // Frustum face normals first: they need no polyhedron (a degenerate all-space far plane has
  // none). The frustum lies in the plane's half-space by definition, so on this axis its range
  // starts at -d exactly: the box is separated when it lies wholly outside the plane. (Projecting
  // the vertices and rays instead would make the range unbounded whenever a ray lying in the
  // plane rounds to a negative dot.) The far side of each axis is checked with the polyhedron.
  for (const Plane& p : f.planes) {
    if (p.is_degenerate()) {
      if (p.d < 0.0f) return true;  // contains nothing
      continue;
    }
    if (p.eval(b.center) + obb_radius(b, p.n) < 0.0f) return true;
  }
  const auto hull = frustum_hull(f);
  if (!hull) return std::nullopt;
  if (hull->empty) return true;
  for (const Plane& p : f.planes)
    if (!p.is_degenerate() && separated_on(p.n, *hull, b)) return true;
  // Box face normals.
  for (int k = 0; k < 3; ++k)
    if (separated_on(glm::cross(b.axes[(k + 1) % 3], b.axes[(k + 2) % 3]), *hull, b)) return true;
  // Edge x edge.
  std::vector<glm::vec3> dirs;
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
      const glm::vec3 a = glm::cross(b.axes[k], dirs[e]);
      if (glm::length(a) <= 1e-6f * glm::length(b.axes[k]) * glm::length(dirs[e])) continue;
      if (separated_on(a, *hull, b, ray_of[e])) return true;
    }
  return false;
}

std::optional<Visibility> sat_classify(const Frustum& f, const Obb& b) {
  // A box with every corner inside every plane cannot be separated: answer before building the
  // polyhedron (the common case for visible boxes). Otherwise the separating-axis search.
  bool all_space_or_planes = true;
  for (const Plane& p : f.planes) all_space_or_planes = all_space_or_planes && !(p.is_degenerate() && p.d < 0.0f);
  if (all_space_or_planes && all_corners_inside(f, obb_corners(b))) return Visibility::inside;
  const std::optional<bool> sep = sat_separated(f, b);
  if (!sep) return std::nullopt;
  return *sep ? Visibility::outside : Visibility::intersecting;
}

}  // namespace cullproof

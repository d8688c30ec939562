// Frustum polyhedron helpers for src/exact (see hull.hpp).
#include "hull.hpp"

#include "cullproof/core/exact.hpp"
#include "cullproof/core/frustum_build.hpp"

#include <algorithm>
#include <cmath>

namespace cullproof {
namespace exact_detail {

template <class T>
std::optional<FrustumHullT<T>> frustum_hull_as(const Frustum& f) {
  FrustumHullT<T> h;
  for (const Plane& p : f.planes)
    if (p.is_degenerate() && p.d < 0.0f) {
      h.empty = true;
      return h;
    }
  for (int i = 0; i < kPlaneCount; ++i)
    if (f[i].is_degenerate() && i != kFar) return std::nullopt;
  const bool infinite = f[kFar].is_degenerate();
  const int layers = infinite ? 1 : 2;
  std::vector<glm::dvec3> exact_corners;
  for (int i = 0; i < 4 * layers; ++i) {
    const auto x = planes_meet(f[(i & 1) ? kRight : kLeft], f[(i & 2) ? kTop : kBottom], f[(i & 4) ? kFar : kNear]);
    if (!x) return std::nullopt;
    exact_corners.push_back(*x);
    h.vertices.push_back(Vec3<T>(*x));
    h.magnitude = std::max({h.magnitude, std::abs(x->x), std::abs(x->y), std::abs(x->z)});
  }
  if (!has_frustum_topology(f, exact_corners)) return std::nullopt;
  for (int i = 0; i < 4 * layers; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit) && (i | bit) < 4 * layers) h.edges.emplace_back(i, i | bit);
  if (infinite) {
    // Lateral edges: where adjacent side planes meet, heading away from the near plane.
    for (int i = 0; i < 4; ++i) {
      const Plane& lr = f[(i & 1) ? kRight : kLeft];
      const Plane& bt = f[(i & 2) ? kTop : kBottom];
      glm::dvec3 r = glm::cross(glm::dvec3(lr.n), glm::dvec3(bt.n));
      const double s = glm::dot(r, glm::dvec3(f[kNear].n));
      if (s == 0.0 || glm::length(r) == 0.0) return std::nullopt;
      if (s < 0.0) r = -r;
      // Scaled by a power of two, not normalised: a unit direction rounds, and a ray that lies in
      // an axis's plane would then project to +-tiny and unbound the range on a random side.
      int e = 0;
      std::frexp(std::max({std::abs(r.x), std::abs(r.y), std::abs(r.z)}), &e);
      r = glm::dvec3(std::ldexp(r.x, -e), std::ldexp(r.y, -e), std::ldexp(r.z, -e));
      h.rays.push_back(Vec3<T>(r));
      h.ray_edges.emplace_back(i, i);
    }
  }
  return h;
}

template std::optional<FrustumHullT<float>> frustum_hull_as<float>(const Frustum& f);
template std::optional<FrustumHullT<double>> frustum_hull_as<double>(const Frustum& f);

namespace {

// The largest magnitude of a normal component (the plane's scale in the products n_i x_i).
double normal_scale(const Plane& p) {
  return std::max({std::abs(double(p.n.x)), std::abs(double(p.n.y)), std::abs(double(p.n.z))});
}

// The box's largest coordinate magnitude, its extent included (double: no overflow).
double box_magnitude(const Obb& b) {
  double e = 0.0;
  for (int i = 0; i < 3; ++i)
    e += double(b.half[i]) *
         std::max({std::abs(double(b.axes[i].x)), std::abs(double(b.axes[i].y)), std::abs(double(b.axes[i].z))});
  return std::max({std::abs(double(b.center.x)), std::abs(double(b.center.y)), std::abs(double(b.center.z))}) + e;
}

}  // namespace

bool float_range_ok(const Frustum& f, const Obb& b) noexcept {
  const double m = box_magnitude(b);
  if (!(m <= 0x1p40)) return false;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      const double u = std::abs(double(b.axes[i][k]));
      if (u != 0.0 && !(u >= 0x1p-20 && u <= 0x1p20)) return false;
    }
  for (const Plane& p : f.planes) {
    if (p.is_degenerate()) continue;
    const double a = normal_scale(p);
    if (!(a >= 0x1p-80 && a <= 0x1p80) || !(std::abs(double(p.d)) <= 0x1p100) || !(a * m <= 0x1p100)) return false;
  }
  return true;
}

bool hull_range_ok(const Frustum& f, const Obb& b, double hull_magnitude) noexcept {
  if (!(hull_magnitude <= 0x1p40) || !(std::max(hull_magnitude, box_magnitude(b)) >= 0x1p-40)) return false;
  for (const Plane& p : f.planes)
    if (!p.is_degenerate() && !(normal_scale(p) * hull_magnitude <= 0x1p100)) return false;
  return true;
}

bool has_frustum_topology(const Frustum& f, const std::vector<glm::dvec3>& corners) {
  for (const Plane& p : f.planes) {
    if (p.is_degenerate()) continue;
    const glm::dvec3 n(p.n);
    const double len = glm::length(n);
    for (const glm::dvec3& c : corners) {
      const double s = (glm::dot(n, c) + double(p.d)) / len;
      const double mag = glm::length(c) + std::abs(double(p.d)) / len;
      if (s < -1e-10 * mag) return false;
    }
  }
  return true;
}

}  // namespace exact_detail

std::optional<FrustumPolyhedron> frustum_polyhedron(const Frustum& f) {
  if (!is_bounded(f)) return std::nullopt;
  const auto c = frustum_corners(f);
  FrustumPolyhedron p;
  for (std::size_t i = 0; i < 8; ++i) p.corners[i] = glm::vec3(c[i]);
  return p;
}

std::optional<glm::vec3> frustum_apex(const Frustum& f) {
  // Least squares over the four side planes (normalised in double): minimise
  // sum (n_i . x + d_i)^2, i.e. solve (sum n n^T) x = -sum d n.
  glm::dmat3 ata(0.0);
  glm::dvec3 atb(0.0);
  double scale = 0.0;
  for (int i : {kLeft, kRight, kBottom, kTop}) {
    if (f[i].is_degenerate()) return std::nullopt;
    glm::dvec3 n(f[i].n);
    const double len = glm::length(n);
    n /= len;
    const double d = double(f[i].d) / len;
    ata += glm::outerProduct(n, n);
    atb -= d * n;
    scale = std::max(scale, std::abs(d));
  }
  const double det = glm::determinant(ata);
  // The side normals of a perspective frustum span 3D; an orthographic one's lie in a plane.
  if (!(std::abs(det) > 1e-9)) return std::nullopt;
  const glm::dvec3 x = glm::inverse(ata) * atb;
  if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return std::nullopt;
  return glm::vec3(x);
}

std::string_view to_string(HoffStage s) noexcept {
  switch (s) {
    case HoffStage::trivial_reject: return "trivial-reject";
    case HoffStage::trivial_accept: return "trivial-accept";
    case HoffStage::edge_face: return "edge-face";
    case HoffStage::containment: return "containment";
    case HoffStage::box_edge_face: return "box-edge-face";
    case HoffStage::final_reject: return "final-reject";
  }
  return "invalid";
}

}  // namespace cullproof

namespace cullproof::exact_detail {

bool point_in_obb(const glm::vec3& p, const Obb& box) noexcept {
  const glm::vec3 d = p - box.center;
  for (int k = 0; k < 3; ++k)
    if (std::abs(glm::dot(d, box.axes[k])) > box.half[k]) return false;
  return true;
}

bool segment_hits_obb_face(const glm::vec3& a, const glm::vec3& b, const Obb& box, int k, float s) noexcept {
  const glm::vec3 n = s * box.axes[k];
  const glm::vec3 fc = box.center + (s * box.half[k]) * box.axes[k];
  const float da = glm::dot(a - fc, n), db = glm::dot(b - fc, n);
  if ((da > 0.0f && db > 0.0f) || (da < 0.0f && db < 0.0f)) return false;
  const int j = (k + 1) % 3, l = (k + 2) % 3;
  if (da == 0.0f && db == 0.0f)  // in the face plane
    return clip_segment_to_rect(glm::dot(a - fc, box.axes[j]), glm::dot(b - a, box.axes[j]), box.half[j],
                                glm::dot(a - fc, box.axes[l]), glm::dot(b - a, box.axes[l]), box.half[l]);
  const float t = da / (da - db);
  const glm::vec3 p = a + t * (b - a);
  return std::abs(glm::dot(p - fc, box.axes[j])) <= box.half[j] &&
         std::abs(glm::dot(p - fc, box.axes[l])) <= box.half[l];
}

}  // namespace cullproof::exact_detail

// Frustum polyhedron helpers for src/exact (see hull.hpp).
#include "hull.hpp"

#include "cullproof/exact.hpp"
#include "cullproof/frustum_build.hpp"

#include <algorithm>
#include <cmath>

namespace cullproof {
namespace exact_detail {

std::optional<FrustumHull> frustum_hull(const Frustum& f) {
  FrustumHull h;
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
    h.vertices.push_back(glm::vec3(*x));
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
      h.rays.push_back(glm::vec3(r));
      h.ray_edges.emplace_back(i, i);
    }
  }
  return h;
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

std::array<glm::vec3, 8> obb_corners(const Obb& b) noexcept {
  std::array<glm::vec3, 8> c;
  for (int i = 0; i < 8; ++i) {
    const float s0 = (i & 1) ? b.half.x : -b.half.x;
    const float s1 = (i & 2) ? b.half.y : -b.half.y;
    const float s2 = (i & 4) ? b.half.z : -b.half.z;
    c[static_cast<std::size_t>(i)] = b.center + s0 * b.axes[0] + s1 * b.axes[1] + s2 * b.axes[2];
  }
  return c;
}

bool all_corners_inside(const Frustum& f, const std::array<glm::vec3, 8>& corners) noexcept {
  for (const Plane& p : f.planes)
    for (const glm::vec3& v : corners)
      if (p.eval(v) < 0.0f) return false;
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

bool clip_segment_to_rect(float a_j, float d_j, float h_j, float a_l, float d_l, float h_l) noexcept {
  float t0 = 0.0f, t1 = 1.0f;
  const float pa[2] = {a_j, a_l}, pd[2] = {d_j, d_l}, h[2] = {h_j, h_l};
  for (int m = 0; m < 2; ++m)
    for (float side : {1.0f, -1.0f}) {
      // side * (pa + t pd) <= h
      const float num = h[m] - side * pa[m], den = side * pd[m];
      if (den == 0.0f) {
        if (num < 0.0f) return false;
      } else if (den > 0.0f) {
        t1 = std::min(t1, num / den);
      } else {
        t0 = std::max(t0, num / den);
      }
    }
  return t0 <= t1;
}

std::optional<Visibility> hoff_trivial_stages(const Frustum& f, const std::array<glm::vec3, 8>& v,
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
      if (f[plane].eval(v[static_cast<std::size_t>(i)]) < 0.0f) code[i] |= 1u << plane;
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

bool segment_hits_frustum_face(const glm::vec3& a, const glm::vec3& b, const Frustum& f, int face) noexcept {
  const Plane& p = f[face];
  const float da = p.eval(a), db = p.eval(b);
  if ((da > 0.0f && db > 0.0f) || (da < 0.0f && db < 0.0f)) return false;
  auto in_others = [&](const glm::vec3& x) {
    for (int i = 0; i < kPlaneCount; ++i)
      if (i != face && f[i].eval(x) < 0.0f) return false;
    return true;
  };
  if (da == 0.0f && db == 0.0f) {
    // In the face plane: clip the segment against the other five half-spaces.
    float t0 = 0.0f, t1 = 1.0f;
    for (int i = 0; i < kPlaneCount; ++i) {
      if (i == face) continue;
      const float ea = f[i].eval(a), eb = f[i].eval(b);
      if (ea < 0.0f && eb < 0.0f) return false;
      if (ea < 0.0f) t0 = std::max(t0, ea / (ea - eb));
      else if (eb < 0.0f) t1 = std::min(t1, ea / (ea - eb));
    }
    return t0 <= t1;
  }
  const float t = da / (da - db);
  return in_others(a + t * (b - a));
}

}  // namespace cullproof::exact_detail

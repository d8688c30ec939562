// Certified separating-axis test for an OBB (or AABB) against a frustum.
//
// Sources: the separating axis theorem (Gottschalk, Lin & Manocha 1996 §4) proposes the axes;
// Farkas' lemma makes each separation certain: if -a = sum_k l_k n_k with l_k >= 0 over the three
// planes meeting at the frustum's extreme corner on axis a, then P(x) = sum_k l_k (n_k.x + d_k)
// is >= 0 on the whole frustum (a non-negative combination of its defining inequalities), so a
// box on which P < 0 everywhere cannot meet the frustum, whatever rounding did to the corners
// that suggested the axis. Claim: certified-conservative.
//
// Procedure:
//  1. the certified n/p-vertex OBB test (certified.cpp): a certain outside or inside ends here;
//  2. the float SAT axes of sat.cpp (box face normals; box edges x frustum edges): where the
//     float projections separate, take the extreme frustum corner on the box's side, solve the
//     3x3 system for l in double; with every l_k >= 0, form P in double and evaluate its maximum
//     over the box, m = P_n.c + P_d + sum_i h_i |P_n.u_i|;
//  3. certify m < 0 with the bound
//        |m - m_true| <= (u + 2^-49) E,   E = sum_k l_k (a_k . V + a_d,k),  V_j = |c_j| + sum_i h_i |u_ij|
//     (a_k from CertifiedFrustum: the float planes are within u a_k of the true ones, end to end;
//     every double operation on these magnitudes adds at most 2^-53 relative each, fewer than 16
//     of them): outside when m < -2^-22 E (4u > u + 2^-49 with margin) - 2^-1000.
//  Otherwise: inside if step 1 certified it, else intersecting.
#include "cullproof/core/certified.hpp"

#include "../exact/hull.hpp"

#include <cmath>

namespace cullproof {

using namespace exact_detail;

namespace {

struct Certifier {
  const CertifiedFrustum::Data& f;
  const Obb& b;
  glm::dvec3 v;  // V_j = |c_j| + sum_i h_i |u_ij|

  Certifier(const CertifiedFrustum& fr, const Obb& box) : f(fr.data()), b(box) {
    for (int j = 0; j < 3; ++j) {
      v[j] = std::abs(double(box.center[j]));
      for (int i = 0; i < 3; ++i) v[j] += double(box.half[i]) * std::abs(double(box.axes[i][j]));
    }
  }

  // Is the box certainly outside the half-space combination sum l_k plane_k with -a = sum l_k n_k?
  bool separates(const glm::dvec3& a, const int planes[3]) const {
    const glm::dvec3 n0(f.planes[planes[0]].n), n1(f.planes[planes[1]].n), n2(f.planes[planes[2]].n);
    const glm::dmat3 m(n0, n1, n2);  // columns
    const double det = glm::determinant(m);
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return false;
    const glm::dvec3 l = glm::inverse(m) * (-a);
    if (!(l.x >= 0.0 && l.y >= 0.0 && l.z >= 0.0)) return false;
    glm::dvec3 pn(0.0);
    double pd = 0.0, e = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Plane& p = f.planes[planes[k]];
      pn += l[k] * glm::dvec3(p.n);
      pd += l[k] * double(p.d);
      const glm::vec4& bd = f.bound[planes[k]];
      e += l[k] * (double(bd.x) * v.x + double(bd.y) * v.y + double(bd.z) * v.z + double(bd.w));
    }
    double mx = glm::dot(pn, glm::dvec3(b.center)) + pd;
    for (int i = 0; i < 3; ++i) mx += double(b.half[i]) * std::abs(glm::dot(pn, glm::dvec3(b.axes[i])));
    if (!std::isfinite(mx) || !std::isfinite(e)) return false;
    return mx < -0x1p-22 * e - 0x1p-1000;
  }
};

}  // namespace

std::optional<Visibility> certified_sat(const CertifiedFrustum& frustum, const Obb& b) {
  const CertifiedFrustum::Data& f = frustum.data();
  const Visibility planes_only = certified_obb_pn_vertex(frustum, b);
  if (planes_only != Visibility::intersecting) return planes_only;
  const auto hull = frustum_hull(f.planes);
  if (!hull || hull->empty) return Visibility::intersecting;  // the plane tests decided what they could
  const Certifier cert(frustum, b);
  const bool infinite = f.planes[kFar].is_degenerate();

  auto try_axis = [&](const glm::vec3& axis) {
    if (axis == glm::vec3(0.0f)) return false;
    // Float projections; remember the extreme corners.
    float fmin = 0, fmax = 0;
    int imin = -1, imax = -1;
    for (std::size_t i = 0; i < hull->vertices.size(); ++i) {
      const float x = glm::dot(hull->vertices[i], axis);
      if (imin < 0 || x < fmin) fmin = x, imin = int(i);
      if (imax < 0 || x > fmax) fmax = x, imax = int(i);
    }
    bool unbounded_hi = false, unbounded_lo = false;
    for (const glm::vec3& r : hull->rays) {
      const float x = glm::dot(r, axis);
      unbounded_hi = unbounded_hi || x > 0.0f;
      unbounded_lo = unbounded_lo || x < 0.0f;
    }
    const float c = glm::dot(b.center, axis), rad = obb_radius(b, axis);
    int corner = -1;
    glm::dvec3 a(axis);
    if (!unbounded_hi && fmax < c - rad) {
      corner = imax;  // the box lies above the frustum along +axis
    } else if (!unbounded_lo && c + rad < fmin) {
      corner = imin;  // below: use -axis
      a = -a;
    }
    if (corner < 0) return false;
    const int planes[3] = {(corner & 1) ? kRight : kLeft, (corner & 2) ? kTop : kBottom,
                           (corner & 4) && !infinite ? kFar : kNear};
    return cert.separates(a, planes);
  };

  for (int k = 0; k < 3; ++k)
    if (try_axis(glm::cross(b.axes[(k + 1) % 3], b.axes[(k + 2) % 3]))) return Visibility::outside;
  std::vector<glm::vec3> dirs;
  for (const auto& [i, j] : hull->edges)
    dirs.push_back(hull->vertices[static_cast<std::size_t>(j)] - hull->vertices[static_cast<std::size_t>(i)]);
  for (const glm::vec3& r : hull->rays) dirs.push_back(r);
  for (int k = 0; k < 3; ++k)
    for (const glm::vec3& e : dirs)
      if (try_axis(glm::cross(b.axes[k], e))) return Visibility::outside;
  return Visibility::intersecting;
}

}  // namespace cullproof

// The oracle's certificates, checked in exact rationals (Gmpq) in x-space, independently of
// the t-space coefficients the decision used, so that a wrong coefficient is caught: a point of
// B ∩ F, a separating plane as Farkas multipliers, a plane B is not inside.

#include "oracle_internal.hpp"

#include <string>
#include <variant>

namespace cullproof::oracle::internal {

// A point of B ∩ F: x = c + Σ t_i e_i with |t_i| <= 1 and every plane >= 0 at x.
std::array<Q, 3> check_box_point(QCase& qc, const std::array<Q, 3>& t) {
  const auto& planes = qc.planes();
  const auto& b = qc.box();
  for (int i = 0; i < 3; ++i)
    if (t[i] > Q(1) || t[i] < Q(-1)) self_check_failed("witness parameter t outside [-1,1]");
  std::array<Q, 3> x;
  for (int k = 0; k < 3; ++k) x[k] = b.c[k] + t[0] * b.e[0][k] + t[1] * b.e[1][k] + t[2] * b.e[2][k];
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3] < 0)
      self_check_failed("witness point violates plane " + std::string(plane_name(j)));
  }
  return x;
}

// A point of ball ∩ F.
void check_sphere_point(QCase& qc, const Sphere& s, const std::array<Q, 3>& x) {
  const auto& planes = qc.planes();
  Q dd(0);
  for (int k = 0; k < 3; ++k) {
    const Q dk = x[k] - q_of(s.center[k]);
    dd += dk * dk;
  }
  const Q r = q_of(s.radius);
  if (dd > r * r) self_check_failed("witness point outside the sphere");
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3] < 0)
      self_check_failed("witness point violates plane " + std::string(plane_name(j)));
  }
}

// Separation: P = Σ λ_j plane_j with λ >= 0 contains F; B must lie strictly behind P.
// Returns P. For a box: max_{x∈B} P(x) = P(c) + Σ_i |∇P·e_i| < 0. For a ball: P(c) < 0 and
// P(c)^2 > r^2 |∇P|^2 (signed distance of the centre below -r).
detail::Coeffs<Q> check_separation(QCase& qc, const std::array<Q, 6>& lambda) {
  const Volume& v = qc.volume();
  const auto& planes = qc.planes();
  detail::Coeffs<Q> P{Q(0), Q(0), Q(0), Q(0)};
  for (int j = 0; j < 6; ++j) {
    if (lambda[j] < 0) self_check_failed("negative Farkas multiplier");
    if (CGAL::is_zero(lambda[j])) continue;
    for (int k = 0; k < 4; ++k) P[k] += lambda[j] * planes[j][k];
  }
  if (const auto* s = std::get_if<Sphere>(&v)) {
    const Q pc = P[0] * q_of(s->center.x) + P[1] * q_of(s->center.y) + P[2] * q_of(s->center.z) + P[3];
    const Q r = q_of(s->radius);
    const Q nn = P[0] * P[0] + P[1] * P[1] + P[2] * P[2];
    if (!(pc < 0) || !(pc * pc > r * r * nn)) self_check_failed("separating plane does not separate the sphere");
    return P;
  }
  const auto& b = qc.box();
  Q m = P[0] * b.c[0] + P[1] * b.c[1] + P[2] * b.c[2] + P[3];
  for (int i = 0; i < 3; ++i) m += CGAL::abs(P[0] * b.e[i][0] + P[1] * b.e[i][1] + P[2] * b.e[i][2]);
  if (!(m < 0)) self_check_failed("separating plane does not separate the box");
  return P;
}

// Not inside: some plane j is violated somewhere in B. For a box, at the corner
// c + Σ s_i e_i with s_i = -sign(n_j·e_i); for a ball, when s_j < 0 or s_j^2 < r^2 |n_j|^2
// (s_j = n_j·c + d_j). Returns j and, for a box, that corner; throws when B ⊆ F.
std::pair<int, std::optional<std::array<Q, 3>>> check_not_inside(QCase& qc) {
  const Volume& v = qc.volume();
  const auto& planes = qc.planes();
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (const auto* s = std::get_if<Sphere>(&v)) {
      const Q sj = p[0] * q_of(s->center.x) + p[1] * q_of(s->center.y) + p[2] * q_of(s->center.z) + p[3];
      const Q r = q_of(s->radius);
      if (sj < 0 || sj * sj < r * r * (p[0] * p[0] + p[1] * p[1] + p[2] * p[2])) return {j, std::nullopt};
      continue;
    }
    const auto& b = qc.box();
    std::array<Q, 3> x = b.c;
    for (int i = 0; i < 3; ++i) {
      const Q ne = p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2];
      for (int k = 0; k < 3; ++k) x[k] = ne > 0 ? x[k] - b.e[i][k] : x[k] + b.e[i][k];
    }
    if (p[0] * x[0] + p[1] * x[1] + p[2] * x[2] + p[3] < 0) return {j, x};
  }
  self_check_failed("an 'intersecting' volume lies inside every plane");
}

Witness separation_witness(const std::array<Q, 6>& lambda, const detail::Coeffs<Q>& P) {
  Witness w;
  w.kind = Witness::Kind::separating_plane;
  w.plane = rationals(std::array<Q, 4>{P[0], P[1], P[2], P[3]});
  w.multipliers = rationals(lambda);
  return w;
}

Witness point_witness(const std::array<Q, 3>& x) {
  Witness w;
  w.kind = Witness::Kind::point;
  w.point = rationals(x);
  return w;
}

}  // namespace cullproof::oracle::internal

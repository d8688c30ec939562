// The oracle's exact distances for cases that are not outside: per plane, how deep the volume
// reaches in (penetration), how far it reaches out (protrusion) and, for `inside`, its clearance.

#include "oracle_internal.hpp"

#include <algorithm>
#include <cmath>

namespace cullproof::oracle::internal {

Margins box_margins(const Planes& P, const detail::BoxT<ET>& b) {
  Margins m;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) continue;
    const auto& p = P.p[j];
    const ET a0 = p[0] * b.c[0] + p[1] * b.c[1] + p[2] * b.c[2] + p[3];
    ET spread(0);
    for (int i = 0; i < 3; ++i) spread = spread + CGAL::abs(p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2]);
    const double len = std::sqrt(approx(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
    const double hi = approx(a0 + spread) / len, lo = approx(a0 - spread) / len;
    m.penetration = std::min(m.penetration, hi);
    m.protrusion = std::max(m.protrusion, -lo);
    m.clearance = std::min(m.clearance, lo);
  }
  return m;
}

// Sphere margins. With s = n·c + d, nn = |n|^2: max over the ball of the signed distance is
// s/|n| + r, the min is s/|n| - r. Where the sum cancels, use (s^2 - r^2 nn) exactly over a
// cancellation-free denominator.
Margins sphere_margins(const Planes& P, const Sphere& sp) {
  Margins m;
  const ET r = et_of(sp.radius);
  const double rd = sp.radius;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) continue;
    const auto& p = P.p[j];
    const ET s = p[0] * et_of(sp.center.x) + p[1] * et_of(sp.center.y) + p[2] * et_of(sp.center.z) + p[3];
    const ET nn = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const double len = std::sqrt(approx(nn)), sd = approx(s);
    const double diff = approx(s * s - r * r * nn);  // (s - r|n|)(s + r|n|)
    // hi = s/|n| + r, lo = s/|n| - r.
    const double hi = sd >= 0 ? sd / len + rd : -diff / (len * (rd * len - sd));
    const double lo = sd <= 0 ? sd / len - rd : diff / (len * (sd + rd * len));
    m.penetration = std::min(m.penetration, hi);
    m.protrusion = std::max(m.protrusion, -lo);
    m.clearance = std::min(m.clearance, lo);
  }
  return m;
}

void set_margin_distance(Result& r, const Margins& m) {
  if (r.truth == Visibility::inside) {
    r.distance = m.clearance;
    r.distance_kind = DistanceKind::clearance;
  } else {
    r.distance = std::min(m.penetration, m.protrusion);
    r.distance_kind = DistanceKind::margin;
    if (r.witness.kind != Witness::Kind::none) {
      r.witness.penetration = m.penetration;
      r.witness.protrusion = m.protrusion;
    }
  }
}

}  // namespace cullproof::oracle::internal

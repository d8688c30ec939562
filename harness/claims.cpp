// What a claim forbids and how far an error lies from being right: error classes, the claim rule,
// the backward distance (see cullproof/campaign.hpp), and the Wilson interval of a rate.
#include "cullproof/campaign.hpp"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace cullproof {

ErrorClass error_class(Visibility verdict, Visibility truth, bool three_way) noexcept {
  if (verdict == truth) return ErrorClass::correct;
  if (!three_way && verdict == Visibility::intersecting && truth == Visibility::inside) return ErrorClass::correct;
  if (verdict == Visibility::outside) return ErrorClass::false_reject;
  if (verdict == Visibility::inside) return ErrorClass::false_inside;
  return truth == Visibility::outside ? ErrorClass::false_intersect : ErrorClass::under_inside;
}

bool violates_claim(Claim claim, ErrorClass e, double distance, double tolerance, double scale, bool float_exact) noexcept {
  if (e == ErrorClass::correct) return false;
  const bool hard = e == ErrorClass::false_reject || e == ErrorClass::false_inside;
  // A certified band, or the rounding allowance; a zero tolerance forgives nothing, not even an
  // error at distance 0 (a volume touching the boundary).
  const bool within = tolerance > 0.0 && distance <= tolerance * scale;
  const bool allowed = within && !float_exact;         // the rounding allowance: only where things round
  switch (claim) {
    case Claim::certified_conservative: return hard;
    case Claim::certified_exact: return hard || !within;
    case Claim::conservative: return hard && !allowed;
    case Claim::exact: return !allowed;
    case Claim::none: return false;
  }
  return false;
}

namespace {

// Planes in double, normalised: the float planes for plane cases; for end-to-end cases the row
// sums of the float matrix taken in double. Degenerate planes: all space is dropped, nothing
// gives an empty list and `empty`.
struct DPlanes {
  std::vector<glm::dvec4> p;
  bool empty = false;
};

DPlanes double_planes(const CaseFrustum& f) {
  DPlanes out;
  std::array<glm::dvec4, 6> raw;
  if (f.matrix) {
    glm::dvec4 r[4];
    for (int i = 0; i < 4; ++i) r[i] = glm::dvec4(matrix_row(*f.matrix, i));
    raw[kLeft] = r[3] + r[0];
    raw[kRight] = r[3] - r[0];
    raw[kBottom] = r[3] + r[1];
    raw[kTop] = r[3] - r[1];
    const glm::dvec4 lower = f.depth.range == DepthRange::negative_one_to_one ? r[3] + r[2] : r[2];
    const glm::dvec4 upper = r[3] - r[2];
    raw[kNear] = f.depth.reversed_z ? upper : lower;
    raw[kFar] = f.depth.reversed_z ? lower : upper;
  } else {
    for (int k = 0; k < 6; ++k) raw[k] = glm::dvec4(glm::dvec3(f.planes[k].n), double(f.planes[k].d));
  }
  for (const glm::dvec4& q : raw) {
    const double len = glm::length(glm::dvec3(q));
    if (len == 0.0) {
      if (q.w < 0.0) out.empty = true;
      continue;
    }
    out.p.push_back(q / len);
  }
  return out;
}

// mu = max over t in [-1,1]^3 of min_j (s_j(c) + sum_i t_i g_ji), by enumerating the vertices of
// the LP in (t, mu): every choice of 4 active constraints among the planes and the 6 bounds.
// The LP is solved in units of the box's size L (its longest half-edge; 1 for a point), so that
// its determinants are about 1 whatever the scale: a box of 1e-40 or of 1e38 is the same problem.
double max_min_depth(const std::vector<glm::dvec4>& planes, const glm::dvec3& c, const glm::dvec3 (&e)[3]) {
  struct Row {
    double a[4];
    double b;  // a . (t, mu / L) >= b
  };
  double size = std::max({glm::length(e[0]), glm::length(e[1]), glm::length(e[2])});
  if (!(size > 0.0) || !std::isfinite(size)) size = 1.0;
  std::vector<Row> rows;
  for (const glm::dvec4& q : planes) {
    const glm::dvec3 n(q);
    // (s(c) + sum t_i (n . e_i) - mu) / L >= 0
    rows.push_back(Row{{glm::dot(n, e[0]) / size, glm::dot(n, e[1]) / size, glm::dot(n, e[2]) / size, -1.0},
                       -(glm::dot(n, c) + q.w) / size});
  }
  for (int i = 0; i < 3; ++i) {
    Row lo{{0, 0, 0, 0}, -1.0}, hi{{0, 0, 0, 0}, -1.0};
    lo.a[i] = 1.0;   // t_i >= -1
    hi.a[i] = -1.0;  // -t_i >= -1
    rows.push_back(lo);
    rows.push_back(hi);
  }
  const int n = int(rows.size());
  double best = -std::numeric_limits<double>::infinity();
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b)
      for (int c2 = b + 1; c2 < n; ++c2)
        for (int d = c2 + 1; d < n; ++d) {
          const int idx[4] = {a, b, c2, d};
          glm::dmat4 m;
          glm::dvec4 rhs;
          for (int r = 0; r < 4; ++r) {
            for (int k = 0; k < 4; ++k) m[k][r] = rows[std::size_t(idx[r])].a[k];
            rhs[r] = rows[std::size_t(idx[r])].b;
          }
          const double det = glm::determinant(m);
          if (std::abs(det) < 1e-14) continue;
          const glm::dvec4 y = glm::inverse(m) * rhs;
          bool ok = true;
          for (const Row& row : rows) {
            const double lhs = row.a[0] * y.x + row.a[1] * y.y + row.a[2] * y.z + row.a[3] * y.w;
            if (lhs < row.b - 1e-9 * (1.0 + std::abs(row.b))) {
              ok = false;
              break;
            }
          }
          if (ok) best = std::max(best, y.w);
        }
  return best * size;
}

}  // namespace

double backward_distance(const CaseFrustum& f, const Volume& v, ErrorClass e) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  if (e == ErrorClass::correct || std::holds_alternative<Sphere>(v)) return inf;
  const DPlanes dp = double_planes(f);
  if (dp.empty) return inf;
  glm::dvec3 c;
  glm::dvec3 ax[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};
  if (const Point* p = std::get_if<Point>(&v)) {
    c = glm::dvec3(*p);
  } else if (const Aabb* a = std::get_if<Aabb>(&v)) {  // exact centre and half-extents in double
    c = (glm::dvec3(a->min) + glm::dvec3(a->max)) * 0.5;
    for (int i = 0; i < 3; ++i) ax[i][i] = (double(a->max[i]) - double(a->min[i])) * 0.5;
  } else {
    const Obb& b = std::get<Obb>(v);
    c = glm::dvec3(b.center);
    for (int i = 0; i < 3; ++i) ax[i] = glm::dvec3(b.axes[i]) * double(b.half[i]);
  }
  // Extremes of each plane over the box: s_j(c) +- sum_i |n_j . e_i|.
  double protrusion = -inf, clearance = inf;
  for (const glm::dvec4& q : dp.p) {
    const glm::dvec3 n(q);
    const double s = glm::dot(n, c) + q.w;
    const double r = std::abs(glm::dot(n, ax[0])) + std::abs(glm::dot(n, ax[1])) + std::abs(glm::dot(n, ax[2]));
    protrusion = std::max(protrusion, -(s - r));
    clearance = std::min(clearance, s - r);
  }
  switch (e) {
    case ErrorClass::false_inside: return std::max(0.0, protrusion);
    case ErrorClass::under_inside: return std::max(0.0, clearance);
    case ErrorClass::false_reject: return std::max(0.0, max_min_depth(dp.p, c, ax));
    case ErrorClass::false_intersect: return std::max(0.0, -max_min_depth(dp.p, c, ax));
    default: return inf;
  }
}

double error_distance(const CaseFrustum& f, const Volume& v, ErrorClass e, double oracle_distance) {
  return std::min(oracle_distance, backward_distance(f, v, e));
}

bool VerifyResult::claim_broken() const noexcept {
  for (const auto& d : distributions)
    for (const auto& m : d.methods)
      if (m.origin != Origin::published && m.refuted()) return true;
  return false;
}

std::pair<double, double> wilson95(std::uint64_t k, std::uint64_t n) noexcept {
  if (n == 0) return {0.0, 0.0};
  const double z = 1.959963984540054, p = double(k) / double(n), nn = double(n);
  const double denom = 1 + z * z / nn, centre = (p + z * z / (2 * nn)) / denom;
  const double half = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn)) / denom;
  // With no success (no failure) the bound is exactly 0 (1); centre - half would leave a rounding
  // residue such as 1e-19 there.
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

}  // namespace cullproof

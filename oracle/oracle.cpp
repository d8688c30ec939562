// The exact oracle: interval filter, exact LP/QP route, checked certificates and
// exact distances. Semantics are docs/semantics.md "The truth"; contracts are in
// cullproof/oracle.hpp.
//
// Sources:
//  - B. Gärtner, S. Schönherr, "An efficient, exact, and generic quadratic programming solver
//    for geometric optimization", SoCG 2000 (CGAL's QP solver, used with exact CGAL::Gmpzf).
//  - H. Brönnimann, C. Burnikel, S. Pion, "Interval arithmetic yields efficient dynamic
//    filters for computational geometry", 1998 (CGAL::Interval_nt, Protect_FPU_rounding).
//  - Farkas' lemma for a box-constrained system: {t ∈ [-1,1]^3 : g_j(t) >= 0} is empty iff some
//    λ >= 0 gives max_{t ∈ [-1,1]^3} Σ λ_j g_j(t) < 0 (LP duality / minimax on compact sets).
//
// Every float reaches the exact route through an explicit lossless conversion (float -> double
// -> Gmpzf/Gmpq, both exact for binary floats). No tolerance appears anywhere: the filter only
// answers when its rounded-outward interval bounds prove the answer.

#include "cullproof/oracle.hpp"

#include "exact_input.hpp"

#include <CGAL/Gmpq.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace cullproof::oracle {

namespace {

using ET = CGAL::Gmpzf;           // exact dyadic numbers: every float, sum and product of floats
using Q = CGAL::Gmpq;             // exact rationals: LP solutions and certificates
using I = CGAL::Interval_nt<false>;  // filter intervals (need Protect_FPU_rounding in scope)

std::atomic<std::uint64_t> g_calls{0}, g_filtered{0}, g_fallbacks{0}, g_exact_lp{0};

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- exact conversions ------------------------------------------------------------------

ET et_of(float x) { return ET(static_cast<double>(x)); }
Q q_of(float x) { return Q(static_cast<double>(x)); }

// Gmpzf value man * 2^exp as a rational, exactly.
Q q_of(const ET& x) {
  Q r;
  mpq_set_z(r.mpq(), x.man());
  const long e = x.exp();
  if (e > 0) mpq_mul_2exp(r.mpq(), r.mpq(), static_cast<mp_bitcnt_t>(e));
  if (e < 0) mpq_div_2exp(r.mpq(), r.mpq(), static_cast<mp_bitcnt_t>(-e));
  return r;
}
Q q_of(const CGAL::Quotient<ET>& x) { return q_of(x.numerator()) / q_of(x.denominator()); }

std::string text(const Q& q) {
  char* s = mpq_get_str(nullptr, 10, q.mpq());
  std::string out(s);
  void (*freefunc)(void*, size_t);
  mp_get_memory_functions(nullptr, nullptr, &freefunc);
  freefunc(s, out.size() + 1);
  return out;
}
double approx(const Q& q) { return mpq_get_d(q.mpq()); }
double approx(const ET& x) { return CGAL::to_double(x); }

nlohmann::json exact_vec(const std::array<Q, 3>& v) {
  return nlohmann::json::array({text(v[0]), text(v[1]), text(v[2])});
}
nlohmann::json approx_vec(const std::array<Q, 3>& v) {
  return nlohmann::json::array({approx(v[0]), approx(v[1]), approx(v[2])});
}

[[noreturn]] void self_check_failed(const std::string& what) {
  throw OracleError("cullproof oracle self-check failed: " + what +
                    " (this is an oracle bug; please file the case)");
}

// ---- the case in exact numbers ------------------------------------------------------------

struct Planes {
  std::array<detail::Coeffs<ET>, 6> p;
  std::array<bool, 6> degenerate{};  // n == 0 exactly
};

Planes exact_planes_et(const CaseFrustum& f) {
  Planes out;
  out.p = detail::exact_planes<ET>(f, [](float x) { return et_of(x); });
  for (int j = 0; j < 6; ++j) {
    const auto& c = out.p[j];
    out.degenerate[j] = CGAL::is_zero(c[0]) && CGAL::is_zero(c[1]) && CGAL::is_zero(c[2]);
  }
  return out;
}

std::array<detail::Coeffs<Q>, 6> exact_planes_q(const CaseFrustum& f) {
  return detail::exact_planes<Q>(f, [](float x) { return q_of(x); });
}

detail::BoxT<Q> exact_box_q(const Volume& v) {
  return detail::exact_box<Q>(v, [](float x) { return q_of(x); }, Q(1, 2));
}

// The case in Gmpq, converted once per call and only when a check needs it.
class QCase {
 public:
  QCase(const CaseFrustum& f, const Volume& v) : f_(f), v_(v) {}
  const std::array<detail::Coeffs<Q>, 6>& planes() {
    if (!planes_) planes_ = exact_planes_q(f_);
    return *planes_;
  }
  const detail::BoxT<Q>& box() {
    if (!box_) box_ = exact_box_q(v_);
    return *box_;
  }
  const Volume& volume() const { return v_; }

 private:
  const CaseFrustum& f_;
  const Volume& v_;
  std::optional<std::array<detail::Coeffs<Q>, 6>> planes_;
  std::optional<detail::BoxT<Q>> box_;
};

// ---- certificate checks (exact, in x-space with Gmpq; independent of the t-space coefficients
// the decision used, so a wrong coefficient is caught here) ------------------------------------

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

nlohmann::json separation_json(const std::array<Q, 6>& lambda, const detail::Coeffs<Q>& P) {
  nlohmann::json mult = nlohmann::json::array();
  for (const Q& l : lambda) mult.push_back(text(l));
  return {{"kind", "separating_plane"},
          {"plane", {text(P[0]), text(P[1]), text(P[2]), text(P[3])}},
          {"plane_approx", {approx(P[0]), approx(P[1]), approx(P[2]), approx(P[3])}},
          {"multipliers", mult}};
}

nlohmann::json point_json(const std::array<Q, 3>& x) {
  return {{"kind", "point"}, {"point", exact_vec(x)}, {"point_approx", approx_vec(x)}};
}

// ---- exact distances ------------------------------------------------------------------------

// Box (or point) margins: per non-degenerate plane, max and min over B of the plane value,
// exactly, divided by |n| at the end.
struct Margins {
  double penetration = kInf;  // min_j max_B dist_j
  double protrusion = 0.0;    // max_j max(0, -min_B dist_j)
  double clearance = kInf;    // min_j min_B dist_j
};

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
    if (r.witness.is_object()) {
      r.witness["penetration"] = m.penetration;
      r.witness["protrusion"] = m.protrusion;
    }
  }
}

// ---- exact solvers --------------------------------------------------------------------------

using Program = CGAL::Quadratic_program<ET>;
using Solution = CGAL::Quadratic_program_solution<ET>;

// t-space coefficients g_j(t) = a_j0 + Σ a_ji t_i of plane j on the box.
std::array<ET, 4> box_coeffs(const detail::Coeffs<ET>& p, const detail::BoxT<ET>& b) {
  std::array<ET, 4> a;
  a[0] = p[0] * b.c[0] + p[1] * b.c[1] + p[2] * b.c[2] + p[3];
  for (int i = 0; i < 3; ++i) a[i + 1] = p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2];
  return a;
}

struct Decision {
  Visibility truth = Visibility::outside;
  std::optional<std::array<Q, 3>> t_or_point;  // box: t of a point in B ∩ F; sphere: the point
  std::optional<std::array<Q, 6>> lambda;      // outside: Farkas multipliers
};

Decision exact_box_route(const Planes& P, const detail::BoxT<ET>& b) {
  Decision out;
  // A plane containing nothing: F is empty.
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j] && P.p[j][3] < 0) {
      std::array<Q, 6> l{};
      l.fill(Q(0));
      l[j] = Q(1);
      out.lambda = l;
      return out;
    }
  }
  // Containment: the minimum of each plane over the box is at a corner: a_0 - Σ |a_i| >= 0.
  std::array<std::array<ET, 4>, 6> a;
  bool inside = true;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) continue;
    a[j] = box_coeffs(P.p[j], b);
    const ET lo = a[j][0] - CGAL::abs(a[j][1]) - CGAL::abs(a[j][2]) - CGAL::abs(a[j][3]);
    if (lo < 0) inside = false;
  }
  if (inside) {
    out.truth = Visibility::inside;
    out.t_or_point = std::array<Q, 3>{Q(0), Q(0), Q(0)};  // the centre is in B ⊆ F
    return out;
  }
  // Feasibility LP: t ∈ [-1,1]^3 with Σ a_ji t_i >= -a_j0 for each plane.
  Program lp(CGAL::LARGER, true, -1, true, 1);
  std::array<int, 6> row_plane{};
  int rows = 0;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) continue;
    for (int i = 0; i < 3; ++i)
      if (!CGAL::is_zero(a[j][i + 1])) lp.set_a(i, rows, a[j][i + 1]);
    lp.set_b(rows, -a[j][0]);
    row_plane[rows] = j;
    ++rows;
  }
  g_exact_lp.fetch_add(1, std::memory_order_relaxed);
  const Solution s = CGAL::solve_quadratic_program(lp, ET());
  if (s.is_infeasible()) {
    // CGAL's infeasibility certificate λ has λ_i <= 0 for ">=" rows and λ^T(A t - b) > 0 for
    // every t in the bounds, so μ = -λ >= 0 gives max over the box of Σ μ_j g_j(t) < 0: our
    // Farkas multipliers, one per plane (checked exactly by check_separation).
    std::array<Q, 6> l;
    l.fill(Q(0));
    int row = 0;
    for (auto it = s.infeasibility_certificate_begin(); it != s.infeasibility_certificate_end(); ++it, ++row)
      l[row_plane[row]] = -q_of(*it);
    out.lambda = l;
    return out;
  }
  if (!s.is_optimal()) self_check_failed("feasibility LP neither infeasible nor optimal");
  out.truth = Visibility::intersecting;
  std::array<Q, 3> t;
  int i = 0;
  for (auto it = s.variable_values_begin(); it != s.variable_values_end() && i < 3; ++it, ++i) t[i] = q_of(*it);
  out.t_or_point = t;
  return out;
}

std::optional<std::array<Q, 6>> kkt_multipliers(const std::array<detail::Coeffs<Q>, 6>& planes,
                                                const std::array<Q, 3>& y, const std::array<Q, 3>& x);

// Closest point y of F to the centre c (exact QP); nullopt when F is empty, with the Farkas
// certificate of emptiness in `lambda`. Checked: y ∈ F, dist2 == |y - c|^2 exactly, and
// `lambda` holds KKT multipliers (λ >= 0, y - c = Σ λ_j n_j over planes active at y), which
// prove optimality: every x ∈ F has Σ λ_j plane_j(x) >= 0, i.e. (y - c)·(x - y) >= 0.
struct Closest {
  std::optional<std::array<Q, 3>> y;
  Q dist2;
  std::array<Q, 6> lambda;  // F empty: Farkas multipliers; else KKT multipliers at y
};

Closest closest_point_of_frustum(QCase& qc, const Planes& P, const std::array<ET, 3>& c) {
  Program qp(CGAL::LARGER, false, 0, false, 0);
  std::array<int, 6> row_plane{};
  int rows = 0;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j] && !(P.p[j][3] < 0)) continue;
    for (int i = 0; i < 3; ++i)
      if (!CGAL::is_zero(P.p[j][i])) qp.set_a(i, rows, P.p[j][i]);
    qp.set_b(rows, -P.p[j][3]);
    row_plane[rows] = j;
    ++rows;
  }
  // |y - c|^2 = y·y - 2 c·y + c·c; CGAL's D is given as 2D.
  for (int i = 0; i < 3; ++i) {
    qp.set_d(i, i, ET(2));
    qp.set_c(i, ET(-2) * c[i]);
  }
  qp.set_c0(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  g_exact_lp.fetch_add(1, std::memory_order_relaxed);
  const Solution s = CGAL::solve_quadratic_program(qp, ET());
  Closest out;
  out.lambda.fill(Q(0));
  if (s.is_infeasible()) {
    int row = 0;
    for (auto it = s.infeasibility_certificate_begin(); it != s.infeasibility_certificate_end(); ++it, ++row)
      out.lambda[row_plane[row]] = -q_of(*it);
    return out;
  }
  if (!s.is_optimal()) self_check_failed("closest-point QP neither infeasible nor optimal");
  std::array<Q, 3> y;
  int i = 0;
  for (auto it = s.variable_values_begin(); it != s.variable_values_end() && i < 3; ++it, ++i) y[i] = q_of(*it);
  out.y = y;
  out.dist2 = q_of(s.objective_value());
  const auto& planes = qc.planes();
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (p[0] * y[0] + p[1] * y[1] + p[2] * y[2] + p[3] < 0) self_check_failed("closest-point QP: y outside F");
  }
  const std::array<Q, 3> cq{q_of(c[0]), q_of(c[1]), q_of(c[2])};
  const Q dx = y[0] - cq[0], dy = y[1] - cq[1], dz = y[2] - cq[2];
  if (dx * dx + dy * dy + dz * dz != out.dist2) self_check_failed("closest-point QP: value is not |y - c|^2");
  if (!CGAL::is_zero(out.dist2)) {
    const auto kkt = kkt_multipliers(planes, y, cq);
    if (!kkt) self_check_failed("closest-point QP: no KKT multipliers prove optimality");
    out.lambda = *kkt;
  }
  return out;
}

// KKT multipliers at the closest point y of F to a point x: y - x = Σ λ_j n_j over planes
// active at y, λ >= 0. Found exactly by trying subsets of at most three active planes
// (Carathéodory) and solving their normal equations.
std::optional<std::array<Q, 6>> kkt_multipliers(const std::array<detail::Coeffs<Q>, 6>& planes,
                                                const std::array<Q, 3>& y, const std::array<Q, 3>& x) {
  std::vector<int> active;
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    const bool deg = CGAL::is_zero(p[0]) && CGAL::is_zero(p[1]) && CGAL::is_zero(p[2]);
    if (!deg && CGAL::is_zero(p[0] * y[0] + p[1] * y[1] + p[2] * y[2] + p[3])) active.push_back(j);
  }
  const std::array<Q, 3> w{y[0] - x[0], y[1] - x[1], y[2] - x[2]};
  const int na = static_cast<int>(active.size());
  auto dot = [&](int j, int k) {
    return planes[j][0] * planes[k][0] + planes[j][1] * planes[k][1] + planes[j][2] * planes[k][2];
  };
  auto dotw = [&](int j) { return planes[j][0] * w[0] + planes[j][1] * w[1] + planes[j][2] * w[2]; };
  for (int mask = 1; mask < (1 << na); ++mask) {
    std::vector<int> S;
    for (int k = 0; k < na; ++k)
      if (mask & (1 << k)) S.push_back(active[static_cast<std::size_t>(k)]);
    if (S.size() > 3) continue;
    const int n = static_cast<int>(S.size());
    // Gaussian elimination on the Gram system G λ = N^T w.
    std::vector<std::vector<Q>> G(static_cast<std::size_t>(n), std::vector<Q>(static_cast<std::size_t>(n + 1)));
    for (int r = 0; r < n; ++r) {
      for (int cc = 0; cc < n; ++cc) G[r][cc] = dot(S[r], S[cc]);
      G[r][n] = dotw(S[r]);
    }
    bool singular = false;
    for (int col = 0; col < n && !singular; ++col) {
      int piv = -1;
      for (int r = col; r < n; ++r)
        if (!CGAL::is_zero(G[r][col])) { piv = r; break; }
      if (piv < 0) { singular = true; break; }
      std::swap(G[col], G[piv]);
      for (int r = 0; r < n; ++r) {
        if (r == col || CGAL::is_zero(G[r][col])) continue;
        const Q fct = G[r][col] / G[col][col];
        for (int cc = col; cc <= n; ++cc) G[r][cc] -= fct * G[col][cc];
      }
    }
    if (singular) continue;
    std::array<Q, 6> lambda;
    lambda.fill(Q(0));
    bool ok = true;
    for (int r = 0; r < n; ++r) {
      const Q l = G[r][n] / G[r][r];
      if (l < 0) ok = false;
      lambda[S[r]] = l;
    }
    if (!ok) continue;
    std::array<Q, 3> sum{Q(0), Q(0), Q(0)};
    for (int j : S)
      for (int k = 0; k < 3; ++k) sum[k] += lambda[j] * planes[j][k];
    if (sum[0] == w[0] && sum[1] == w[1] && sum[2] == w[2]) return lambda;
  }
  return std::nullopt;
}

// Euclidean distance between a box and F by the exact QP
//   min |c + E t - y|^2  over t ∈ [-1,1]^3, y ∈ F.
// Returns the exact squared distance (nullopt when F is empty); checks the optimal pair.
std::optional<Q> box_distance2(QCase& qc, const Planes& P, const detail::BoxT<ET>& b) {
  Program qp(CGAL::LARGER, true, -1, true, 1);
  for (int k = 0; k < 3; ++k) {
    qp.set_l(3 + k, false);
    qp.set_u(3 + k, false);
  }
  int rows = 0;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j] && !(P.p[j][3] < 0)) continue;
    for (int k = 0; k < 3; ++k)
      if (!CGAL::is_zero(P.p[j][k])) qp.set_a(3 + k, rows, P.p[j][k]);
    qp.set_b(rows, -P.p[j][3]);
    ++rows;
  }
  // Objective t^T (E^T E) t - 2 t^T E^T y + y^T y + 2 c^T E t - 2 c^T y + c^T c (2D given).
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j <= i; ++j) {
      const ET eij = b.e[i][0] * b.e[j][0] + b.e[i][1] * b.e[j][1] + b.e[i][2] * b.e[j][2];
      if (!CGAL::is_zero(eij)) qp.set_d(i, j, ET(2) * eij);
    }
    for (int k = 0; k < 3; ++k)
      if (!CGAL::is_zero(b.e[i][k])) qp.set_d(3 + k, i, ET(-2) * b.e[i][k]);
    qp.set_d(3 + i, 3 + i, ET(2));
    qp.set_c(i, ET(2) * (b.c[0] * b.e[i][0] + b.c[1] * b.e[i][1] + b.c[2] * b.e[i][2]));
    qp.set_c(3 + i, ET(-2) * b.c[i]);
  }
  qp.set_c0(b.c[0] * b.c[0] + b.c[1] * b.c[1] + b.c[2] * b.c[2]);
  g_exact_lp.fetch_add(1, std::memory_order_relaxed);
  const Solution s = CGAL::solve_quadratic_program(qp, ET());
  if (s.is_infeasible()) return std::nullopt;
  if (!s.is_optimal()) self_check_failed("distance QP neither infeasible nor optimal");
  std::array<Q, 6> z;
  int i = 0;
  for (auto it = s.variable_values_begin(); it != s.variable_values_end() && i < 6; ++it, ++i) z[i] = q_of(*it);
  // Check: the pair (x, y) is feasible and realises the optimal value exactly.
  const auto& planes = qc.planes();
  const auto& bq = qc.box();
  std::array<Q, 3> x;
  for (int k = 0; k < 3; ++k) {
    if (z[k] > Q(1) || z[k] < Q(-1)) self_check_failed("distance QP: t outside [-1,1]");
    x[k] = bq.c[k] + z[0] * bq.e[0][k] + z[1] * bq.e[1][k] + z[2] * bq.e[2][k];
  }
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (p[0] * z[3] + p[1] * z[4] + p[2] * z[5] + p[3] < 0) self_check_failed("distance QP: y outside F");
  }
  const Q value = q_of(s.objective_value());
  const Q dx = x[0] - z[3], dy = x[1] - z[4], dz = x[2] - z[5];
  if (dx * dx + dy * dy + dz * dz != value) self_check_failed("distance QP: value is not |x - y|^2");
  if (CGAL::is_zero(value)) self_check_failed("distance QP: zero distance for an outside volume");
  // Optimality, exactly: with KKT multipliers λ at y (y - x = Σ λ_j n_j over planes active at
  // y), P = Σ λ_j plane_j is >= 0 on F and P(y) = 0; if also max_B P = P(x) = -|y - x|^2, then
  // every b ∈ B, q ∈ F has (y - x)·(q - b) >= |y - x|^2, so |q - b| >= |y - x|.
  const std::array<Q, 3> y{z[3], z[4], z[5]};
  const auto lambda = kkt_multipliers(planes, y, x);
  if (!lambda) self_check_failed("distance QP: no KKT multipliers prove optimality");
  detail::Coeffs<Q> S{Q(0), Q(0), Q(0), Q(0)};
  for (int j = 0; j < 6; ++j)
    for (int k = 0; k < 4; ++k) S[k] += (*lambda)[j] * planes[j][k];
  Q max_b = S[0] * bq.c[0] + S[1] * bq.c[1] + S[2] * bq.c[2] + S[3];
  for (int e = 0; e < 3; ++e) max_b += CGAL::abs(S[0] * bq.e[e][0] + S[1] * bq.e[e][1] + S[2] * bq.e[e][2]);
  if (max_b != -value) self_check_failed("distance QP: the closest pair is not optimal");
  return value;
}

Decision exact_sphere(const Planes& P, QCase& qc, const Sphere& sp, std::optional<Q>& dist2) {
  Decision out;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j] && P.p[j][3] < 0) {
      std::array<Q, 6> l;
      l.fill(Q(0));
      l[j] = Q(1);
      out.lambda = l;
      return out;
    }
  }
  const std::array<ET, 3> c{et_of(sp.center.x), et_of(sp.center.y), et_of(sp.center.z)};
  const ET r = et_of(sp.radius);
  // Inside: every plane's signed distance at the centre is at least r:
  // s >= 0 and s^2 >= r^2 |n|^2, exactly.
  bool inside = true;
  for (int j = 0; j < 6 && inside; ++j) {
    if (P.degenerate[j]) continue;
    const auto& p = P.p[j];
    const ET s = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3];
    if (s < 0 || s * s < r * r * (p[0] * p[0] + p[1] * p[1] + p[2] * p[2])) inside = false;
  }
  if (inside) {
    out.truth = Visibility::inside;
    out.t_or_point = std::array<Q, 3>{q_of(c[0]), q_of(c[1]), q_of(c[2])};
    return out;
  }
  Closest cl = closest_point_of_frustum(qc, P, c);
  if (!cl.y) {  // F is empty
    out.lambda = cl.lambda;
    return out;
  }
  dist2 = cl.dist2;
  const Q rq = q_of(r);
  if (cl.dist2 <= rq * rq) {
    out.truth = Visibility::intersecting;
    out.t_or_point = *cl.y;
    return out;
  }
  // The KKT multipliers at y are the separation certificate: P = Σ λ_j plane_j has gradient
  // y - c and P(y) = 0, so P(c) = -|y - c|^2 and the ball lies strictly behind P.
  out.lambda = cl.lambda;
  return out;
}

// ---- interval filter --------------------------------------------------------------------------
// Everything below runs under Protect_FPU_rounding (rounding towards +infinity), as
// Interval_nt<false> requires. Doubles computed here (candidate points, multipliers) are only
// guesses; what decides is an interval bound on them, which is sound whatever the guess.

struct FilterAnswer {
  bool decided = false;
  Visibility truth = Visibility::outside;
  std::array<double, 6> lambda{};  // outside: Farkas multipliers
  std::array<double, 3> pt{};      // box: t of a point of B ∩ F; sphere: the point itself
};

bool solve3(const double A[3][3], const double rhs[3], double x[3]) {
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return false;
  for (int col = 0; col < 3; ++col) {
    double M[3][3];
    for (int r = 0; r < 3; ++r)
      for (int cc = 0; cc < 3; ++cc) M[r][cc] = cc == col ? rhs[r] : A[r][cc];
    const double dc = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                      M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                      M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
    x[col] = dc / det;
    if (!std::isfinite(x[col])) return false;
  }
  return true;
}

using IPlanes = std::array<detail::Coeffs<I>, 6>;

// Guesses of Farkas multipliers over plane pairs and triples: the combination whose gradient
// points from the volume's centre c towards the nearest point of the pair's edge line or the
// triple's vertex. `check(lambda)` decides with intervals.
template <class Check>
bool farkas_guesses(const IPlanes& P, const std::array<bool, 6>& active, const double c[3], Check check,
                    std::array<double, 6>& lambda_out) {
  double n[6][3], d[6];
  for (int j = 0; j < 6; ++j) {
    for (int k = 0; k < 3; ++k) n[j][k] = CGAL::to_double(P[j][k]);
    d[j] = CGAL::to_double(P[j][3]);
  }
  std::array<double, 6> lambda{};
  // Pairs: point p on the line {plane_j = 0, plane_k = 0} closest to c, then λ from the 2x2
  // normal equations of λ_j n_j + λ_k n_k = p - c.
  for (int j = 0; j < 6; ++j) {
    if (!active[j]) continue;
    for (int k = j + 1; k < 6; ++k) {
      if (!active[k]) continue;
      const double u[3] = {n[j][1] * n[k][2] - n[j][2] * n[k][1], n[j][2] * n[k][0] - n[j][0] * n[k][2],
                           n[j][0] * n[k][1] - n[j][1] * n[k][0]};
      const double A[3][3] = {{n[j][0], n[j][1], n[j][2]}, {n[k][0], n[k][1], n[k][2]}, {u[0], u[1], u[2]}};
      const double rhs[3] = {-d[j], -d[k], u[0] * c[0] + u[1] * c[1] + u[2] * c[2]};
      double p[3];
      if (!solve3(A, rhs, p)) continue;
      const double w[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
      const double gjj = n[j][0] * n[j][0] + n[j][1] * n[j][1] + n[j][2] * n[j][2];
      const double gkk = n[k][0] * n[k][0] + n[k][1] * n[k][1] + n[k][2] * n[k][2];
      const double gjk = n[j][0] * n[k][0] + n[j][1] * n[k][1] + n[j][2] * n[k][2];
      const double bj = n[j][0] * w[0] + n[j][1] * w[1] + n[j][2] * w[2];
      const double bk = n[k][0] * w[0] + n[k][1] * w[1] + n[k][2] * w[2];
      const double det = gjj * gkk - gjk * gjk;
      if (!(std::abs(det) > 0.0)) continue;
      lambda.fill(0.0);
      lambda[j] = std::max(0.0, (bj * gkk - bk * gjk) / det);
      lambda[k] = std::max(0.0, (gjj * bk - gjk * bj) / det);
      if (!(lambda[j] > 0.0 || lambda[k] > 0.0) || !std::isfinite(lambda[j]) || !std::isfinite(lambda[k])) continue;
      if (check(lambda)) {
        lambda_out = lambda;
        return true;
      }
    }
  }
  // Triples: vertex v of three planes, λ solving Σ λ_i n_i = v - c.
  for (int j = 0; j < 6; ++j) {
    if (!active[j]) continue;
    for (int k = j + 1; k < 6; ++k) {
      if (!active[k]) continue;
      for (int l = k + 1; l < 6; ++l) {
        if (!active[l]) continue;
        const int idx[3] = {j, k, l};
        double A[3][3], AT[3][3], rhs[3], v[3], lam[3];
        for (int r = 0; r < 3; ++r) {
          for (int cc = 0; cc < 3; ++cc) {
            A[r][cc] = n[idx[r]][cc];
            AT[cc][r] = n[idx[r]][cc];
          }
          rhs[r] = -d[idx[r]];
        }
        if (!solve3(A, rhs, v)) continue;
        const double w[3] = {v[0] - c[0], v[1] - c[1], v[2] - c[2]};
        if (!solve3(AT, w, lam)) continue;
        lambda.fill(0.0);
        bool any = false;
        for (int r = 0; r < 3; ++r) {
          lambda[idx[r]] = std::max(0.0, lam[r]);
          any = any || lam[r] > 0.0;
        }
        if (!any) continue;
        if (check(lambda)) {
          lambda_out = lambda;
          return true;
        }
      }
    }
  }
  return false;
}

// Degenerate planes in the filter: n == 0 is exact when all three intervals are the point 0
// (a sum of two floats is zero in floating point only when it is zero exactly).
enum class PlaneState { active, all_space, empty, unknown };
PlaneState plane_state(const detail::Coeffs<I>& p) {
  for (int k = 0; k < 3; ++k)
    if (!(p[k].is_point() && p[k].inf() == 0.0)) return PlaneState::active;
  if (p[3].sup() < 0.0) return PlaneState::empty;
  if (p[3].inf() >= 0.0) return PlaneState::all_space;
  return PlaneState::unknown;
}

FilterAnswer filter_box(const CaseFrustum& f, const Volume& v) {
  CGAL::Protect_FPU_rounding<true> guard;
  FilterAnswer out;
  auto conv = [](float x) { return I(static_cast<double>(x)); };
  const IPlanes P = detail::exact_planes<I>(f, conv);
  const detail::BoxT<I> b = detail::exact_box<I>(v, conv, I(0.5));
  std::array<bool, 6> active{};
  std::array<std::array<I, 4>, 6> a;
  bool all_in = true, some_out = false;
  for (int j = 0; j < 6; ++j) {
    const PlaneState st = plane_state(P[j]);
    if (st == PlaneState::empty) {
      out.decided = true;
      out.lambda[j] = 1.0;
      return out;
    }
    if (st == PlaneState::unknown) return out;
    if (st == PlaneState::all_space) continue;
    active[j] = true;
    const auto& p = P[j];
    a[j][0] = p[0] * b.c[0] + p[1] * b.c[1] + p[2] * b.c[2] + p[3];
    for (int i = 0; i < 3; ++i) a[j][i + 1] = p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2];
    const I spread = CGAL::abs(a[j][1]) + CGAL::abs(a[j][2]) + CGAL::abs(a[j][3]);
    const I hi = a[j][0] + spread, lo = a[j][0] - spread;
    if (hi.sup() < 0.0) {  // the whole box is behind plane j
      out.decided = true;
      out.lambda[j] = 1.0;
      return out;
    }
    if (!(lo.inf() >= 0.0)) all_in = false;
    if (lo.sup() < 0.0) some_out = true;
  }
  if (all_in) {  // every corner is certainly inside every plane
    out.decided = true;
    out.truth = Visibility::inside;
    return out;
  }
  auto in_frustum = [&](const double t[3]) {
    for (int j = 0; j < 6; ++j) {
      if (!active[j]) continue;
      const I g = a[j][0] + a[j][1] * t[0] + a[j][2] * t[1] + a[j][3] * t[2];
      if (!(g.inf() >= 0.0)) return false;
    }
    return true;
  };
  if (some_out) {
    // A point of B certainly in F proves "intersecting" (B is certainly not inside).
    for (int q = 0; q < 27; ++q) {
      const double t[3] = {double(q % 3 - 1), double(q / 3 % 3 - 1), double(q / 9 - 1)};
      if (in_frustum(t)) {
        out.decided = true;
        out.truth = Visibility::intersecting;
        out.pt = {t[0], t[1], t[2]};
        return out;
      }
    }
    // The mean of F's corners mapped into the box's parameters, clamped to [-1,1]^3.
    double corner_sum[3] = {0, 0, 0};
    bool bounded = true;
    for (int q = 0; q < 8 && bounded; ++q) {
      const int idx[3] = {q & 1 ? kRight : kLeft, q & 2 ? kTop : kBottom, q & 4 ? kFar : kNear};
      double A[3][3], rhs[3], x[3];
      for (int r = 0; r < 3; ++r) {
        for (int cc = 0; cc < 3; ++cc) A[r][cc] = CGAL::to_double(P[idx[r]][cc]);
        rhs[r] = -CGAL::to_double(P[idx[r]][3]);
      }
      bounded = solve3(A, rhs, x);
      for (int k = 0; k < 3; ++k) corner_sum[k] += x[k] / 8.0;
    }
    if (bounded) {
      double E[3][3], rhs[3], t[3];
      for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 3; ++i) E[k][i] = CGAL::to_double(b.e[i][k]);
        rhs[k] = corner_sum[k] - CGAL::to_double(b.c[k]);
      }
      if (solve3(E, rhs, t)) {
        for (double& ti : t) ti = std::clamp(ti, -1.0, 1.0);
        if (in_frustum(t)) {
          out.decided = true;
          out.truth = Visibility::intersecting;
          out.pt = {t[0], t[1], t[2]};
          return out;
        }
      }
    }
  }
  // Outside by a combination of two or three planes.
  const double c[3] = {CGAL::to_double(b.c[0]), CGAL::to_double(b.c[1]), CGAL::to_double(b.c[2])};
  auto separates = [&](const std::array<double, 6>& lambda) {
    I g[4] = {I(0), I(0), I(0), I(0)};
    for (int j = 0; j < 6; ++j) {
      if (lambda[j] == 0.0) continue;
      for (int k = 0; k < 4; ++k) g[k] += I(lambda[j]) * a[j][k];
    }
    return (g[0] + CGAL::abs(g[1]) + CGAL::abs(g[2]) + CGAL::abs(g[3])).sup() < 0.0;
  };
  if (farkas_guesses(P, active, c, separates, out.lambda)) {
    out.decided = true;
    return out;
  }
  return out;
}

FilterAnswer filter_sphere(const CaseFrustum& f, const Sphere& sp) {
  CGAL::Protect_FPU_rounding<true> guard;
  FilterAnswer out;
  auto conv = [](float x) { return I(static_cast<double>(x)); };
  const IPlanes P = detail::exact_planes<I>(f, conv);
  const I c[3] = {conv(sp.center.x), conv(sp.center.y), conv(sp.center.z)};
  const I r = conv(sp.radius);
  std::array<bool, 6> active{};
  std::array<I, 6> s;
  bool all_in = true, some_out = false, centre_in = true;
  for (int j = 0; j < 6; ++j) {
    const PlaneState st = plane_state(P[j]);
    if (st == PlaneState::empty) {
      out.decided = true;
      out.lambda[j] = 1.0;
      return out;
    }
    if (st == PlaneState::unknown) return out;
    if (st == PlaneState::all_space) continue;
    active[j] = true;
    const auto& p = P[j];
    s[j] = p[0] * c[0] + p[1] * c[1] + p[2] * c[2] + p[3];
    const I rl = r * CGAL::sqrt(CGAL::square(p[0]) + CGAL::square(p[1]) + CGAL::square(p[2]));
    if ((s[j] + rl).sup() < 0.0) {
      out.decided = true;
      out.lambda[j] = 1.0;
      return out;
    }
    const I lo = s[j] - rl;
    if (!(lo.inf() >= 0.0)) all_in = false;
    if (lo.sup() < 0.0) some_out = true;
    if (!(s[j].inf() >= 0.0)) centre_in = false;
  }
  if (all_in) {
    out.decided = true;
    out.truth = Visibility::inside;
    out.pt = {sp.center.x, sp.center.y, sp.center.z};
    return out;
  }
  auto point_in_both = [&](const double q[3]) {
    I dd(0);
    for (int k = 0; k < 3; ++k) dd += CGAL::square(I(q[k]) - c[k]);
    if (!((dd - r * r).sup() <= 0.0)) return false;
    for (int j = 0; j < 6; ++j) {
      if (!active[j]) continue;
      const auto& p = P[j];
      if (!((p[0] * q[0] + p[1] * q[1] + p[2] * q[2] + p[3]).inf() >= 0.0)) return false;
    }
    return true;
  };
  if (some_out) {
    if (centre_in) {
      out.decided = true;
      out.truth = Visibility::intersecting;
      out.pt = {sp.center.x, sp.center.y, sp.center.z};
      return out;
    }
    // The centre pushed just past each plane it violates.
    for (int j = 0; j < 6; ++j) {
      if (!active[j] || !(s[j].sup() < 0.0)) continue;
      double n[3];
      for (int k = 0; k < 3; ++k) n[k] = CGAL::to_double(P[j][k]);
      const double step = -CGAL::to_double(s[j]) / (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * (1.0 + 0x1p-20);
      const double q[3] = {sp.center.x + step * n[0], sp.center.y + step * n[1], sp.center.z + step * n[2]};
      if (point_in_both(q)) {
        out.decided = true;
        out.truth = Visibility::intersecting;
        out.pt = {q[0], q[1], q[2]};
        return out;
      }
    }
  }
  const double cd[3] = {sp.center.x, sp.center.y, sp.center.z};
  auto separates = [&](const std::array<double, 6>& lambda) {
    I g[4] = {I(0), I(0), I(0), I(0)};
    for (int j = 0; j < 6; ++j) {
      if (lambda[j] == 0.0) continue;
      for (int k = 0; k < 4; ++k) g[k] += I(lambda[j]) * P[j][k];
    }
    const I pc = g[0] * c[0] + g[1] * c[1] + g[2] * c[2] + g[3];
    return (pc + r * CGAL::sqrt(CGAL::square(g[0]) + CGAL::square(g[1]) + CGAL::square(g[2]))).sup() < 0.0;
  };
  if (farkas_guesses(P, active, cd, separates, out.lambda)) {
    out.decided = true;
    return out;
  }
  return out;
}

template <std::size_t N>
std::array<Q, N> q_array(const std::array<double, N>& a) {
  std::array<Q, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = Q(a[i]);
  return out;
}

}  // namespace

// ---- public API ---------------------------------------------------------------------------------

Result classify(const CaseFrustum& f, const Volume& v, const Options& o) {
  detail::validate_case(f, v);
  const Sphere* sphere = std::get_if<Sphere>(&v);
  Result r;
  r.distance = kNaN;

  std::optional<Decision> dec;
  if (o.filter) {
    g_calls.fetch_add(1, std::memory_order_relaxed);
    const FilterAnswer fa = sphere ? filter_sphere(f, *sphere) : filter_box(f, v);
    if (fa.decided) {
      g_filtered.fetch_add(1, std::memory_order_relaxed);
      r.filtered = true;
      Decision d;
      d.truth = fa.truth;
      if (fa.truth == Visibility::outside) d.lambda = q_array(fa.lambda);
      else d.t_or_point = q_array(fa.pt);
      dec = d;
    } else {
      g_fallbacks.fetch_add(1, std::memory_order_relaxed);
    }
  }

  QCase qc(f, v);
  std::optional<Planes> planes;
  auto exact = [&]() -> const Planes& {
    if (!planes) planes = exact_planes_et(f);
    return *planes;
  };
  std::optional<Q> sphere_dist2;
  const auto box_et = [&] { return detail::exact_box<ET>(v, [](float x) { return et_of(x); }, ET(0.5)); };
  if (!dec) {
    dec = sphere ? exact_sphere(exact(), qc, *sphere, sphere_dist2) : exact_box_route(exact(), box_et());
  }
  r.truth = dec->truth;

  // Certificates. The filter's were proved by its interval bounds; the exact route's are
  // checked here in Gmpq, in x-space. With witness_json, every certificate (filtered or not)
  // is re-checked exactly while it is written out.
  const bool check_exact = !r.filtered || o.witness_json;
  if (check_exact) {
    if (r.truth == Visibility::outside) {
      const auto P = check_separation(qc, *dec->lambda);
      if (o.witness_json) r.witness = separation_json(*dec->lambda, P);
    } else {
      std::array<Q, 3> x;
      if (sphere) {
        x = *dec->t_or_point;
        check_sphere_point(qc, *sphere, x);
      } else {
        x = check_box_point(qc, *dec->t_or_point);
      }
      if (o.witness_json) r.witness = point_json(x);
      if (r.truth == Visibility::intersecting) {
        const auto [plane, corner] = check_not_inside(qc);
        if (o.witness_json) {
          r.witness["violated_plane"] = plane;
          if (corner) r.witness["outside_corner"] = exact_vec(*corner);
        }
      }
    }
  }

  if (o.distance) {
    if (r.truth == Visibility::outside) {
      r.distance_kind = DistanceKind::euclidean;
      if (sphere) {
        if (!sphere_dist2 && !r.filtered) {
          // Exact route ended before the QP only when F is empty.
          r.distance = kInf;
        } else {
          if (!sphere_dist2) {
            const std::array<ET, 3> c{et_of(sphere->center.x), et_of(sphere->center.y), et_of(sphere->center.z)};
            const Closest cl = closest_point_of_frustum(qc, exact(), c);
            if (cl.y) sphere_dist2 = cl.dist2;
          }
          if (!sphere_dist2) {
            r.distance = kInf;
          } else {
            // dist(ball, F) = |y - c| - r = (|y-c|^2 - r^2) / (|y-c| + r), no cancellation.
            const Q rq = q_of(sphere->radius);
            const double num = approx(*sphere_dist2 - rq * rq);
            r.distance = num / (std::sqrt(approx(*sphere_dist2)) + double(sphere->radius));
          }
        }
      } else {
        const auto d2 = box_distance2(qc, exact(), box_et());
        r.distance = d2 ? std::sqrt(approx(*d2)) : kInf;
      }
    } else {
      set_margin_distance(r, sphere ? sphere_margins(exact(), *sphere) : box_margins(exact(), box_et()));
    }
  }
  return r;
}

Result classify(const CaseFrustum& f, const Volume& v) { return classify(f, v, Options{}); }

Visibility truth(const CaseFrustum& f, const Volume& v) {
  Options o;
  o.distance = false;
  o.witness_json = false;
  return classify(f, v, o).truth;
}

const char* to_string(DistanceKind k) noexcept {
  switch (k) {
    case DistanceKind::euclidean: return "euclidean";
    case DistanceKind::margin: return "margin";
    case DistanceKind::clearance: return "clearance";
    case DistanceKind::none: break;
  }
  return "none";
}

nlohmann::json to_json(const Result& r) {
  nlohmann::json j;
  j["truth"] = std::string(cullproof::to_string(r.truth));
  if (std::isfinite(r.distance)) j["distance"] = r.distance;
  else j["distance"] = nullptr;
  j["distance_kind"] = to_string(r.distance_kind);
  j["filtered"] = r.filtered;
  j["witness"] = r.witness.is_null() ? nlohmann::json::object() : r.witness;
  return j;
}

Stats stats() noexcept {
  Stats s;
  s.calls = g_calls.load(std::memory_order_relaxed);
  s.filtered = g_filtered.load(std::memory_order_relaxed);
  s.fallbacks = g_fallbacks.load(std::memory_order_relaxed);
  s.exact_lp = g_exact_lp.load(std::memory_order_relaxed);
  return s;
}

void reset_stats() noexcept {
  g_calls.store(0);
  g_filtered.store(0);
  g_fallbacks.store(0);
  g_exact_lp.store(0);
}

}  // namespace cullproof::oracle

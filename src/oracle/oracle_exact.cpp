// The oracle's exact route: feasibility LPs and closest-point QPs solved exactly with CGAL's QP
// solver over Gmpzf, each answer checked before it is returned.
//
// Source: B. Gärtner, S. Schönherr, "An efficient, exact, and generic quadratic programming
// solver for geometric optimization", SoCG 2000 (CGAL's QP solver, used with exact CGAL::Gmpzf).

#include "oracle_internal.hpp"

#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <cmath>
#include <vector>

namespace cullproof::oracle::internal {

std::atomic<std::uint64_t> g_exact_lp{0}, g_closest_pairs{0};

namespace {

using Program = CGAL::Quadratic_program<ET>;
using Solution = CGAL::Quadratic_program_solution<ET>;

// t-space coefficients g_j(t) = a_j0 + Σ a_ji t_i of plane j on the box.
std::array<ET, 4> box_coeffs(const detail::Coeffs<ET>& p, const detail::BoxT<ET>& b) {
  std::array<ET, 4> a;
  a[0] = p[0] * b.c[0] + p[1] * b.c[1] + p[2] * b.c[2] + p[3];
  for (int i = 0; i < 3; ++i) a[i + 1] = p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2];
  return a;
}

}  // namespace

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

namespace {
std::optional<std::array<Q, 6>> kkt_multipliers(const std::array<detail::Coeffs<Q>, 6>& planes,
                                                const std::array<Q, 3>& y, const std::array<Q, 3>& x);
}  // namespace

Closest closest_point_of_frustum(QCase& qc, const Planes& P, const std::array<ET, 3>& c) {
  // The pair found in double, when proven (the same conditions as the checks below).
  if (qc.guess) {
    detail::BoxT<ET> b;
    b.c = c;
    for (auto& ei : b.e) ei = {ET(0), ET(0), ET(0)};
    if (auto pair = proven_closest_pair(P, b, /*want_point=*/true)) {
      g_closest_pairs.fetch_add(1, std::memory_order_relaxed);
      Closest out;
      out.y = pair->y;
      out.dist2 = pair->dist2;
      out.lambda = pair->lambda;
      return out;
    }
  }
  const std::array<Q, 3> cq{q_of(c[0]), q_of(c[1]), q_of(c[2])};
  const auto& planes = qc.planes();
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
  for (int j = 0; j < 6; ++j) {
    const auto& p = planes[j];
    if (p[0] * y[0] + p[1] * y[1] + p[2] * y[2] + p[3] < 0) self_check_failed("closest-point QP: y outside F");
  }
  const Q dx = y[0] - cq[0], dy = y[1] - cq[1], dz = y[2] - cq[2];
  if (dx * dx + dy * dy + dz * dz != out.dist2) self_check_failed("closest-point QP: value is not |y - c|^2");
  if (!CGAL::is_zero(out.dist2)) {
    const auto kkt = kkt_multipliers(planes, y, cq);
    if (!kkt) self_check_failed("closest-point QP: no KKT multipliers prove optimality");
    out.lambda = *kkt;
  }
  return out;
}

namespace {

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

}  // namespace

namespace {

// The squared distance of the pair (x = c + Σ t_i e_i, y) when the pair is proven the closest of
// B and F, else the check that fails. λ are KKT multipliers at y (y - x = Σ λ_j n_j over planes
// through y, λ >= 0): then P = Σ λ_j plane_j is >= 0 on F with P(y) = 0, and if also
// max_B P = P(x) = -|y - x|^2, every b ∈ B, q ∈ F has (y - x)·(q - b) >= |y - x|^2, so
// |q - b| >= |y - x|.
struct PairCheck {
  std::optional<Q> value;
  const char* problem = nullptr;
};

PairCheck check_pair(QCase& qc, const std::array<Q, 3>& t, const std::array<Q, 3>& y) {
  const auto& planes = qc.planes();
  const auto& bq = qc.box();
  std::array<Q, 3> x;
  for (std::size_t k = 0; k < 3; ++k) {
    if (t[k] > Q(1) || t[k] < Q(-1)) return {std::nullopt, "t outside [-1,1]"};
    x[k] = bq.c[k] + t[0] * bq.e[0][k] + t[1] * bq.e[1][k] + t[2] * bq.e[2][k];
  }
  for (const auto& p : planes)
    if (p[0] * y[0] + p[1] * y[1] + p[2] * y[2] + p[3] < 0) return {std::nullopt, "y outside F"};
  const Q dx = x[0] - y[0], dy = x[1] - y[1], dz = x[2] - y[2];
  const Q value = dx * dx + dy * dy + dz * dz;
  if (CGAL::is_zero(value)) return {std::nullopt, "zero distance for an outside volume"};
  const auto lambda = kkt_multipliers(planes, y, x);
  if (!lambda) return {std::nullopt, "no KKT multipliers prove optimality"};
  detail::Coeffs<Q> S{Q(0), Q(0), Q(0), Q(0)};
  for (std::size_t j = 0; j < 6; ++j)
    for (std::size_t k = 0; k < 4; ++k) S[k] += (*lambda)[j] * planes[j][k];
  Q max_b = S[0] * bq.c[0] + S[1] * bq.c[1] + S[2] * bq.c[2] + S[3];
  for (std::size_t e = 0; e < 3; ++e) max_b += CGAL::abs(S[0] * bq.e[e][0] + S[1] * bq.e[e][1] + S[2] * bq.e[e][2]);
  if (max_b != -value) return {std::nullopt, "the closest pair is not optimal"};
  return {value, nullptr};
}

}  // namespace

// Euclidean distance between a box and F: the pair found in double when it is proven the closest
// (proven_closest_pair), else the exact QP
//   min |c + E t - y|^2  over t ∈ [-1,1]^3, y ∈ F,
// whose optimum is checked the same way. Returns the exact squared distance (nullopt when F is
// empty).
std::optional<Q> box_distance2(QCase& qc, const Planes& P, const detail::BoxT<ET>& b) {
  if (qc.guess)
    if (auto pair = proven_closest_pair(P, b, /*want_point=*/false)) {
      g_closest_pairs.fetch_add(1, std::memory_order_relaxed);
      return pair->dist2;
    }
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
  const PairCheck c = check_pair(qc, {z[0], z[1], z[2]}, {z[3], z[4], z[5]});
  if (!c.value) self_check_failed(std::string("distance QP: ") + c.problem);
  if (*c.value != q_of(s.objective_value())) self_check_failed("distance QP: value is not |x - y|^2");
  return c.value;
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

}  // namespace cullproof::oracle::internal

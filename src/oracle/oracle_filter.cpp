// The oracle's interval filter: decides a case only when interval bounds, rounded outward,
// prove the answer (a point of B ∩ F, Farkas multipliers, or B inside every plane).
//
// Sources:
//  - H. Brönnimann, C. Burnikel, S. Pion, "Interval arithmetic yields efficient dynamic
//    filters for computational geometry", 1998 (CGAL::Interval_nt, Protect_FPU_rounding).
//  - Farkas' lemma for a box-constrained system: {t ∈ [-1,1]^3 : g_j(t) >= 0} is empty iff some
//    λ >= 0 gives max_{t ∈ [-1,1]^3} Σ λ_j g_j(t) < 0 (LP duality / minimax on compact sets).

#include "oracle_internal.hpp"

#include <cmath>

namespace cullproof::oracle::internal {

// Everything below runs under Protect_FPU_rounding (rounding towards +infinity), as
// Interval_nt<false> requires. Doubles computed here (candidate points, multipliers) are only
// guesses; what decides is an interval bound on them, which is sound whatever the guess.

namespace {

// A 3x3 linear system by Cramer's rule, for the guesses below (a vertex of three planes, the foot
// of an edge line, multipliers, a point in an OBB's axes): only finiteness matters, since
// intervals prove or refute each guess after. A witness records the multipliers these guesses
// give, so they stay with this solver rather than planes_meet (whose cut-off refuses near-parallel
// planes: a sound answer for a vertex, a different guess here).
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

// plane_state of plane j, an empty plane recorded in `out` as deciding outside (lambda_j = 1):
// the filter ends on an empty or undecided plane and skips an all-space one.
PlaneState enter_plane(const detail::Coeffs<I>& p, int j, FilterAnswer& out) {
  const PlaneState st = plane_state(p);
  if (st == PlaneState::empty) {
    out.decided = true;
    out.lambda[j] = 1.0;
  }
  return st;
}

}  // namespace

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
    const PlaneState st = enter_plane(P[j], j, out);
    if (st == PlaneState::empty || st == PlaneState::unknown) return out;
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
    const PlaneState st = enter_plane(P[j], j, out);
    if (st == PlaneState::empty || st == PlaneState::unknown) return out;
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

}  // namespace cullproof::oracle::internal

// How far a verdict lies from being the truth (cullproof/oracle/oracle.hpp, VerdictShift): the shift of
// every frustum plane, in distance units, that makes the verdict given the truth, bounded from
// below by exact certificates.
//
// Boxes (and OBBs and points) are parallelepipeds c + Σ t_i e_i, |t_i| <= 1, so the protrusion and
// the clearance are corner values a_j0 ∓ Σ_i |a_ji| (exact) over |n_j|, and the depth is the LP
//   max μ  subject to  a_j0 + Σ_i a_ji t_i >= μ w_j,  t ∈ [-1, 1]^3,
// solved exactly by CGAL's QP solver with w_j >= |n_j| rounded up: scaling every w_j by (1 + ε)
// scales the optimum by 1 / (1 + ε), so the optimum moves toward zero and is a lower bound on
// |depth| whichever its sign. Balls: the depth max_{|y - c| <= r} min_j s_j(y) is a small convex
// program, solved approximately in double over its active sets; its answer is then certified, a
// point of the ball bounding the depth from below and multipliers λ >= 0 (Σ λ_j s_j is at least
// the minimum, and its maximum over the ball is Σ λ_j s_j(c) + r |Σ λ_j n_j/|n_j||) from above.

#include "oracle_internal.hpp"

#include <CGAL/FPU.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cullproof::oracle {

namespace internal {
namespace {

using Program = CGAL::Quadratic_program<ET>;
using Solution = CGAL::Quadratic_program_solution<ET>;

// A non-degenerate plane in exact numbers with |n| as an interval.
struct NPlane {
  detail::Coeffs<ET> p;
  I len;  // encloses |n|
};

// A zero is [0, 0]: CGAL's interval of a Gmpzf widens its mantissa by 2^-53 at the number's own
// exponent, which for zero is 0, giving [0, 2^-53]; beside a plane whose |n| is near 1e-16 that is
// as wide as the plane itself.
I iv(const ET& x) { return CGAL::is_zero(x) ? I(0) : I(CGAL::to_interval(x)); }
I iv(const Q& x) { return I(CGAL::to_interval(x)); }

// The double of an interval's end nearer zero: a lower bound on |x| with x's sign.
double toward_zero(const I& x) { return x.inf() >= 0.0 ? x.inf() : x.sup() <= 0.0 ? x.sup() : 0.0; }

// ---- boxes, OBBs and points ---------------------------------------------------------------------

struct BoxRows {
  std::vector<std::array<ET, 4>> a;  // a_j0, a_j1..3 per plane
  std::vector<ET> lo;                // min over B of n_j·x + d_j (a corner value)
};

BoxRows box_rows(const std::vector<NPlane>& planes, const detail::BoxT<ET>& b) {
  BoxRows out;
  for (const NPlane& q : planes) {
    const auto& p = q.p;
    std::array<ET, 4> a;
    a[0] = p[0] * b.c[0] + p[1] * b.c[1] + p[2] * b.c[2] + p[3];
    for (int i = 0; i < 3; ++i) a[i + 1] = p[0] * b.e[i][0] + p[1] * b.e[i][1] + p[2] * b.e[i][2];
    out.lo.push_back(a[0] - CGAL::abs(a[1]) - CGAL::abs(a[2]) - CGAL::abs(a[3]));
    out.a.push_back(a);
  }
  return out;
}

// The depth's LP with w_j = the upper end of |n_j|'s interval; its optimum as an exact rational.
Q box_depth_lp(const std::vector<NPlane>& planes, const BoxRows& rows) {
  Program lp(CGAL::LARGER, true, -1, true, 1);
  lp.set_l(3, false);
  lp.set_u(3, false);
  for (std::size_t j = 0; j < planes.size(); ++j) {
    const int row = int(j);
    for (int i = 0; i < 3; ++i)
      if (!CGAL::is_zero(rows.a[j][std::size_t(i) + 1])) lp.set_a(i, row, rows.a[j][std::size_t(i) + 1]);
    lp.set_a(3, row, -ET(planes[j].len.sup()));
    lp.set_b(row, -rows.a[j][0]);
  }
  lp.set_c(3, ET(-1));  // minimise -μ
  g_exact_lp.fetch_add(1, std::memory_order_relaxed);
  const Solution s = CGAL::solve_quadratic_program(lp, ET());
  if (!s.is_optimal()) self_check_failed("depth LP not optimal");
  return -q_of(s.objective_value());
}

// ---- balls ---------------------------------------------------------------------------------------

// The ball's planes in double: unit normals u_j and centre values b_j = s_j(c).
struct BallPlanes {
  std::vector<glm::dvec3> u;
  std::vector<double> b;
};

double value_at(const BallPlanes& bp, const glm::dvec3& z) {
  double v = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < bp.u.size(); ++j) v = std::min(v, bp.b[j] + glm::dot(bp.u[j], z));
  return v;
}

// Solves the small symmetric system G x = y (n <= 3) by Gaussian elimination with pivoting;
// false when it is singular.
template <int N>
bool solve(std::array<std::array<double, N>, N> g, std::array<double, N> y, std::array<double, N>& x) {
  for (int col = 0; col < N; ++col) {
    int piv = col;
    for (int r = col + 1; r < N; ++r)
      if (std::abs(g[r][col]) > std::abs(g[piv][col])) piv = r;
    if (!(std::abs(g[piv][col]) > 1e-300)) return false;
    std::swap(g[col], g[piv]);
    std::swap(y[col], y[piv]);
    for (int r = col + 1; r < N; ++r) {
      const double f = g[r][col] / g[col][col];
      for (int k = col; k < N; ++k) g[r][k] -= f * g[col][k];
      y[r] -= f * y[col];
    }
  }
  for (int r = N - 1; r >= 0; --r) {
    double s = y[r];
    for (int k = r + 1; k < N; ++k) s -= g[r][k] * x[k];
    x[r] = s / g[r][r];
  }
  return true;
}

// A candidate optimum of max_{|z| <= r} min_j (b_j + u_j·z): the planes it makes equal.
struct Candidate {
  glm::dvec3 z{0.0};
  std::vector<std::size_t> active;
  double value = -std::numeric_limits<double>::infinity();
};

// The point of {z : (u_j0 - u_jk)·z = b_jk - b_j0 for k >= 1, |z| <= r} that maximises u_j0·z.
std::optional<glm::dvec3> on_sphere(const BallPlanes& bp, const std::vector<std::size_t>& js, double r) {
  const glm::dvec3 u = bp.u[js[0]];
  std::vector<glm::dvec3> m;
  std::vector<double> beta;
  for (std::size_t k = 1; k < js.size(); ++k) {
    m.push_back(u - bp.u[js[k]]);
    beta.push_back(bp.b[js[k]] - bp.b[js[0]]);
  }
  glm::dvec3 z0(0.0), un = u;
  if (m.size() == 1) {
    const double mm = glm::dot(m[0], m[0]);
    if (!(mm > 0.0)) return std::nullopt;
    z0 = m[0] * (beta[0] / mm);
    un = u - m[0] * (glm::dot(u, m[0]) / mm);
  } else if (m.size() == 2) {
    std::array<std::array<double, 2>, 2> g{{{glm::dot(m[0], m[0]), glm::dot(m[0], m[1])},
                                            {glm::dot(m[1], m[0]), glm::dot(m[1], m[1])}}};
    std::array<double, 2> x{}, xu{};
    if (!solve<2>(g, {beta[0], beta[1]}, x) || !solve<2>(g, {glm::dot(u, m[0]), glm::dot(u, m[1])}, xu)) return std::nullopt;
    z0 = m[0] * x[0] + m[1] * x[1];
    un = u - (m[0] * xu[0] + m[1] * xu[1]);
  }
  const double rest = r * r - glm::dot(z0, z0);
  if (rest < 0.0) return std::nullopt;
  // u_j0 constant on the subspace (up to rounding): every point of it in the ball is as good.
  const double nn = glm::length(un);
  return nn > 1e-9 ? z0 + un * (std::sqrt(rest) / nn) : z0;
}

// The interior point where four planes are equal, if it lies in the ball.
std::optional<glm::dvec3> interior(const BallPlanes& bp, const std::vector<std::size_t>& js, double r) {
  // (u_j0 - u_jk)·z = b_jk - b_j0, k = 1..3.
  std::array<std::array<double, 3>, 3> g{};
  std::array<double, 3> y{}, x{};
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 row = bp.u[js[0]] - bp.u[js[std::size_t(k) + 1]];
    g[k] = {row.x, row.y, row.z};
    y[k] = bp.b[js[std::size_t(k) + 1]] - bp.b[js[0]];
  }
  if (!solve<3>(g, y, x)) return std::nullopt;
  const glm::dvec3 z(x[0], x[1], x[2]);
  if (glm::dot(z, z) > r * r) return std::nullopt;
  return z;
}

Candidate best_candidate(const BallPlanes& bp, double r) {
  const std::size_t n = bp.u.size();
  Candidate best;
  auto offer = [&](std::optional<glm::dvec3> z, std::vector<std::size_t> js) {
    if (!z) return;
    const double v = value_at(bp, *z);
    if (v > best.value) best = Candidate{*z, std::move(js), v};
  };
  offer(glm::dvec3(0.0), {});
  for (std::size_t a = 0; a < n; ++a) {
    offer(on_sphere(bp, {a}, r), {a});
    for (std::size_t b = a + 1; b < n; ++b) {
      offer(on_sphere(bp, {a, b}, r), {a, b});
      for (std::size_t c = b + 1; c < n; ++c) {
        offer(on_sphere(bp, {a, b, c}, r), {a, b, c});
        for (std::size_t d = c + 1; d < n; ++d) offer(interior(bp, {a, b, c, d}, r), {a, b, c, d});
      }
    }
  }
  return best;
}

// Multipliers for the candidate's active planes from its optimality conditions: Σ λ_j u_j = κ z
// (z on the sphere) or 0 (inside it), Σ λ_j = 1; negatives clipped. Any λ >= 0 gives a valid
// bound; these make it tight.
std::vector<double> kkt_lambda(const BallPlanes& bp, const Candidate& c, double r) {
  std::vector<double> lambda(bp.u.size(), 0.0);
  const std::size_t k = c.active.size();
  if (k == 0) return lambda;
  if (k == 1) {
    lambda[c.active[0]] = 1.0;
    return lambda;
  }
  // Least squares in the columns u_j (and -z/r on the sphere) with the row Σ λ_j = 1 weighted.
  std::vector<std::array<double, 4>> cols;
  for (std::size_t j : c.active) cols.push_back({bp.u[j].x, bp.u[j].y, bp.u[j].z, 1.0});
  const bool on = k < 4 && r > 0.0;
  if (on) cols.push_back({-c.z.x / r, -c.z.y / r, -c.z.z / r, 0.0});
  const std::array<double, 4> rhs{0.0, 0.0, 0.0, 1.0};
  std::vector<double> x(cols.size(), 0.0);
  auto normal = [&](auto dim) {
    constexpr int N = decltype(dim)::value;
    std::array<std::array<double, N>, N> g{};
    std::array<double, N> y{}, sol{};
    for (int a = 0; a < N; ++a) {
      for (int b = 0; b < N; ++b)
        for (int e = 0; e < 4; ++e) g[a][b] += cols[std::size_t(a)][std::size_t(e)] * cols[std::size_t(b)][std::size_t(e)];
      for (int e = 0; e < 4; ++e) y[a] += cols[std::size_t(a)][std::size_t(e)] * rhs[std::size_t(e)];
    }
    if (!solve<N>(g, y, sol)) return false;
    for (int a = 0; a < N; ++a) x[std::size_t(a)] = sol[std::size_t(a)];
    return true;
  };
  bool ok = false;
  switch (cols.size()) {
    case 2: ok = normal(std::integral_constant<int, 2>{}); break;
    case 3: ok = normal(std::integral_constant<int, 3>{}); break;
    case 4: ok = normal(std::integral_constant<int, 4>{}); break;
    default: break;
  }
  if (!ok) return lambda;
  for (std::size_t i = 0; i < k; ++i) lambda[c.active[i]] = std::max(0.0, x[i]);
  return lambda;
}

// Certified: a lower bound on min_j s_j(c + z) for the point c + z shrunk into the ball.
std::optional<double> primal_bound(const std::vector<NPlane>& planes, const std::array<ET, 3>& c, glm::dvec3 z, float radius) {
  const ET r2 = ET(double(radius)) * ET(double(radius));
  for (int tries = 0; tries < 8; ++tries) {
    const ET z2 = ET(z.x) * ET(z.x) + ET(z.y) * ET(z.y) + ET(z.z) * ET(z.z);
    if (z2 <= r2) break;
    z *= 1.0 - 0x1p-40 * double(1 << tries * 3);
    if (tries == 7) z = glm::dvec3(0.0);
  }
  const std::array<ET, 3> y{c[0] + ET(z.x), c[1] + ET(z.y), c[2] + ET(z.z)};
  CGAL::Protect_FPU_rounding<true> guard;
  double lo = std::numeric_limits<double>::infinity();
  for (const NPlane& q : planes) {
    const ET a = q.p[0] * y[0] + q.p[1] * y[1] + q.p[2] * y[2] + q.p[3];
    lo = std::min(lo, (iv(a) / q.len).inf());
  }
  return lo;
}

// Certified: an upper bound on the depth from multipliers λ >= 0 (not all zero).
std::optional<double> dual_bound(const std::vector<NPlane>& planes, const std::vector<ET>& centre_values, float radius,
                                 const std::vector<double>& lambda) {
  CGAL::Protect_FPU_rounding<true> guard;
  I sum(0), total(0), g[3] = {I(0), I(0), I(0)};
  for (std::size_t j = 0; j < planes.size(); ++j) {
    if (!(lambda[j] > 0.0)) continue;
    const I l(lambda[j]);
    total += l;
    sum += l * (iv(centre_values[j]) / planes[j].len);
    for (int i = 0; i < 3; ++i) g[i] += l * (iv(planes[j].p[std::size_t(i)]) / planes[j].len);
  }
  if (!(total.inf() > 0.0)) return std::nullopt;
  const I norm = CGAL::sqrt(CGAL::square(g[0]) + CGAL::square(g[1]) + CGAL::square(g[2]));
  return ((sum + I(double(radius)) * norm) / total).sup();
}

}  // namespace

VerdictDistance verdict_distance(const CaseFrustum& f, const Volume& v, Visibility verdict) {
  VerdictDistance out;
  out.truth = truth(f, v);  // validates the input
  if (verdict == out.truth) return out;
  switch (verdict) {
    case Visibility::outside: out.shift = VerdictShift::to_outside; break;
    case Visibility::inside: out.shift = VerdictShift::to_inside; break;
    case Visibility::intersecting:
      out.shift = out.truth == Visibility::outside ? VerdictShift::to_meeting : VerdictShift::to_leaving;
      break;
  }
  const Planes P = exact_planes_et(f);
  std::vector<NPlane> planes;
  for (int j = 0; j < 6; ++j) {
    if (P.degenerate[j]) {
      // A plane holding nothing: no shift of the others makes B meet F.
      if (P.p[std::size_t(j)][3] < 0) {
        out.distance = kInf;
        return out;
      }
      continue;  // all space
    }
    const auto& p = P.p[std::size_t(j)];
    CGAL::Protect_FPU_rounding<true> guard;
    planes.push_back(NPlane{p, CGAL::sqrt(iv(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]))});
  }
  if (planes.empty()) {  // F is all space: B stays inside whatever moves
    out.distance = kInf;
    return out;
  }

  if (const Sphere* sp = std::get_if<Sphere>(&v)) {
    const std::array<ET, 3> c{et_of(sp->center.x), et_of(sp->center.y), et_of(sp->center.z)};
    std::vector<ET> cv;
    for (const NPlane& q : planes) cv.push_back(q.p[0] * c[0] + q.p[1] * c[1] + q.p[2] * c[2] + q.p[3]);
    const I r(double(sp->radius));
    if (out.shift == VerdictShift::to_inside || out.shift == VerdictShift::to_leaving) {
      CGAL::Protect_FPU_rounding<true> guard;
      // protrusion max_j (r - s_j(c)); clearance min_j (s_j(c) - r)
      double best = out.shift == VerdictShift::to_inside ? -kInf : kInf;
      for (std::size_t j = 0; j < planes.size(); ++j) {
        const I s = iv(cv[j]) / planes[j].len;
        if (out.shift == VerdictShift::to_inside) best = std::max(best, (r - s).inf());
        else best = std::min(best, (s - r).inf());
      }
      out.distance = std::max(0.0, best);
      return out;
    }
    // The depth, through certificates of a near-optimal solution found in double.
    BallPlanes bp;
    for (std::size_t j = 0; j < planes.size(); ++j) {
      const auto& p = planes[j].p;
      const glm::dvec3 n(approx(p[0]), approx(p[1]), approx(p[2]));
      const double len = glm::length(n);
      bp.u.push_back(n / len);
      bp.b.push_back(approx(cv[j]) / len);
    }
    const double rd = sp->radius;
    const Candidate best = best_candidate(bp, rd);
    if (out.shift == VerdictShift::to_outside) {
      out.distance = std::max(0.0, primal_bound(planes, c, best.z, sp->radius).value_or(0.0));
    } else {  // to_meeting: the depth is negative; bound it from above
      double lo = 0.0;
      std::vector<std::vector<double>> tries{kkt_lambda(bp, best, rd)};
      for (std::size_t j = 0; j < planes.size(); ++j) {
        std::vector<double> e(planes.size(), 0.0);
        e[j] = 1.0;
        tries.push_back(e);
      }
      for (const auto& l : tries)
        if (auto up = dual_bound(planes, cv, sp->radius, l)) lo = std::max(lo, -*up);
      out.distance = lo;
    }
    return out;
  }

  const detail::BoxT<ET> b = detail::exact_box<ET>(v, [](float x) { return et_of(x); }, ET(0.5));
  const BoxRows rows = box_rows(planes, b);
  if (out.shift == VerdictShift::to_inside || out.shift == VerdictShift::to_leaving) {
    CGAL::Protect_FPU_rounding<true> guard;
    double best = out.shift == VerdictShift::to_inside ? -kInf : kInf;
    for (std::size_t j = 0; j < planes.size(); ++j) {
      const I s = iv(rows.lo[j]) / planes[j].len;  // min over B of s_j
      if (out.shift == VerdictShift::to_inside) best = std::max(best, (-s).inf());
      else best = std::min(best, s.inf());
    }
    out.distance = std::max(0.0, best);
    return out;
  }
  bool point = true;
  for (const auto& e : b.e)
    for (const ET& x : e) point = point && CGAL::is_zero(x);
  I depth;
  if (point) {  // min_j s_j(c), directly
    CGAL::Protect_FPU_rounding<true> guard;
    depth = iv(rows.a[0][0]) / planes[0].len;  // an interval holds no infinity: start from a plane
    for (std::size_t j = 1; j < planes.size(); ++j) depth = CGAL::min(depth, iv(rows.a[j][0]) / planes[j].len);
  } else {
    depth = iv(box_depth_lp(planes, rows));
  }
  const double d = toward_zero(depth);
  out.distance = std::max(0.0, out.shift == VerdictShift::to_outside ? d : -d);
  return out;
}

}  // namespace internal

VerdictDistance distance_to_verdict(const CaseFrustum& f, const Volume& v, Visibility verdict) {
  return internal::verdict_distance(f, v, verdict);
}

std::string_view to_string(VerdictShift s) noexcept {
  switch (s) {
    case VerdictShift::to_outside: return "depth";
    case VerdictShift::to_inside: return "protrusion";
    case VerdictShift::to_meeting: return "gap";
    case VerdictShift::to_leaving: return "clearance";
    case VerdictShift::none: break;
  }
  return "none";
}

}  // namespace cullproof::oracle

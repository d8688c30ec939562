// Certified-exact culling: the cascade of cullproof/exact_certified.hpp. Claim: certified-exact,
// error band zero (the verdict is the exact truth on every valid float input).
//
// Sources: the n/p-vertex test, Assarsson & Möller, "Optimized View Frustum Culling Algorithms
// for Bounding Boxes", 2000, §3.1; separating axes, Gottschalk, Lin & Manocha, "OBBTree", 1996,
// §4, here as their dual: Farkas' lemma (a box and an intersection of half-spaces are disjoint iff
// a non-negative combination of the half-spaces excludes the whole box); the error analysis is
// the standard model (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., §2.2,
// §3.1, §3.5); the exact stage is exact_decide.cpp.
//
// ---- The error model ----------------------------------------------------------------------------
// All stages compute in double, u = 2^-53, gamma_k = k u / (1 - k u). Inputs are floats (at most
// 2^128 in magnitude, at least 2^-149 when not zero); plane coefficients are sums of two floats,
// rounded once to double: n^ = fl(n), |n^ - n| <= u |n^| (Higham (2.5)) and n^ == 0 iff n == 0.
// Each plane is scaled by 2^-e with e = ilogb(sum |n^_i|): exact (the results stay within
// [2^-300, 2^300]). A product of a float and such a double, any sum of a few of them, and every
// bound below lies in [2^-700, 2^400] or is zero: doubles neither overflow nor underflow, and the
// standard model holds without its underflow term. Every bound holds whatever the order of
// evaluation and whether or not a multiply-add is fused (a fused operation rounds once instead of
// twice; the gamma_k of a sum of k terms covers both).
//
// ---- Stage 1: planes ----------------------------------------------------------------------------
// Boxes (AABB). For scaled plane (n', d') and a float point p with |p_i| <= M, the computed
// v = fl(n'.p + D) (D = d_out or d_in, the offset with the constant part of the margin folded in)
// satisfies |v - (n'.p + D)| <= gamma_4 (A' M + |D|) (Higham (3.4)), and the true scaled plane
// S' = n.p 2^-e + d 2^-e satisfies |n'.p + d' - S'| <= u (A' M + |d'|). With
// d_out >= d' + delta, d_in <= d' - delta, delta = kBox u |d'|, T = fl(t_box M) >= 8 u (1 - u) A' M:
//   v(d_out) < -T  =>  S' <= v + gamma_4 (A' M + |d'| + 2 delta) + u (A' M + |d'|) - delta < 0,
// since T >= (gamma_4 + u) A' M and delta (1 - gamma_4) >= (gamma_4 (1 + 2^-40) + u) |d'|; the
// inside test v(d_in) >= T => S' > 0 is the mirror image. kBox = 8 > 5.0001 needed.
// At the p-vertex: v(d_out) < -T proves the box outside the plane; v(d_in) >= T proves the p-vertex
// inside it. At the n-vertex: v(d_in) >= T proves the box inside the plane, v(d_out) < -T proves it
// crosses the plane. The p- and n-vertices are chosen by the sign of n'_i, which is that of the
// true n_i (a rounded value has the sign of the exact one, and is zero only when that is zero).
// A box that lies in every plane but one, k, and crosses k with its p-vertex inside k meets the
// frustum at that p-vertex: intersecting.
//
// Spheres. v_out = fl(n'.c + d_out + rho), v_in = fl(n'.c + d_in - rho), rho = fl(r norm'):
// |norm' - |n 2^-e|| <= 3.501 u norm' (a sum of three squares, gamma_3, a square root, u, and
// ||n'| - |n 2^-e|| <= u |n'|), so |rho - r |n 2^-e|| <= 4.502 u r norm' (1 + u) and norm' <= 1.00001 A'.
// The five-term sum rounds by gamma_5 (A' M + |D| + rho). In all the error is at most
// 6.0001 u A' M + 9.503 u A' r + 6.0001 u |d'|, covered by T = fl(t_sphere fl(M + r)) with
// t_sphere = kSphere u max A' (kSphere = 16 > 9.503 / (1 - u)^3) and delta = kSphereOffset u |d'|
// (8 > 6.0001 / (1 - gamma_5)). The centre alone is inside plane k when fl(n'.c + d_in) >= T
// (the same bound with r = 0).
//
// OBBs and stage 2 rows. A box is c + sum t_i e_i, t in [-1,1]^3; plane j on it is the row
// g_j(t) = a_j0 + sum a_ji t_i. AABB: c = (lo + hi) / 2, e_i = (hi_i - lo_i) / 2 along axis i, each
// computed with one rounding (relative u): |a^_j0 - a_j0| <= (gamma_4 + 2 u + u^2)(A' M_c + |d'|),
// |a^_ji - a_ji| <= 3.0001 u |n'_i| h_i. OBB: a^_j0 = fl(n'.c + d'), within 5.0001 u (A' M_c + |d'|);
// a^_ji = fl(h_i fl(n'.u_i)), within (gamma_3 + u + u (1 + gamma_3)) h_i A' U_i <= 5.0002 u h_i A' U_i
// (U_i = max_k |u_ik|). Evaluating fl(a^_j0 + sum a^_ji t_i) at |t_i| <= 1 adds gamma_4
// (|a^_j0| + sum |a^_ji|). With W_j = A'_j X + |d'_j| (X = M_c + h_max for an AABB, M_c + sum h_i U_i
// for an OBB) bounding |a_j0| + sum |a_ji|, the total is at most 14.01 u W_j (OBB; 13.03 u for an
// AABB): eps_j = kRow u W_j (1 + kSlack), kRow = 16, bounds |fl(g^_j(t)) - g_j(t)| on the whole cube.
// So g^_j(t) >= eps_j proves g_j(t) >= 0, min_t g^_j = fl(a^_j0 - sum |a^_ji|) >= eps_j proves the
// box inside plane j and < -eps_j that it crosses it; max_t g^_j >= eps_j or < -eps_j likewise.
//
// ---- Stage 2: axes ----------------------------------------------------------------------------
// Let J be the planes that stage 1 could not prove to hold the whole volume. Every other plane
// holds it, so the volume meets the frustum iff it meets the intersection P_J of the planes in J.
// Boxes: P_J meets the box iff max over t in the cube of min_j g_j(t) / w_j >= 0 (w_j = eps_j > 0).
// That is a linear programme in (t, s): maximise s subject to g_j(t) >= s w_j, |t_i| <= 1, solved
// in double by the simplex method (max_min_lp: any answer is only a candidate). Its optimum s* is
// also min over lambda >= 0, sum lambda_j w_j = 1 of psi(lambda) = sum lambda_j a_j0 + sum_i
// |sum_j lambda_j a_ji| (LP duality), the maximum over the box of the combined plane
// sum lambda_j (n_j, d_j): a separating axis made of the frustum's planes.
//  - Witness: a t (clamped to the cube, so that c + sum t_i e_i is in the box exactly) with
//    fl(g^_j(t)) >= eps_j for every j in J proves the box meets the frustum. Candidates: the
//    centre t = 0, the frustum's interior point in box coordinates (clamped), the eight corners,
//    and the programme's optimum.
//  - Farkas: lambda >= 0 with psi^(lambda) < -kFarkasBox u sum lambda_j W_j (1 + kSlack) proves the
//    box outside: |psi(a) - psi(a^)| <= sum lambda_j (coefficient errors) <= 10.01 u sum lambda_j W_j,
//    and evaluating psi^ (at most |J| + 4 <= 10 roundings on each term) adds gamma_10 sum lambda_j
//    W_j: 20.03 u < kFarkasBox = 32 u.
// Spheres: the ball meets P_J iff the point of P_J nearest its centre is within r. That point is
// the projection of c onto the planes of a subset S of J (|S| <= 3, independent normals): with the
// Gram matrix G_S of the scaled normals (prepared once per frame) mu = G_S^-1 s_S, x_S = c - N^T mu,
// |c - x_S|^2 = s_S . mu. The nearest feasible projection is found in double, then proved:
//  - Witness: x^ = x_S pulled towards the frustum's interior point g (x^ = x_S + eta (g - x_S)), or
//    the point of the segment from c to g just past where it enters P_J; a double point x^ with
//    fl(n'.x^ + d') >= kPoint u (A' X + |d'|) (1 + kSlack) for every j in J (the value rounds by
//    gamma_4 + u < 5.0001 u) and fl(sum (x^_i - c_i)^2) (1 + kDistance u) <= r^2 (relative error of
//    the squared distance <= 5.0001 u; r^2 is exact in double) is a common point: intersecting.
//  - Farkas: lambda = -mu >= 0 (the KKT multipliers of the nearest point) gives the half-space
//    sum lambda_j (n'_j, d'_j), which holds P_J; the ball is outside when its value at c is below
//    -r |sum lambda_j n_j|. The computed value is within 5.0001 u sum lambda_j W_j (the planes at c)
//    plus gamma_6 sum lambda_j |s^_j| (the sum) <= 11.01 u sum lambda_j W_j < kFarkasCentre, and
//    each component of the combined normal within (u + gamma_3) sum lambda_j |n'_ji|, so its length
//    within 4.01 u sum lambda_j A'_j (< kFarkasNormal) plus the rounding of its computed length.
// What neither proves (a volume within a few units in the last place of touching, or touching)
// goes to the exact stage, with J.
//
// ---- Stage 3: exact (exact_decide.cpp) --------------------------------------------------------
// Whether each plane of J holds the volume, and whether the volume meets P_J, exactly.
#include "cullproof/exact_certified.hpp"

#include "exact_decide.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cullproof {

namespace {

using M = ExactMargins;
constexpr double kU = M::u;

// x rounded up (x >= 0 computed with fewer than 2^10 roundings): every bound is made with it.
inline double up(double x) noexcept { return x * (1.0 + M::kSlack); }

// The smallest double >= x and the largest <= x, for an x already rounded to nearest from a
// value within one unit in the last place of it.
inline double next_up(double x) noexcept { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
inline double next_down(double x) noexcept { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

inline void set_stage(ExactStage* s, ExactStage v) noexcept {
  if (s) *s = v;
}

// ---- A small linear programme (stage 2 of boxes, and the interior point) -------------------------
//
// Maximise s subject to a_j0 + sum_i a_ji t_i >= s w_j (j < m, w_j > 0) and |t_i| <= 1, by the
// simplex method on a dense tableau (Bland's rule; at most 64 pivots). With y_i = t_i + 1 in
// [0, 2] and z = s + z0 >= 0 (z0 makes the origin feasible), the rows are
// w_j z - sum_i a_ji y_i <= (a_j0 - sum_i a_ji) + w_j z0 and y_i <= 2. The answer is a candidate
// only: the stages prove what they use of it.
struct LpAnswer {
  bool ok = false;
  double s = 0.0;
  double t[3] = {0, 0, 0};
  double lambda[6] = {0, 0, 0, 0, 0, 0};  // dual multipliers of the rows j
};

LpAnswer max_min_lp(int m, const double (*a_in)[4], const double* w_in) {
  constexpr int kMaxRows = 9, kCols = 4 + kMaxRows + 1;
  const int rows = m + 3, rhs = 4 + rows;
  double T[kMaxRows][kCols] = {};
  double obj[kCols] = {};
  int basis[kMaxRows];
  // Each row scaled by sigma_j = 1 / (|a_j0| + sum |a_ji| + w_j): the same constraint, entries of
  // magnitude at most 1, so that the pivoting tolerances below are relative.
  double a[6][4], w[6], sigma[6];
  for (int j = 0; j < m; ++j) {
    const double size = std::abs(a_in[j][0]) + std::abs(a_in[j][1]) + std::abs(a_in[j][2]) + std::abs(a_in[j][3]) + w_in[j];
    sigma[j] = size > 0.0 ? 1.0 / size : 1.0;
    for (int i = 0; i < 4; ++i) a[j][i] = a_in[j][i] * sigma[j];
    w[j] = w_in[j] * sigma[j];
    if (!(w[j] > 0.0)) w[j] = 0x1p-600;
  }
  double z0 = 0.0;
  for (int j = 0; j < m; ++j) {
    const double b = a[j][0] - a[j][1] - a[j][2] - a[j][3];
    z0 = std::max(z0, -b / w[j]);
  }
  for (int j = 0; j < m; ++j) {
    T[j][0] = -a[j][1];
    T[j][1] = -a[j][2];
    T[j][2] = -a[j][3];
    T[j][3] = w[j];
    T[j][4 + j] = 1.0;
    T[j][rhs] = std::max(0.0, a[j][0] - a[j][1] - a[j][2] - a[j][3] + w[j] * z0);
    basis[j] = 4 + j;
  }
  for (int i = 0; i < 3; ++i) {
    const int r = m + i;
    T[r][i] = 1.0;
    T[r][4 + r] = 1.0;
    T[r][rhs] = 2.0;
    basis[r] = 4 + r;
  }
  obj[3] = -1.0;  // maximise z
  LpAnswer out;
  for (int iter = 0; iter < 64; ++iter) {
    int enter = -1;
    for (int c = 0; c < rhs; ++c)
      if (obj[c] < -1e-12) {
        enter = c;
        break;
      }
    if (enter < 0) {
      out.ok = true;
      break;
    }
    int leave = -1;
    double best = 0.0;
    for (int r = 0; r < rows; ++r) {
      if (T[r][enter] <= 1e-12) continue;
      const double ratio = T[r][rhs] / T[r][enter];
      if (leave < 0 || ratio < best || (ratio == best && basis[r] < basis[leave])) leave = r, best = ratio;
    }
    if (leave < 0) return out;  // unbounded: cannot happen with w > 0; give up
    const double p = T[leave][enter];
    for (int c = 0; c <= rhs; ++c) T[leave][c] /= p;
    for (int r = 0; r < rows; ++r) {
      if (r == leave || T[r][enter] == 0.0) continue;
      const double f = T[r][enter];
      for (int c = 0; c <= rhs; ++c) T[r][c] -= f * T[leave][c];
    }
    const double f = obj[enter];
    for (int c = 0; c <= rhs; ++c) obj[c] -= f * T[leave][c];
    basis[leave] = enter;
  }
  if (!out.ok) return out;
  double y[4] = {0, 0, 0, 0};
  for (int r = 0; r < rows; ++r)
    if (basis[r] < 4) y[basis[r]] = T[r][rhs];
  for (int i = 0; i < 3; ++i) out.t[i] = std::min(1.0, std::max(-1.0, y[i] - 1.0));
  out.s = y[3] - z0;
  for (int j = 0; j < m; ++j) out.lambda[j] = std::max(0.0, obj[4 + j]) * sigma[j];
  return out;
}

// ---- Per-frame preparation ---------------------------------------------------------------------

void exact_planes(const CaseFrustum& cf, ExactCertifiedFrustum& f) {
  if (!cf.matrix) {
    for (int k = 0; k < 6; ++k) {
      const Plane& p = cf.planes[k];
      f.first[static_cast<std::size_t>(k)] = {p.n.x, p.n.y, p.n.z, p.d};
      f.second[static_cast<std::size_t>(k)] = {0, 0, 0, 0};
    }
    return;
  }
  // Gribb-Hartmann rows as CONVENTIONS "Matrices" fixes them (the oracle's truth): row r4 plus or
  // minus row rj, or r3 alone for the [0,1] near bound; reversed-Z swaps the two depth bounds.
  const glm::mat4& m = *cf.matrix;
  const glm::vec4 r1 = matrix_row(m, 0), r2 = matrix_row(m, 1), r3 = matrix_row(m, 2), r4 = matrix_row(m, 3);
  auto set = [&](int k, const glm::vec4& a, const glm::vec4& b, float sign) {
    for (int i = 0; i < 4; ++i) {
      f.first[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = a[i];
      f.second[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] = sign * b[i];  // negation is exact
    }
  };
  set(kLeft, r4, r1, 1.0f);
  set(kRight, r4, r1, -1.0f);
  set(kBottom, r4, r2, 1.0f);
  set(kTop, r4, r2, -1.0f);
  const bool no = cf.depth.range == DepthRange::negative_one_to_one;
  const int lower = cf.depth.reversed_z ? kFar : kNear, upper = cf.depth.reversed_z ? kNear : kFar;
  if (no) set(lower, r4, r3, 1.0f);
  else set(lower, r3, glm::vec4(0.0f), 1.0f);
  set(upper, r4, r3, -1.0f);
}

// The plane's value at a double point x, and the margin it must exceed to prove the point inside
// (kPoint u (A' |x|_max + |d'|), see "Stage 2" in the file comment).
inline double plane_at(const ExactCertifiedPlane& p, const double* x) noexcept {
  return p.nx * x[0] + p.ny * x[1] + p.nz * x[2] + p.d;
}
inline double point_margin(const ExactCertifiedPlane& p, double xmax) noexcept {
  return up(M::kPoint * kU * (p.a * xmax + p.ad));
}
inline double max_abs3(const double* x) noexcept {
  return std::max(std::abs(x[0]), std::max(std::abs(x[1]), std::abs(x[2])));
}

// A point strictly inside every plane, found once per frame (the anchor of witness points):
// the centre of the largest ball in the frustum within a box about its vertices (the same linear
// programme as stage 2, with w_j = |n'_j|), then certified plane by plane.
void find_interior(ExactCertifiedFrustum& f) {
  f.has_interior = false;
  if (f.count == 0) {
    f.has_interior = true;
    f.interior = {0, 0, 0};
    return;
  }
  // Vertices of the planes' arrangement that lie (about) in the frustum: a box to search in.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  int found = 0;
  for (int a = 0; a < f.count; ++a)
    for (int b = a + 1; b < f.count; ++b)
      for (int c = b + 1; c < f.count; ++c) {
        const ExactCertifiedPlane* P[3] = {&f.plane[std::size_t(a)], &f.plane[std::size_t(b)], &f.plane[std::size_t(c)]};
        const double m[3][3] = {{P[0]->nx, P[0]->ny, P[0]->nz}, {P[1]->nx, P[1]->ny, P[1]->nz}, {P[2]->nx, P[2]->ny, P[2]->nz}};
        const double r[3] = {-P[0]->d, -P[1]->d, -P[2]->d};
        const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        if (!(std::abs(det) > 1e-9)) continue;
        double x[3];
        for (int col = 0; col < 3; ++col) {
          double mm[3][3];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) mm[i][j] = j == col ? r[i] : m[i][j];
          x[col] = (mm[0][0] * (mm[1][1] * mm[2][2] - mm[1][2] * mm[2][1]) - mm[0][1] * (mm[1][0] * mm[2][2] - mm[1][2] * mm[2][0]) +
                    mm[0][2] * (mm[1][0] * mm[2][1] - mm[1][1] * mm[2][0])) /
                   det;
        }
        if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2])) continue;
        const double xm = max_abs3(x);
        bool in = true;
        for (int k = 0; k < f.count && in; ++k) {
          const ExactCertifiedPlane& p = f.plane[std::size_t(k)];
          in = plane_at(p, x) >= -1e-9 * (p.a * xm + p.ad);
        }
        if (!in) continue;
        for (int i = 0; i < 3; ++i) {
          lo[i] = found ? std::min(lo[i], x[i]) : x[i];
          hi[i] = found ? std::max(hi[i], x[i]) : x[i];
        }
        ++found;
      }
  double centre[3], half = 0.0;
  for (int i = 0; i < 3; ++i) {
    centre[i] = found ? 0.5 * (lo[i] + hi[i]) : 0.0;
    half = std::max(half, found ? hi[i] - lo[i] : 0x1p60);
  }
  half = std::max(half, 1e-30 + 1e-12 * max_abs3(centre));
  double a[6][4], w[6];
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    a[j][0] = plane_at(p, centre);
    a[j][1] = p.nx * half;
    a[j][2] = p.ny * half;
    a[j][3] = p.nz * half;
    w[j] = p.norm;
  }
  const LpAnswer lp = max_min_lp(f.count, a, w);
  if (!lp.ok || !(lp.s > 0.0)) return;
  double g[3];
  for (int i = 0; i < 3; ++i) g[i] = centre[i] + half * lp.t[i];
  const double gm = max_abs3(g);
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    const double v = plane_at(p, g), margin = point_margin(p, gm);
    if (!(v > 2.0 * margin)) return;
    f.interior_value[std::size_t(j)] = v - margin;  // a lower bound of the true scaled value
  }
  f.interior = {g[0], g[1], g[2]};
  f.has_interior = true;
}

}  // namespace

const char* to_string(ExactStage s) noexcept {
  switch (s) {
    case ExactStage::planes: return "planes";
    case ExactStage::axes: return "axes";
    case ExactStage::exact: return "exact";
  }
  return "invalid";
}

ExactCertifiedFrustum prepare_exact_certified(const CaseFrustum& cf) {
  ExactCertifiedFrustum f;
  exact_planes(cf, f);
  f.certified = certify(cf);
  double a_max = 0.0;
  for (int k = 0; k < 6; ++k) {
    const auto& x = f.first[std::size_t(k)];
    const auto& y = f.second[std::size_t(k)];
    // One rounding of the exact sum of two floats.
    const double n[3] = {double(x[0]) + double(y[0]), double(x[1]) + double(y[1]), double(x[2]) + double(y[2])};
    const double d = double(x[3]) + double(y[3]);
    if (n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0) {
      if (d < 0.0) f.empty = true;  // n == 0 exactly, d < 0 exactly: holds nothing
      continue;                     // d >= 0: all space
    }
    const int e = std::ilogb(std::abs(n[0]) + std::abs(n[1]) + std::abs(n[2]));
    ExactCertifiedPlane& p = f.plane[std::size_t(f.count++)];
    p.index = k;
    p.nx = std::ldexp(n[0], -e);
    p.ny = std::ldexp(n[1], -e);
    p.nz = std::ldexp(n[2], -e);
    p.d = std::ldexp(d, -e);
    p.a = up(std::abs(p.nx) + std::abs(p.ny) + std::abs(p.nz));
    p.ad = std::abs(p.d);
    p.norm = std::sqrt(p.nx * p.nx + p.ny * p.ny + p.nz * p.nz);
    const double db = M::kBox * kU * p.ad, ds = M::kSphereOffset * kU * p.ad;
    p.d_out_box = next_up(p.d + db);
    p.d_in_box = next_down(p.d - db);
    p.d_out_sphere = next_up(p.d + ds);
    p.d_in_sphere = next_down(p.d - ds);
    a_max = std::max(a_max, p.a);
  }
  f.t_box = up(M::kBox * kU * a_max);
  f.t_sphere = up(M::kSphere * kU * a_max);
  for (int i = 0; i < f.count; ++i)
    for (int j = 0; j < f.count; ++j) {
      const ExactCertifiedPlane &p = f.plane[std::size_t(i)], &q = f.plane[std::size_t(j)];
      f.gram[std::size_t(i)][std::size_t(j)] = p.nx * q.nx + p.ny * q.ny + p.nz * q.nz;
    }
  if (!f.empty) find_interior(f);
  return f;
}

namespace {

// ---- Boxes: stages 2 and 3 ---------------------------------------------------------------------

// The rows g_j(t) = a_j0 + sum a_ji t_i of the planes in J for one box, with their bounds.
struct BoxRows {
  int m = 0;
  int plane[6] = {};      // index into f.plane
  double a[6][4] = {};    // a^_j0, a^_j1, a^_j2, a^_j3
  double w[6] = {};       // W_j = A'_j X + |d'_j|
  double eps[6] = {};     // kRow u W_j (1 + kSlack): bounds |fl(g^_j(t)) - g_j(t)| on the cube
};

inline double row_at(const double* a, const double* t) noexcept { return a[0] + a[1] * t[0] + a[2] * t[1] + a[3] * t[2]; }
inline double row_min(const double* a) noexcept { return a[0] - std::abs(a[1]) - std::abs(a[2]) - std::abs(a[3]); }

bool witness(const BoxRows& r, const double* t) noexcept {
  for (int j = 0; j < r.m; ++j)
    if (!(row_at(r.a[j], t) >= r.eps[j])) return false;
  return true;
}

// Proves the box outside with the multipliers lambda >= 0 (see "Farkas" in the file comment).
bool farkas(const BoxRows& r, const double* lambda) noexcept {
  double psi0 = 0.0, comb[3] = {0, 0, 0}, weight = 0.0;
  for (int j = 0; j < r.m; ++j) {
    psi0 += lambda[j] * r.a[j][0];
    for (int i = 0; i < 3; ++i) comb[i] += lambda[j] * r.a[j][i + 1];
    weight += lambda[j] * r.w[j];
  }
  const double psi = psi0 + std::abs(comb[0]) + std::abs(comb[1]) + std::abs(comb[2]);
  return weight > 0.0 && psi < -up(M::kFarkasBox * kU * weight);
}

// The box in the cascade: AABB (aabb set) or OBB.
struct BoxIn {
  const Aabb* aabb = nullptr;
  const Obb* obb = nullptr;
};

void make_rows(const ExactCertifiedFrustum& f, const BoxIn& b, unsigned J, BoxRows& r) {
  double c[3], e[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}, X;
  if (b.aabb) {
    double hmax = 0.0;
    for (int i = 0; i < 3; ++i) {
      c[i] = 0.5 * (double(b.aabb->min[i]) + double(b.aabb->max[i]));
      e[i][i] = 0.5 * (double(b.aabb->max[i]) - double(b.aabb->min[i]));
      hmax = std::max(hmax, e[i][i]);
    }
    X = up(max_abs3(c) + hmax);
  } else {
    double h = 0.0;
    for (int i = 0; i < 3; ++i) {
      const glm::vec3& u = b.obb->axes[i];
      c[i] = double(b.obb->center[i]);
      h += double(b.obb->half[i]) * std::max(std::abs(double(u.x)), std::max(std::abs(double(u.y)), std::abs(double(u.z))));
    }
    X = up(max_abs3(c) + h);
  }
  r.m = 0;
  for (int j = 0; j < f.count; ++j) {
    if (!(J >> j & 1)) continue;
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    double* a = r.a[r.m];
    a[0] = p.nx * c[0] + p.ny * c[1] + p.nz * c[2] + p.d;
    if (b.aabb) {
      a[1] = p.nx * e[0][0];
      a[2] = p.ny * e[1][1];
      a[3] = p.nz * e[2][2];
    } else {
      for (int i = 0; i < 3; ++i) {
        const glm::vec3& u = b.obb->axes[i];
        a[i + 1] = double(b.obb->half[i]) * (p.nx * double(u.x) + p.ny * double(u.y) + p.nz * double(u.z));
      }
    }
    r.w[r.m] = up(p.a * X + p.ad);
    r.eps[r.m] = up(M::kRow * kU * r.w[r.m]);
    r.plane[r.m] = j;
    ++r.m;
  }
}

// The interior point g in the box's coordinates, clamped to the cube (a point of the box).
void interior_in_box(const ExactCertifiedFrustum& f, const BoxIn& b, double* t) noexcept {
  for (int i = 0; i < 3; ++i) {
    double ti = 0.0;
    if (b.aabb) {
      const double lo = b.aabb->min[i], hi = b.aabb->max[i];
      const double h = 0.5 * (hi - lo);
      if (h > 0.0) ti = (f.interior[std::size_t(i)] - 0.5 * (lo + hi)) / h;
    } else {
      const glm::vec3& u = b.obb->axes[i];
      const double h = b.obb->half[i];
      const double uu = double(u.x) * u.x + double(u.y) * u.y + double(u.z) * u.z;
      if (h > 0.0 && uu > 0.0) {
        const double proj = (f.interior[0] - b.obb->center.x) * u.x + (f.interior[1] - b.obb->center.y) * u.y +
                            (f.interior[2] - b.obb->center.z) * u.z;
        ti = proj / (h * uu);
      }
    }
    t[i] = std::isfinite(ti) ? std::min(1.0, std::max(-1.0, ti)) : 0.0;
  }
}

enum class Tri : std::uint8_t { no, yes, unknown };

// Whether the box meets P_J (the rows r): yes (a certified witness), no (a certified Farkas
// combination), or unknown (inside every bound).
Tri box_meets(const ExactCertifiedFrustum& f, const BoxIn& b, const BoxRows& r) {
  const double centre[3] = {0, 0, 0};
  if (witness(r, centre)) return Tri::yes;
  if (r.m == 1) {
    // One plane: its p-vertex (the maximum over the cube) decides.
    const double mx = r.a[0][0] + std::abs(r.a[0][1]) + std::abs(r.a[0][2]) + std::abs(r.a[0][3]);
    if (mx >= r.eps[0]) return Tri::yes;
    if (mx < -r.eps[0]) return Tri::no;
    return Tri::unknown;
  }
  if (f.has_interior) {
    double t[3];
    interior_in_box(f, b, t);
    if (witness(r, t)) return Tri::yes;
  }
  for (int s = 0; s < 8; ++s) {
    const double t[3] = {s & 1 ? 1.0 : -1.0, s & 2 ? 1.0 : -1.0, s & 4 ? 1.0 : -1.0};
    if (witness(r, t)) return Tri::yes;
  }
  // The programme with w_j = W_j: eps_j is the same multiple of W_j for every j, so its optimum
  // is the best candidate for both certificates.
  const LpAnswer lp = max_min_lp(r.m, r.a, r.w);
  if (!lp.ok) return Tri::unknown;
  if (lp.s > 0.0 && witness(r, lp.t)) return Tri::yes;
  if (lp.s < 0.0 && farkas(r, lp.lambda)) return Tri::no;
  return Tri::unknown;
}

// Keeps the rows whose plane is in `keep`.
void filter_rows(BoxRows& r, unsigned keep) {
  int n = 0;
  for (int j = 0; j < r.m; ++j) {
    if (!(keep >> r.plane[j] & 1)) continue;
    if (n != j) {
      r.plane[n] = r.plane[j];
      for (int i = 0; i < 4; ++i) r.a[n][i] = r.a[j][i];
      r.w[n] = r.w[j];
      r.eps[n] = r.eps[j];
    }
    ++n;
  }
  r.m = n;
}

// Stages 2 and 3 for a box that no plane surely excludes: r holds the rows of the planes J that
// stage 1 could not prove to hold it (`crossing`: those it proved to cut it).
Visibility box_rest(const ExactCertifiedFrustum& f, const BoxIn& b, BoxRows& r, unsigned crossing, ExactStage* stage) {
  set_stage(stage, ExactStage::axes);
  // Containment from the rows (their margin may be finer than stage 1's for this plane).
  unsigned J = 0, unknown = 0;
  for (int j = 0; j < r.m; ++j) {
    const unsigned bit = 1u << r.plane[j];
    if (crossing & bit) {
      J |= bit;
      continue;
    }
    const double mn = row_min(r.a[j]);
    if (mn >= r.eps[j]) continue;  // holds the box: no longer in J
    J |= bit;
    if (mn < -r.eps[j]) crossing |= bit;
    else unknown |= bit;
  }
  if (J == 0) return Visibility::inside;
  filter_rows(r, J);
  const Tri meets = box_meets(f, b, r);
  if (meets == Tri::no) return Visibility::outside;
  if (crossing && meets == Tri::yes) return Visibility::intersecting;
  // Stage 3: whether the planes left undecided hold the box, whether it meets P_J.
  set_stage(stage, ExactStage::exact);
  const exact_detail::BoxRef ref{b.aabb, b.obb};
  if (!crossing) {
    bool inside = true;
    for (int j = 0; j < f.count && inside; ++j)
      if (unknown >> j & 1) inside = exact_detail::box_in_plane(f, f.plane[std::size_t(j)].index, ref);
    if (inside) return Visibility::inside;
  }
  if (meets == Tri::yes) return Visibility::intersecting;
  int planes[6], n = 0;
  for (int j = 0; j < f.count; ++j)
    if (J >> j & 1) planes[n++] = f.plane[std::size_t(j)].index;
  return exact_detail::box_meets_planes(f, planes, n, ref) ? Visibility::intersecting : Visibility::outside;
}

// ---- Spheres: stages 2 and 3 -------------------------------------------------------------------

// Proves the point x^ (double) a common point of the ball and P_J.
bool sphere_witness(const ExactCertifiedFrustum& f, unsigned J, const Sphere& s, const double* x) noexcept {
  const double xm = max_abs3(x);
  for (int j = 0; j < f.count; ++j) {
    if (!(J >> j & 1)) continue;
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    if (!(plane_at(p, x) >= point_margin(p, xm))) return false;
  }
  const double dx = x[0] - double(s.center.x), dy = x[1] - double(s.center.y), dz = x[2] - double(s.center.z);
  const double q = dx * dx + dy * dy + dz * dz;
  const double r = s.radius;
  return q * (1.0 + M::kDistance * kU) <= r * r;
}

// Proves the ball outside P_J with multipliers lambda >= 0 over the planes S (|S| = k).
bool sphere_farkas(const ExactCertifiedFrustum& f, const double* sc, const double* wc, const int* S, int k,
                   const double* lambda, double r) noexcept {
  double value = 0.0, weight = 0.0, na = 0.0, n[3] = {0, 0, 0};
  for (int q = 0; q < k; ++q) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(S[q])];
    value += lambda[q] * sc[S[q]];
    weight += lambda[q] * wc[S[q]];
    na += lambda[q] * p.a;
    n[0] += lambda[q] * p.nx;
    n[1] += lambda[q] * p.ny;
    n[2] += lambda[q] * p.nz;
  }
  const double value_up = value + up(M::kFarkasCentre * kU * weight);
  if (!(value_up < 0.0)) return false;
  const double len_up = up(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * (1.0 + 4.0 * kU) + M::kFarkasNormal * kU * na);
  return up(r * len_up) < -value_up * (1.0 - 4.0 * kU);
}

Tri sphere_meets(const ExactCertifiedFrustum& f, unsigned J, const Sphere& s, const double* sc, const double* wc) {
  const double c[3] = {s.center.x, s.center.y, s.center.z};
  const double r = s.radius;
  int js[6], m = 0;
  for (int j = 0; j < f.count; ++j)
    if (J >> j & 1) js[m++] = j;
  // The segment from the centre to the interior point g: the point just past its entry into P_J.
  if (f.has_interior) {
    double eta = 0.0;
    for (int q = 0; q < m; ++q) {
      const int j = js[q];
      if (sc[j] < 0.0) {
        const double denom = f.interior_value[std::size_t(j)] - sc[j];
        if (denom > 0.0) eta = std::max(eta, -sc[j] / denom);
      }
    }
    eta = std::min(1.0, eta * (1.0 + 0x1p-20) + 0x1p-30);
    double x[3];
    for (int i = 0; i < 3; ++i) x[i] = c[i] + eta * (f.interior[std::size_t(i)] - c[i]);
    if (sphere_witness(f, J, s, x)) return Tri::yes;
  }
  // The nearest feasible projection onto the planes of a subset of J.
  double best = std::numeric_limits<double>::infinity(), best_x[3] = {0, 0, 0}, best_lambda[3] = {0, 0, 0};
  int best_S[3] = {0, 0, 0}, best_k = -1;
  auto consider = [&](const int* S, int k, const double* mu) {
    double x[3] = {c[0], c[1], c[2]}, dist2 = 0.0;
    for (int q = 0; q < k; ++q) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(S[q])];
      x[0] -= mu[q] * p.nx;
      x[1] -= mu[q] * p.ny;
      x[2] -= mu[q] * p.nz;
      dist2 += mu[q] * sc[S[q]];
    }
    if (!(dist2 < best)) return;
    const double xm = max_abs3(x);
    for (int q = 0; q < m; ++q) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(js[q])];
      if (plane_at(p, x) < -1e-9 * (p.a * xm + p.ad)) return;  // not in P_J (approximately)
    }
    best = dist2;
    best_k = k;
    for (int i = 0; i < 3; ++i) best_x[i] = x[i];
    for (int q = 0; q < k; ++q) best_S[q] = S[q], best_lambda[q] = std::max(0.0, -mu[q]);
  };
  const auto& G = f.gram;
  for (int qa = 0; qa < m; ++qa) {
    const int a = js[qa];
    const int S[1] = {a};
    const double mu[1] = {sc[a] / G[a][a]};
    consider(S, 1, mu);
    for (int qb = qa + 1; qb < m; ++qb) {
      const int b = js[qb];
      const double D = G[a][a] * G[b][b] - G[a][b] * G[a][b];
      if (!(D > 1e-12 * G[a][a] * G[b][b])) continue;
      const int S2[2] = {a, b};
      const double mu2[2] = {(G[b][b] * sc[a] - G[a][b] * sc[b]) / D, (G[a][a] * sc[b] - G[a][b] * sc[a]) / D};
      consider(S2, 2, mu2);
      for (int qc = qb + 1; qc < m; ++qc) {
        const int cc = js[qc];
        const double e00 = G[a][a], e01 = G[a][b], e02 = G[a][cc], e11 = G[b][b], e12 = G[b][cc], e22 = G[cc][cc];
        const double c00 = e11 * e22 - e12 * e12, c01 = e02 * e12 - e01 * e22, c02 = e01 * e12 - e02 * e11;
        const double c11 = e00 * e22 - e02 * e02, c12 = e01 * e02 - e00 * e12, c22 = e00 * e11 - e01 * e01;
        const double D3 = e00 * c00 + e01 * c01 + e02 * c02;
        if (!(D3 > 1e-12 * e00 * e11 * e22)) continue;
        const int S3[3] = {a, b, cc};
        const double mu3[3] = {(c00 * sc[a] + c01 * sc[b] + c02 * sc[cc]) / D3, (c01 * sc[a] + c11 * sc[b] + c12 * sc[cc]) / D3,
                               (c02 * sc[a] + c12 * sc[b] + c22 * sc[cc]) / D3};
        consider(S3, 3, mu3);
      }
    }
  }
  if (best_k < 0) return Tri::unknown;
  const double r2 = r * r;
  if (best < r2) {
    if (f.has_interior) {
      // Pull the projection towards g by half the room left in the ball.
      const double d = std::sqrt(std::max(0.0, best));
      double gx[3], gl = 0.0;
      for (int i = 0; i < 3; ++i) gx[i] = f.interior[std::size_t(i)] - best_x[i], gl += gx[i] * gx[i];
      gl = std::sqrt(gl);
      if (gl > 0.0) {
        const double eta = std::min(1.0, 0.5 * (r - d) / gl);
        double x[3];
        for (int i = 0; i < 3; ++i) x[i] = best_x[i] + eta * gx[i];
        if (sphere_witness(f, J, s, x)) return Tri::yes;
      }
    }
    return Tri::unknown;
  }
  if (best > r2 && sphere_farkas(f, sc, wc, best_S, best_k, best_lambda, r)) return Tri::no;
  return Tri::unknown;
}

}  // namespace

// ---- Stage 1 and the cascades ------------------------------------------------------------------

Visibility exact_certified_aabb(const ExactCertifiedFrustum& f, const Aabb& b, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  const double lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
  const double m = std::max(std::max(std::max(hi[0], hi[1]), hi[2]), -std::min(std::min(lo[0], lo[1]), lo[2]));
  const double T = f.t_box * m, neg_t = -T;
  unsigned J = 0, crossing = 0, p_in = 0;
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    const double px = p.nx >= 0.0 ? hi[0] : lo[0], qx = p.nx >= 0.0 ? lo[0] : hi[0];
    const double py = p.ny >= 0.0 ? hi[1] : lo[1], qy = p.ny >= 0.0 ? lo[1] : hi[1];
    const double pz = p.nz >= 0.0 ? hi[2] : lo[2], qz = p.nz >= 0.0 ? lo[2] : hi[2];
    const double sp = (p.nx * px + p.ny * py) + p.nz * pz;
    if (sp + p.d_out_box < neg_t) return Visibility::outside;
    const double sq = (p.nx * qx + p.ny * qy) + p.nz * qz;
    if (!(sq + p.d_in_box >= T)) {
      const unsigned bit = 1u << j;
      J |= bit;
      if (sq + p.d_out_box < neg_t) crossing |= bit;
      if (sp + p.d_in_box >= T) p_in |= bit;
    }
  }
  if (J == 0) return Visibility::inside;
  if ((J & (J - 1)) == 0 && crossing == J && p_in == J) return Visibility::intersecting;
  const BoxIn in{&b, nullptr};
  BoxRows r;
  make_rows(f, in, J, r);
  return box_rest(f, in, r, crossing, stage);
}

Visibility exact_certified_obb(const ExactCertifiedFrustum& f, const Obb& b, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  // Stage 1 on the rows of every plane: max and min of g_j over the cube with eps_j.
  const BoxIn in{nullptr, &b};
  BoxRows r;
  make_rows(f, in, (1u << f.count) - 1u, r);
  unsigned J = 0, crossing = 0, p_in = 0;
  for (int j = 0; j < r.m; ++j) {
    const double* a = r.a[j];
    const double rad = std::abs(a[1]) + std::abs(a[2]) + std::abs(a[3]);
    if (a[0] + rad < -r.eps[j]) return Visibility::outside;
    if (!(a[0] - rad >= r.eps[j])) {
      const unsigned bit = 1u << j;
      J |= bit;
      if (a[0] - rad < -r.eps[j]) crossing |= bit;
      if (a[0] + rad >= r.eps[j]) p_in |= bit;
    }
  }
  if (J == 0) return Visibility::inside;
  if ((J & (J - 1)) == 0 && crossing == J && p_in == J) return Visibility::intersecting;
  filter_rows(r, J);
  return box_rest(f, in, r, crossing, stage);
}

Visibility exact_certified_sphere(const ExactCertifiedFrustum& f, const Sphere& s, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  const double c[3] = {s.center.x, s.center.y, s.center.z}, r = s.radius;
  const double mc = max_abs3(c);
  const double T = f.t_sphere * (mc + r), neg_t = -T;
  unsigned J = 0, crossing = 0, reach = 0, centre_in = 0;
  double sc[6], wc[6];
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    const double v = (p.nx * c[0] + p.ny * c[1]) + p.nz * c[2];
    const double rho = r * p.norm;
    if ((v + p.d_out_sphere) + rho < neg_t) return Visibility::outside;
    const double w_in = v + p.d_in_sphere;
    if (!(w_in - rho >= T)) {
      const unsigned bit = 1u << j;
      J |= bit;
      if ((v + p.d_out_sphere) - rho < neg_t) crossing |= bit;
      if ((v + p.d_in_sphere) + rho >= T) reach |= bit;
      if (w_in >= T) centre_in |= bit;
    }
    sc[j] = v + p.d;
    wc[j] = up(p.a * mc + p.ad);
  }
  if (J == 0) return Visibility::inside;
  if (crossing) {
    // One plane left, reached by the ball: it meets the frustum inside that plane. The centre in
    // every plane of J: the centre is a common point.
    if (((J & (J - 1)) == 0 && reach == J) || centre_in == J) return Visibility::intersecting;
  }
  set_stage(stage, ExactStage::axes);
  const Tri meets = sphere_meets(f, J, s, sc, wc);
  if (meets == Tri::no) return Visibility::outside;
  if (crossing && meets == Tri::yes) return Visibility::intersecting;
  set_stage(stage, ExactStage::exact);
  if (!crossing) {
    bool inside = true;
    for (int j = 0; j < f.count && inside; ++j)
      if (J >> j & 1) inside = exact_detail::sphere_in_plane(f, f.plane[std::size_t(j)].index, s);
    if (inside) return Visibility::inside;
  }
  if (meets == Tri::yes) return Visibility::intersecting;
  int planes[6], n = 0;
  for (int j = 0; j < f.count; ++j)
    if (J >> j & 1) planes[n++] = f.plane[std::size_t(j)].index;
  return exact_detail::sphere_meets_planes(f, planes, n, s) ? Visibility::intersecting : Visibility::outside;
}

void exact_certified_aabbs(const ExactCertifiedFrustum& f, const Aabb* boxes, std::size_t n, Visibility* verdicts) {
  for (std::size_t i = 0; i < n; ++i) verdicts[i] = exact_certified_aabb(f, boxes[i]);
}

void exact_certified_spheres(const ExactCertifiedFrustum& f, const Sphere* spheres, std::size_t n, Visibility* verdicts) {
  for (std::size_t i = 0; i < n; ++i) verdicts[i] = exact_certified_sphere(f, spheres[i]);
}

}  // namespace cullproof

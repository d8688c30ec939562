// Certified-exact culling: the cascade of cullproof/simd/exact_certified.hpp. Claim: certified-exact,
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
// Boxes (AABB), in centre-extent form: c = fl((lo + hi) / 2), h = fl((hi - lo) / 2) (one rounding
// each), and for scaled plane (n', d') the p- and n-vertex values are n'.c + d +- sum |n'_i h_i|
// (no choice of vertex per axis). The computed v = fl(n'.c + D +- sum |n'_i h_i|), D = d_out or
// d_in (the offset with the constant part of the margin folded in), is a seven-term inner
// product: |v - (its exact value)| <= gamma_7 (A' M (1 + u) + |D|) (Higham (3.4); |c_i| + h_i <=
// max(|lo_i|, |hi_i|) (1 + u) <= M (1 + u)). Rounding c and h moves the value by at most u A' M; the
// true scaled plane differs from (n', d') by at most u (A' M + |d'|). With d_out >= d' + delta,
// d_in <= d' - delta, delta = kBox u |d'| and T = fl(t_box M) >= kBox u (1 - u) A' M:
//   v(d_out) < -T  =>  the true maximum over the box is < 0 (the box is outside the plane),
// since T >= (gamma_7 (1 + u) + 2u) A' M (9.0002 u < kBox = 16 u) and delta (1 - gamma_7) >=
// (gamma_7 (1 + kBox u)(1 + 2u) + u) |d'|; v(d_in) >= T => the true minimum > 0 (inside) is the
// mirror image, and likewise the maximum with d_in (the p-vertex is inside the plane) and the
// minimum with d_out (the box crosses the plane). The p-vertex is the corner on the side of
// sign(n'_i) per axis, which is that of the true n_i (a rounded value has the sign of the exact
// one, and is zero only when that is zero). A box that lies in every plane but those of a set J,
// crosses one of them, and has its p-vertex inside each plane of J, where the normals of J agree
// in sign on every axis (so that the p-vertices coincide), meets the frustum there: intersecting.
// OBBs: e_i = h_i u_i is exact in double; s = fl(n'.c) within gamma_3 A' M_c, rad = sum
// |fl(n'.e_i)| within (gamma_3 + gamma_2) A' H (H = sum h_i max_k |u_ik|), two more additions
// (gamma_2) and the coefficients (u): at most 8.0002 u A' (M_c + H) + 3.0001 u |d'|, covered by the
// same kBox with X = M_c + H in place of M.
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
// Stage 2 rows. A box is c + sum t_i e_i, t in [-1,1]^3; plane j on it is the row
// g_j(t) = a_j0 + sum a_ji t_i. AABB: a^_j0 = fl(n'.c + d'), within (gamma_4 (1 + u) + 2u)
// (A' M + |d'|) (c rounded, coefficients), a^_ji = fl(n'_i h_i), within 3.0001 u |n'_i| h_i. OBB:
// a^_j0 within (gamma_4 + u)(A' M_c + |d'|), a^_ji = fl(n'.e_i) within (gamma_3 + u)(1 + u) A' h_i
// U_i (U_i = max_k |u_ik|). Evaluating fl(a^_j0 + sum a^_ji t_i) at |t_i| <= 1 adds gamma_4
// (|a^_j0| + sum |a^_ji|). With W_j = A'_j X + |d'_j| (X = M for an AABB, M_c + H for an OBB)
// bounding |a_j0| + sum |a_ji|, the total is at most 13.0003 u W_j: eps_j = kRow u W_j (1 + kSlack),
// kRow = 16, bounds |fl(g^_j(t)) - g_j(t)| on the whole cube. So g^_j(t) >= eps_j proves
// g_j(t) >= 0, min_t g^_j = fl(a^_j0 - sum |a^_ji|) >= eps_j proves the box inside plane j and
// < -eps_j that it crosses it; max_t g^_j >= eps_j or < -eps_j likewise.
//
// ---- Stage 2: axes ----------------------------------------------------------------------------
// Let J be the planes that stage 1 could not prove to hold the whole volume. Every other plane
// holds it, so the volume meets the frustum iff it meets the intersection P_J of the planes in J,
// and it is inside iff every plane of J holds it.
//
// Witness points. Once per frame the cascade finds a point g strictly inside every plane (the
// centre of the largest ball in the frustum, by the programme below) and anchors: g, the centres
// of the faces and the vertices, each pulled 2^-12 of the way towards g, kept where its plane
// values at a double point x exceed the margin: fl(n'.x + d') >= kPoint u (A' |x|_max + |d'|)
// (1 + kSlack) proves n.x + d > 0 (the value rounds by gamma_4 + u < 5.0001 u of the magnitude).
// An AABB that holds an anchor (compared exactly) meets the frustum; a ball whose centre lies
// within r of one, by fl(sum (x_i - c_i)^2) (1 + kDistance u) <= r^2 (the squared distance has a
// relative error of at most 5.0001 u; r^2 is exact in double), meets it too.
//
// Boxes: P_J meets the box iff max over t in the cube of min_j g_j(t) / W_j >= 0. That is a linear
// programme in (t, s): maximise s subject to g_j(t) >= s W_j, |t_i| <= 1. Its optimum s* is also
// min over lambda >= 0, sum lambda_j W_j = 1 of psi(lambda) = sum lambda_j a_j0 + sum_i
// |sum_j lambda_j a_ji| (LP duality), the maximum over the box of the combined plane
// sum lambda_j (n_j, d_j): a separating axis made of the frustum's planes. For |J| <= 3 the
// minimum is found by enumerating the dual vertices (best_dual: single planes; pairs with one box
// axis cancelled, SAT's edge-cross-box-axis axes; triples with two cancelled, SAT's box axes),
// otherwise by the simplex method in double (max_min_lp). Either only proposes: a candidate is
// used only once proved, as follows.
//  - Witness: a t (clamped to the cube, so that c + sum t_i e_i is in the box exactly) with
//    fl(g^_j(t)) >= eps_j for every j in J proves the box meets the frustum. Candidates, in order:
//    the centre t = 0, the primal point of the best dual vertex (complementary slackness: the
//    combined row's p-vertex on the other axes, the rows of the support balanced on the cancelled
//    ones), the anchors clamped to the box, and the programme's optimum.
//  - Farkas: lambda >= 0 with psi^(lambda) < -kFarkasBox u sum lambda_j W_j (1 + kSlack) proves the
//    box outside: |psi(a) - psi(a^)| <= sum lambda_j (coefficient errors) <= 9.0003 u sum lambda_j W_j,
//    and evaluating psi^ (at most |J| + 3 <= 9 roundings on each term) adds gamma_9 sum lambda_j
//    W_j: 18.01 u < kFarkasBox (1 - gamma_6) = 32 u (1 - gamma_6) (the weight's own rounding).
// Before building the rows, an AABB whose planes of J agree in sign on every axis (so that they
// share their p-vertex) and each proved that p-vertex inside is intersecting (stage 1 data).
//
// AABBs, the frame's combinations. psi is piecewise linear in lambda, so its minimum lies at a
// vertex of {lambda >= 0, sum lambda_j W_j = 1} cut by the hyperplanes sum_j lambda_j a_ji = 0: a
// support of k <= 4 planes with k - 1 box axes cancelled. For an AABB a_ji = n_ji h_i, so the
// multipliers that cancel axis i (axes i and k) are those that cancel the normals' components:
// the same rays for every box, prepared once per frame (combinations). Four planes cancel all
// three axes only where sum lambda_j n_j = 0, and there psi = sum lambda_j d_j >= 0 when P_J is
// not empty (it holds P). So when the list holds every vertex of one to three planes
// (comb_complete: an interior point was certified, and every multiplier's sign is known), an
// AABB meets P_J as soon as every plane of J (its p-vertex proved inside by stage 1) and every
// combination within J is positive at the box, and any combination negative at it proves it
// outside. Neither needs rows, witnesses or the programme.
//  - Multipliers. Two planes whose normals differ in sign on axis i: lambda = (|n'_bi|, |n'_ai|),
//    within u lambda of those of the exact normals. Three planes, axes i and k: lambda = x cross y
//    (x, y: the three normals' components i and k); each component is the difference of two
//    products of rounded coefficients, within (2u + u^2 + gamma_2) P_q < kMultiplier u P_q = dl_q
//    of the exact one (P_q: the sum of the two products' magnitudes). A triple is kept in the
//    orientation where every component is >= -dl_q, negative ones set to 0 (towards the exact
//    ones); where both orientations pass the exact multipliers may point anywhere, and the list
//    is not complete (unless every P_q is 0: exactly no vertex). All are scaled by a power of two
//    so that the largest lies in [1, 2).
//  - Value. The combination at the box, v = fl(C.c + D + sum_i |C_i| h_i) with C, D the rounded
//    three-term sums of lambda_q (n'_q, d'_q). Against psi of the exact planes, box and
//    multipliers: the multipliers move it by at most (1 + u) sum dl_q (A'_q X + |d'_q|) (the
//    exact rows' magnitudes); the coefficients by u (1 + u) sum lambda_q (A'_q X + |d'_q|); C and D
//    by gamma_3 (1 + u) of the same; c and h (rounded once each) by 2u (1 + u) sum lambda_q A'_q X;
//    the seven-term evaluation by gamma_7 (1 + gamma_3)(1 + u) of the same. In all at most
//    13.02 u on the X part and 11.02 u on the |d'| part, below kCombination = 16:
//    k1 = 2 sum dl_q A'_q + kCombination u sum lambda_q A'_q, k0 the same with |d'_q|, rounded up,
//    each plus kUnderflow (products of small multipliers and coefficients), and the test is
//    v < -(k1 X + k0) (1 + kSlack) for outside, v > (k1 X + k0) (1 + kSlack) for positive.
//
// Spheres: the ball meets P_J iff the point of P_J nearest its centre is within r. That point is
// the projection of c onto the planes of a subset S of J (|S| <= 3, independent normals): with the
// Gram matrix G_S of the scaled normals (prepared once per frame) mu = G_S^-1 s_S, x_S = c - N^T mu,
// |c - x_S|^2 = s_S . mu. After the anchors and the point of the segment from c to g just past its
// entry into P_J, the nearest feasible projection is found in double, then proved:
//  - Witness: x^ = x_S pulled towards g by half the room left in the ball, with its plane values
//    and its distance to c proved as for the anchors: intersecting.
//  - Farkas: lambda = -mu >= 0 (the KKT multipliers of the nearest point) gives the half-space
//    sum lambda_j (n'_j, d'_j), which holds P_J; the ball is outside when its value at c is below
//    -r |sum lambda_j n_j|. The computed value is within (gamma_4 + u) sum lambda_j W_j (the planes
//    at c, W_j = A'_j M_c + |d'_j|) plus gamma_3 sum lambda_j |s^_j| (the sum): 8.0003 u <
//    kFarkasCentre (1 - gamma_3); each component of the combined normal within (gamma_3 + u)
//    sum lambda_j |n'_ji|, so its length within 4.0001 u sum lambda_j A'_j (the 1-norm bounds the
//    2-norm) < kFarkasNormal (1 - gamma_3), and the computed length sqrt(fl(sum n_i^2)) within
//    2.5001 u of the exact length of the computed normal (taken times 1 + 4u).
// Multipliers: a certificate holds for any lambda >= 0, and scaling them all by a power of two
// changes every computed value by the same exact factor; farkas() and sphere_farkas() first scale
// them so that the largest lies in [1, 2). Products of the smaller ones with small coefficients
// can still underflow (lambda of three rows is a product of two coefficients, times a third in
// the combination), each by at most 2^-1075, far fewer than 2^70 of them: the absolute term
// kUnderflow = 2^-1000 added to each Farkas bound covers them. With the largest multiplier at
// least 1 it is far below the relative part whenever that row's W_j exceeds 2^-900, so it costs
// no proof but those of volumes and planes within 2^-900 of the origin (left to the exact stage).
// What neither proves (a volume within a few units in the last place of touching, or touching)
// goes to the exact stage, with J.
//
// ---- The AABB array form's float pass (batch_combinations.cpp) --------------------------------
// What the SIMD batch and its witness pass leave is tested again in float, several boxes per
// instruction, on the planes and the frame's combinations: stage 1 and the combinations above,
// with float margins of their own. Item q is a plane, (C, D) = (n'_j, d'_j), or a combination,
// (C, D) = sum lambda (n', d'), in double, and (C*, D*) what it stands for: the exact scaled plane
// (sum_i |C_i - C*_i| <= k1 = u A'_j, |D - D*| <= k0 = u |d'_j|: one rounding per coefficient);
// for a combination, both the exact planes combined with these multipliers (any lambda >= 0 gives
// a half-space holding the frustum: for outside) and the exact vertex of the dual (for meets);
// the k1, k0 of "AABBs, the frame's combinations" bound both (their multiplier and coefficient
// terms alone). Each item is scaled by 2^-e (exact in double, the same half-space; e = ilogb A_C,
// raised so that |D| 2^-e <= 2^101) and rounded to float: Cf_i within u_f |C_i| + 2^-150 of C_i
// (u_f = 2^-24; 2^-150 for a subnormal), so e1 = k1 + sum_i (u_f |C_i| + 2^-150) bounds
// sum |Cf_i - C*_i| and e0 = k0 + u_f |D| + 2^-150 bounds |Df - D*|.
//  At a box B (float corners, coordinates at most X in magnitude) let p maximise Cf.x over B (the
// vertex chosen by the signs of Cf) and p* maximise C*.x. Where the signs agree p_i = p*_i, where
// they differ Cf_i p_i >= Cf_i p*_i; so max_B (C*.x + D*) = C*.p* + D* <= Cf.p + Df + e1 X + e0,
// and >= C*.p + D* >= Cf.p + Df - e1 X - e0. The same holds for the minimum at the vertex q that
// minimises Cf.x. The value v = fl(Cf.p + Df), in any order, fused or not, is within
// gamma_4 (A_f X + |Df|) + 3 2^-150 of Cf.p + Df (A_f = sum |Cf_i|; gamma_4 < 4.0001 u_f; three
// products may underflow). The threshold theta = fl(t X + delta) (one or two roundings, each a
// factor of at least 1 - u_f or an error of 2^-150), with
//    t >= (e1 + 4.0001 u_f A_f)(1 + 2^-20),  delta >= (e0 + 4.0001 u_f |Df|)(1 + 2^-20) + 2^-126,
// both rounded up to float (2^-126 takes every underflow term), bounds the whole error: v < -theta
// at p proves max_B < 0 (the box outside the half-space, hence the frustum), v >= theta at p proves
// max_B > 0, and at q, v >= theta proves the half-space holds the box and v < -theta that a vertex
// is strictly outside it. With Cf, Df, t, delta finite and X <= x_safe = min_q (2^120 - |Df| -
// delta) / (A_f + t), nothing overflows; a NaN coordinate fails every comparison.
//  Per box: outside when an item proves it; inside when every plane holds the box; intersecting
// when the list is complete (comb_complete, and every plane and combination has its float item),
// every plane not proved to hold the box (J) has the box's p-vertex proved inside, every
// combination within J is proved positive (the argument for the combinations above), and some
// plane has a vertex strictly outside (so the box is not inside).
//
// ---- Stage 3: exact (exact_decide.cpp) --------------------------------------------------------
// Whether each plane of J holds the volume, and whether the volume meets P_J, exactly.
#include "cullproof/simd/exact_certified.hpp"
#include "cullproof/core/frustum_build.hpp"

#include "exact_decide.hpp"
#include "exact_lanes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <optional>
#include <utility>

namespace cullproof {

namespace {

// x * 2^k as std::ldexp gives it (the exact product, correctly rounded): one multiplication where
// 2^k is a normal double, which rounds the exact product once, as ldexp does.
double times_pow2(double x, int k) {
  if (k < -1022 || k > 1023) return std::ldexp(x, k);
  const std::uint64_t bits = std::uint64_t(k + 1023) << 52;
  double p;
  std::memcpy(&p, &bits, sizeof p);
  return x * p;
}

using M = ExactMargins;
constexpr double kU = M::u;

// x rounded up (x >= 0 computed with fewer than 2^10 roundings): every bound is made with it.
inline double up(double x) noexcept { return x * (1.0 + M::kSlack); }

// Covers the underflows of products of multipliers and coefficients (see "Multipliers").
constexpr double kUnderflow = M::kFarkasUnderflow;

// The multipliers scaled by a power of two (exact) so that the largest lies in [1, 2); false
// when none is positive and finite.
bool normalised(const double* lambda, int k, double* out) noexcept {
  double largest = 0.0;
  for (int q = 0; q < k; ++q) {
    if (!(lambda[q] >= 0.0) || !std::isfinite(lambda[q])) return false;
    largest = std::max(largest, lambda[q]);
  }
  if (!(largest > 0.0)) return false;
  std::uint64_t bits;
  std::memcpy(&bits, &largest, sizeof bits);
  const int field = int(bits >> 52);  // largest > 0: no sign bit
  if (field == 0 || field == 2046) {  // subnormal, or 2^-e not a normal number: scalbn
    const int e = std::ilogb(largest);
    for (int q = 0; q < k; ++q) out[q] = std::scalbn(lambda[q], -e);
    return true;
  }
  // 2^-e with e = field - 1023, a normal number: each product is what scalbn gives (exact, or
  // one rounding of the exact product when it is subnormal).
  const std::uint64_t scale_bits = std::uint64_t(2046 - field) << 52;
  double scale;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  for (int q = 0; q < k; ++q) out[q] = lambda[q] * scale;
  return true;
}

// The smallest double >= x and the largest <= x, for an x already rounded to nearest from a
// value within one unit in the last place of it.
inline double next_up(double x) noexcept { return std::nextafter(x, std::numeric_limits<double>::infinity()); }
inline double next_down(double x) noexcept { return std::nextafter(x, -std::numeric_limits<double>::infinity()); }

inline void set_stage(ExactStage* s, ExactStage v) noexcept {
  if (s) *s = v;
}

// ---- A small linear programme: exact_lanes::max_min_lp (stage 2 of boxes, the interior point) --

using exact_lanes::LpAnswer;
using exact_lanes::max_min_lp;

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
  double vertex[20][3];
  unsigned vertex_planes[20];
  for (int a = 0; a < f.count; ++a)
    for (int b = a + 1; b < f.count; ++b)
      for (int c = b + 1; c < f.count; ++c) {
        auto coeffs = [&](int k) {
          const ExactCertifiedPlane& p = f.plane[std::size_t(k)];
          return glm::dvec4(p.nx, p.ny, p.nz, p.d);
        };
        const std::optional<glm::dvec3> meet = planes_meet(coeffs(a), coeffs(b), coeffs(c));
        if (!meet) continue;
        const double x[3] = {meet->x, meet->y, meet->z};
        const double xm = max_abs3(x);
        bool in = true;
        for (int k = 0; k < f.count && in; ++k) {
          const ExactCertifiedPlane& p = f.plane[std::size_t(k)];
          in = plane_at(p, x) >= -1e-9 * (p.a * xm + p.ad);
        }
        if (!in) continue;
        for (int i = 0; i < 3; ++i) vertex[found][i] = x[i];
        vertex_planes[found] = 1u << a | 1u << b | 1u << c;
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
  // Anchors: g, the centre of each face (the mean of its vertices) and each vertex, pulled
  // 2^-12 of the way towards g and kept where certified inside every plane: witness points for
  // volumes that hold part of a face or a corner of the frustum.
  f.anchor_count = 0;
  auto put = [&](const double* x) {
    const std::size_t k = std::size_t(f.anchor_count++);
    f.anchor_x[k] = x[0], f.anchor_y[k] = x[1], f.anchor_z[k] = x[2];
  };
  auto add_anchor = [&](const double* p) {
    if (f.anchor_count >= ExactCertifiedFrustum::kAnchors) return;
    double x[3];
    for (int i = 0; i < 3; ++i) x[i] = p[i] + 0x1p-12 * (g[i] - p[i]);
    const double xm = max_abs3(x);
    for (int j = 0; j < f.count; ++j)
      if (!(plane_at(f.plane[std::size_t(j)], x) >= point_margin(f.plane[std::size_t(j)], xm))) return;
    put(x);
  };
  put(g);
  for (int j = 0; j < f.count; ++j) {
    double centre_j[3] = {0, 0, 0};
    int on = 0;
    for (int v = 0; v < found; ++v)
      if (vertex_planes[v] >> j & 1) {
        for (int i = 0; i < 3; ++i) centre_j[i] += vertex[v][i];
        ++on;
      }
    if (on < 3) continue;
    for (double& x : centre_j) x /= on;
    add_anchor(centre_j);
  }
  for (int v = 0; v < found; ++v) add_anchor(vertex[v]);
  f.anchor_lo = {f.anchor_x[0], f.anchor_y[0], f.anchor_z[0]};
  f.anchor_hi = f.anchor_lo;
  for (int k = 1; k < f.anchor_count; ++k) {
    const double x[3] = {f.anchor_x[std::size_t(k)], f.anchor_y[std::size_t(k)], f.anchor_z[std::size_t(k)]};
    for (int i = 0; i < 3; ++i)
      f.anchor_lo[std::size_t(i)] = std::min(f.anchor_lo[std::size_t(i)], x[i]),
      f.anchor_hi[std::size_t(i)] = std::max(f.anchor_hi[std::size_t(i)], x[i]);
  }
}

// The frame's combinations of planes for AABBs (see "AABBs, the frame's combinations").
void build_combinations(ExactCertifiedFrustum& f) {
  bool complete = f.has_interior;
  unsigned support[ExactCertifiedFrustum::kCombinations];
  auto add = [&](const int* S, const double* lambda_in, const double* dl_in, int k) {
    double lambda[3], dl[3], largest = 0.0;
    for (int q = 0; q < k; ++q) largest = std::max(largest, lambda_in[q]);
    const int e = std::ilogb(largest);
    for (int q = 0; q < k; ++q) lambda[q] = times_pow2(lambda_in[q], -e), dl[q] = times_pow2(dl_in[q], -e);
    ExactCertifiedFrustum::Combination c;
    double sa = 0.0, sd = 0.0, ea = 0.0, ed = 0.0;
    unsigned mask = 0;
    for (int q = 0; q < k; ++q) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(S[q])];
      c.cx += lambda[q] * p.nx, c.cy += lambda[q] * p.ny, c.cz += lambda[q] * p.nz, c.d += lambda[q] * p.d;
      sa += lambda[q] * p.a, sd += lambda[q] * p.ad, ea += dl[q] * p.a, ed += dl[q] * p.ad;
      mask |= 1u << S[q];
    }
    c.k1 = up(2.0 * ea + M::kCombination * kU * sa) + kUnderflow;
    c.k0 = up(2.0 * ed + M::kCombination * kU * sd) + kUnderflow;
    support[f.comb_count] = mask;
    c.planes = mask;
    f.comb[std::size_t(f.comb_count++)] = c;
  };
  auto normal = [&](int j, int i) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    return i == 0 ? p.nx : i == 1 ? p.ny : p.nz;
  };
  for (int a = 0; a < f.count; ++a)
    for (int b = a + 1; b < f.count; ++b) {
      for (int i = 0; i < 3; ++i) {
        const double na = normal(a, i), nb = normal(b, i);
        if (!((na < 0.0 && nb > 0.0) || (na > 0.0 && nb < 0.0))) continue;
        const int S[2] = {a, b};
        const double lambda[2] = {std::abs(nb), std::abs(na)};
        const double dl[2] = {kU * lambda[0], kU * lambda[1]};
        add(S, lambda, dl, 2);
      }
      for (int c = b + 1; c < f.count; ++c)
        for (int skip = 0; skip < 3; ++skip) {  // the axis left uncancelled
          const int i = skip == 0 ? 1 : 0, k = skip == 2 ? 1 : 2;
          const int S[3] = {a, b, c};
          const double x[3] = {normal(a, i), normal(b, i), normal(c, i)};
          const double y[3] = {normal(a, k), normal(b, k), normal(c, k)};
          double lambda[3], dl[3];
          bool plus = true, minus = true, zero = true;
          for (int q = 0; q < 3; ++q) {
            const int q1 = (q + 1) % 3, q2 = (q + 2) % 3;
            lambda[q] = x[q1] * y[q2] - x[q2] * y[q1];
            const double P = std::abs(x[q1] * y[q2]) + std::abs(x[q2] * y[q1]);
            dl[q] = up(M::kMultiplier * kU * P);
            zero = zero && P == 0.0;
            plus = plus && lambda[q] >= -dl[q];
            minus = minus && lambda[q] <= dl[q];
          }
          if (plus && minus) {
            complete = complete && zero;
            continue;
          }
          if (!plus && !minus) continue;  // mixed signs: no vertex
          for (double& v : lambda) v = std::max(0.0, minus ? -v : v);
          add(S, lambda, dl, 3);
        }
    }
  // comb_in[J] = the combinations whose support lies in J: each combination at its own support,
  // then every set given what its subsets hold, one plane at a time (a sum over subsets).
  for (auto& words : f.comb_in) words = {0, 0};
  for (int q = 0; q < f.comb_count; ++q)
    f.comb_in[support[q]][std::size_t(q / 64)] |= std::uint64_t(1) << (q % 64);
  for (unsigned bit = 1; bit < 64; bit <<= 1)
    for (unsigned J = 0; J < 64; ++J)
      if (J & bit)
        for (std::size_t w = 0; w < 2; ++w) f.comb_in[J][w] |= f.comb_in[J ^ bit][w];
  f.comb_complete = complete;
}

// The planes and the frame's combinations in float, for the AABB array form (see "The AABB array
// form's float pass"): item j is plane j, item count + q combination q. An item that does not fit
// a float is made inert (zero, with an infinite threshold: it proves nothing) and leaves the list
// incomplete; so does a plane, for which the pass is then skipped (J needs every plane).
void build_float_items(ExactCertifiedFrustum& f) {
  using F = FloatPassMargins;
  constexpr double uf = F::u, tiny = F::kSubnormal, widen = 1.0 + F::kWiden, room = F::kRoom;
  double x_safe = std::numeric_limits<float>::max();
  bool complete = f.comb_complete;
  f.float_count = 0;
  auto add = [&](double cx, double cy, double cz, double d, double k1, double k0, std::uint32_t planes) {
    const double a = std::abs(cx) + std::abs(cy) + std::abs(cz);
    int e = a > 0.0 ? std::ilogb(a) : d != 0.0 ? std::ilogb(std::abs(d)) - 100 : 0;
    if (d != 0.0) e = std::max(e, std::ilogb(std::abs(d)) - 100);
    const double c[3] = {times_pow2(cx, -e), times_pow2(cy, -e), times_pow2(cz, -e)}, ds = times_pow2(d, -e);
    ExactCertifiedFrustum::FloatItem q;
    q.cx = float(c[0]), q.cy = float(c[1]), q.cz = float(c[2]), q.d = float(ds);
    q.planes = planes;
    q.max = {std::uint8_t(q.cx >= 0.0f), std::uint8_t(q.cy >= 0.0f), std::uint8_t(q.cz >= 0.0f)};
    std::size_t m = 0;  // the planes in it (one to three), the last one repeated
    for (int k = 0; k < 6 && m < 3; ++k)
      if (planes >> k & 1u) q.member[m++] = std::uint8_t(k);
    for (std::size_t i = m; i < 3; ++i) q.member[i] = q.member[m - 1];
    double e1 = up(times_pow2(k1, -e));
    for (int i = 0; i < 3; ++i) e1 += uf * std::abs(c[i]) + tiny;
    const double af = double(std::abs(q.cx)) + double(std::abs(q.cy)) + double(std::abs(q.cz));
    const double e0 = up(times_pow2(k0, -e)) + uf * std::abs(ds) + tiny;
    q.t = float_at_least(up((e1 + F::kEval * uf * af) * widen));
    q.delta = float_at_least(up((e0 + F::kEval * uf * std::abs(double(q.d))) * widen + F::kUnderflow));
    const bool finite = std::isfinite(q.cx) && std::isfinite(q.cy) && std::isfinite(q.cz) && std::isfinite(q.d) &&
                        std::isfinite(q.t) && std::isfinite(q.delta);
    if (finite) {
      x_safe = std::min(x_safe, (room - std::abs(double(q.d)) - double(q.delta)) / (af + double(q.t)));
    } else {
      q.cx = q.cy = q.cz = q.d = 0.0f;
      q.t = q.delta = std::numeric_limits<float>::infinity();
    }
    f.float_item[std::size_t(f.float_count++)] = q;
    return finite;
  };
  bool planes_fit = true;
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    planes_fit = add(p.nx, p.ny, p.nz, p.d, up(kU * p.a), up(kU * p.ad), 1u << j) && planes_fit;
  }
  for (int q = 0; q < f.comb_count; ++q) {
    const ExactCertifiedFrustum::Combination& c = f.comb[std::size_t(q)];
    complete = add(c.cx, c.cy, c.cz, c.d, c.k1, c.k0, c.planes) && complete;
  }
  f.float_planes = planes_fit ? f.count : 0;
  f.float_no_combination = 0;
  for (std::size_t J = 0; J < 64; ++J)
    f.float_no_combination |= std::uint64_t((f.comb_in[J][0] | f.comb_in[J][1]) == 0) << J;
  f.float_complete = complete && planes_fit;
  f.float_x_safe = x_safe > 0.0 ? float_at_most(x_safe) : 0.0f;
}

}  // namespace

std::string_view to_string(ExactStage s) noexcept {
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
    p.nx = times_pow2(n[0], -e);
    p.ny = times_pow2(n[1], -e);
    p.nz = times_pow2(n[2], -e);
    p.d = times_pow2(d, -e);
    p.a = up(std::abs(p.nx) + std::abs(p.ny) + std::abs(p.nz));
    p.ad = std::abs(p.d);
    p.norm = std::sqrt(p.nx * p.nx + p.ny * p.ny + p.nz * p.nz);
    const double db = M::kBox * kU * p.ad, ds = M::kSphereOffset * kU * p.ad;
    p.d_out_box = next_up(p.d + db);
    p.d_in_box = next_down(p.d - db);
    p.d_out_sphere = next_up(p.d + ds);
    p.d_in_sphere = next_down(p.d - ds);
    a_max = std::max(a_max, p.a);
    const std::pair<ExactCertifiedFrustum::Lane, double> lane[] = {
        {f.kLaneNx, p.nx}, {f.kLaneNy, p.ny}, {f.kLaneNz, p.nz}, {f.kLaneD, p.d},
        {f.kLaneDOutBox, p.d_out_box}, {f.kLaneDInBox, p.d_in_box},
        {f.kLaneDOutSphere, p.d_out_sphere}, {f.kLaneDInSphere, p.d_in_sphere},
        {f.kLaneNorm, p.norm}, {f.kLaneA, p.a}, {f.kLaneAd, p.ad}};
    static_assert(std::size(lane) == ExactCertifiedFrustum::kLaneCount, "every lane filled");
    for (const auto& [row, value] : lane) f.lanes[std::size_t(row)][std::size_t(f.count - 1)] = value;
  }
  for (unsigned set = 0; set < 64; ++set) {
    unsigned pos = 0, neg = 0;
    for (int j = 0; j < f.count; ++j) {
      if (!(set >> j & 1)) continue;
      const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
      const double n[3] = {p.nx, p.ny, p.nz};
      for (int i = 0; i < 3; ++i) pos |= unsigned(n[i] > 0.0) << i, neg |= unsigned(n[i] < 0.0) << i;
    }
    f.same_p_vertex[set] = (pos & neg) == 0;
  }
  f.t_box = up(M::kBox * kU * a_max);
  f.t_sphere = up(M::kSphere * kU * a_max);
  for (int i = 0; i < f.count; ++i)
    for (int j = 0; j < f.count; ++j) {
      const ExactCertifiedPlane &p = f.plane[std::size_t(i)], &q = f.plane[std::size_t(j)];
      f.gram[std::size_t(i)][std::size_t(j)] = p.nx * q.nx + p.ny * q.ny + p.nz * q.nz;
    }
  f.anchor_x.fill(std::numeric_limits<double>::quiet_NaN());
  f.anchor_y = f.anchor_z = f.anchor_x;
  if (!f.empty) find_interior(f);
  if (!f.empty) build_combinations(f);
  if (!f.empty) build_float_items(f);
  return f;
}

namespace {

// ---- Boxes: stages 2 and 3 ---------------------------------------------------------------------

// eps_j = kRow u W_j (1 + kSlack), with W_j computed in a few roundings (covered by the slack).
constexpr double kEpsRow = M::kRow * kU * (1.0 + M::kSlack);

// The rows g_j(t) = a_j0 + sum a_ji t_i of some planes for one box, with their bounds.
// (Left uninitialised: only the first m entries are written and read.)
struct BoxRows {
  int m;
  int plane[6];      // index into f.plane
  double a[6][4];    // a^_j0, a^_j1, a^_j2, a^_j3
  double w[6];       // W_j = A'_j X + |d'_j|
  double eps[6];     // kRow u W_j (1 + kSlack): bounds |fl(g^_j(t)) - g_j(t)| on the cube
};

inline double row_at(const double* a, const double* t) noexcept { return a[0] + a[1] * t[0] + a[2] * t[1] + a[3] * t[2]; }
inline double row_min(const double* a) noexcept { return a[0] - std::abs(a[1]) - std::abs(a[2]) - std::abs(a[3]); }

bool witness(const BoxRows& r, const double* t) noexcept {
  for (int j = 0; j < r.m; ++j)
    if (!(row_at(r.a[j], t) >= r.eps[j])) return false;
  return true;
}

// Proves the box outside with multipliers lambda[q] >= 0 on rows S[q] (see "Farkas" in the file
// comment).
bool farkas(const BoxRows& r, const int* S, const double* given, int k) noexcept {
  double lambda[6];
  if (k > 6 || !normalised(given, k, lambda)) return false;
  double psi0 = 0.0, comb[3] = {0, 0, 0}, weight = 0.0;
  for (int q = 0; q < k; ++q) {
    const double* a = r.a[S[q]];
    psi0 += lambda[q] * a[0];
    for (int i = 0; i < 3; ++i) comb[i] += lambda[q] * a[i + 1];
    weight += lambda[q] * r.w[S[q]];
  }
  const double psi = psi0 + std::abs(comb[0]) + std::abs(comb[1]) + std::abs(comb[2]);
  return weight > 0.0 && psi < -(up(M::kFarkasBox * kU * weight) + kUnderflow);
}

// The box in the cascade: an AABB (aabb set) or an OBB.
struct BoxIn {
  const Aabb* aabb = nullptr;
  const Obb* obb = nullptr;
  bool anchors_tried = false;  // an OBB's anchors failed already (obb_anchor_witness)
};

// Point x in an OBB's coordinates, clamped to the cube (a point of the box).
void obb_coordinates(const Obb& b, const std::array<double, 3>& x, double* t) noexcept {
  for (int i = 0; i < 3; ++i) {
    const glm::vec3& u = b.axes[i];
    const double h = b.half[i];
    const double uu = double(u.x) * u.x + double(u.y) * u.y + double(u.z) * u.z;
    double ti = 0.0;
    if (h > 0.0 && uu > 0.0) {
      const double proj = (x[0] - b.center.x) * u.x + (x[1] - b.center.y) * u.y + (x[2] - b.center.z) * u.z;
      ti = proj / (h * uu);
    }
    t[i] = std::isfinite(ti) ? std::min(1.0, std::max(-1.0, ti)) : 0.0;
  }
}

enum class Tri : std::uint8_t { no, yes, unknown };

// The dual of the programme for at most three rows, by enumeration of its vertices: the minimum
// over lambda >= 0 of psi(lambda) / sum lambda_j W_j lies at a single row, at a pair with one
// t-axis cancelled (lambda_a a_ai + lambda_b a_bi = 0: the edge of two planes against a box axis,
// SAT's cross-product axes) or at a triple with two cancelled (the combined normal along one box
// axis: SAT's box face normals). A negative value proves the box outside (after farkas()); else
// the primal point of the best vertex (complementary slackness: the combined row's p-vertex on
// the other axes, the rows of the support balanced on the cancelled ones) is the witness.
struct Dual {
  double value = 1.0, weight = 0.0;  // psi and sum lambda_j W_j of the best vertex (none yet: 1 / 0)
  int k = 0;
  int S[3] = {0, 0, 0};
  double lambda[3] = {0, 0, 0};
  int zero[2] = {-1, -1};
};

template <int k>
void offer(const BoxRows& r, Dual& best, const int* S, const double* lambda, const int* zero) {
  double psi = 0.0, weight = 0.0;
  for (int q = 0; q < k; ++q) psi += lambda[q] * r.a[S[q]][0], weight += lambda[q] * r.w[S[q]];
  for (int i = 1; i <= 3; ++i) {
    double c = 0.0;
    for (int q = 0; q < k; ++q) c += lambda[q] * r.a[S[q]][i];
    psi += std::abs(c);
  }
  if (!(weight > 0.0)) return;
  // psi / weight < best.value, compared without dividing (weights are positive).
  if (!(psi * best.weight < best.value * weight)) return;
  best.value = psi;
  best.weight = weight;
  best.k = k;
  for (int q = 0; q < 3; ++q) best.S[q] = q < k ? S[q] : 0, best.lambda[q] = q < k ? lambda[q] : 0.0;
  best.zero[0] = zero ? zero[0] : -1;
  best.zero[1] = zero && k == 3 ? zero[1] : -1;
}

Dual best_dual(const BoxRows& r) {
  Dual best;
  const double one = 1.0;
  for (int a = 0; a < r.m; ++a) offer<1>(r, best, &a, &one, nullptr);
  for (int a = 0; a < r.m; ++a)
    for (int b = a + 1; b < r.m; ++b) {
      for (int i = 1; i <= 3; ++i) {
        if (!(r.a[a][i] * r.a[b][i] < 0.0)) continue;
        const int S[2] = {a, b};
        const double lambda[2] = {std::abs(r.a[b][i]), std::abs(r.a[a][i])};
        const int zero[1] = {i};
        offer<2>(r, best, S, lambda, zero);
      }
      for (int c = b + 1; c < r.m; ++c) {
        const int S[3] = {a, b, c};
        for (int l = 1; l <= 3; ++l) {
          const int i = l == 1 ? 2 : 1, k = l == 3 ? 2 : 3;  // the two cancelled axes
          // lambda orthogonal to columns i and k over rows a, b, c: their cross product.
          const double x[3] = {r.a[a][i], r.a[b][i], r.a[c][i]}, y[3] = {r.a[a][k], r.a[b][k], r.a[c][k]};
          double lambda[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
          if (lambda[0] <= 0.0 && lambda[1] <= 0.0 && lambda[2] <= 0.0)
            for (double& v : lambda) v = -v;
          if (!(lambda[0] >= 0.0 && lambda[1] >= 0.0 && lambda[2] >= 0.0)) continue;
          const int zero[2] = {i, k};
          offer<3>(r, best, S, lambda, zero);
        }
      }
    }
  return best;
}

// The primal point of a dual vertex (see best_dual), clamped to the cube.
void primal(const BoxRows& r, const Dual& d, double* t) {
  for (int i = 1; i <= 3; ++i) {
    double c = 0.0;
    for (int q = 0; q < d.k; ++q) c += d.lambda[q] * r.a[d.S[q]][i];
    t[i - 1] = c > 0.0 ? 1.0 : c < 0.0 ? -1.0 : 0.0;
  }
  // The rows of the support scaled by 1 / W: equal at the optimum. Unknowns: the cancelled axes.
  // (A proposal only, checked by witness(): reciprocals instead of a division per entry.)
  double inv_w[3] = {0, 0, 0};
  for (int q = 0; q < d.k; ++q) inv_w[q] = 1.0 / r.w[d.S[q]];
  auto scaled = [&](int q, int i) { return r.a[d.S[q]][i] * inv_w[q]; };
  auto rest = [&](int q) {  // the scaled row at t with the cancelled axes at 0
    double v = scaled(q, 0);
    for (int i = 1; i <= 3; ++i)
      if (i != d.zero[0] && i != d.zero[1]) v += scaled(q, i) * t[i - 1];
    return v;
  };
  if (d.k == 2) {
    const int i = d.zero[0];
    const double den = scaled(0, i) - scaled(1, i);
    if (den != 0.0) t[i - 1] = (rest(1) - rest(0)) / den;
  } else if (d.k == 3) {
    const int i = d.zero[0], k = d.zero[1];
    // (row0 - row1) and (row0 - row2) vanish: a 2x2 system in t_i, t_k.
    const double m00 = scaled(0, i) - scaled(1, i), m01 = scaled(0, k) - scaled(1, k);
    const double m10 = scaled(0, i) - scaled(2, i), m11 = scaled(0, k) - scaled(2, k);
    const double b0 = rest(1) - rest(0), b1 = rest(2) - rest(0);
    const double det = m00 * m11 - m01 * m10;
    if (det != 0.0) {
      t[i - 1] = (b0 * m11 - m01 * b1) / det;
      t[k - 1] = (m00 * b1 - b0 * m10) / det;
    }
  }
  for (int i = 0; i < 3; ++i) t[i] = std::isfinite(t[i]) ? std::min(1.0, std::max(-1.0, t[i])) : 0.0;
}

// Whether the box meets P_J (the rows r): yes (a certified witness), no (a certified Farkas
// combination), or unknown (inside every bound).
Tri box_meets(const ExactCertifiedFrustum& f, const BoxIn& b, const BoxRows& r) {
  const double centre[3] = {0, 0, 0};
  if (witness(r, centre)) return Tri::yes;
  if (r.m <= 3) {
    const Dual d = best_dual(r);
    if (d.value < 0.0 && farkas(r, d.S, d.lambda, d.k)) return Tri::no;
    double t[3];
    primal(r, d, t);
    if (witness(r, t)) return Tri::yes;
  }
  // The frame's anchors in the box's coordinates, clamped to the cube: the point of the box
  // nearest each (an AABB's; an OBB's in its own axes). An AABB was compared with every anchor
  // already (holds_anchor); of the points nearest them, that nearest the interior point is the
  // one that proves what the programme below would otherwise have to.
  if (b.obb && !b.anchors_tried && exact_lanes::obb_anchor_witness(f, *b.obb, r.m, r.a, r.eps)) return Tri::yes;
  if (b.aabb && f.anchor_count > 0) {
    double t[3];
    const double x[3] = {f.anchor_x[0], f.anchor_y[0], f.anchor_z[0]};
    for (int i = 0; i < 3; ++i) {
      const double lo = b.aabb->min[i], hi = b.aabb->max[i], h = 0.5 * (hi - lo);
      const double ti = h > 0.0 ? (x[i] - 0.5 * (lo + hi)) / h : 0.0;
      t[i] = std::isfinite(ti) ? std::min(1.0, std::max(-1.0, ti)) : 0.0;
    }
    if (witness(r, t)) return Tri::yes;
  }
  // The programme with w_j = W_j: eps_j is the same multiple of W_j for every j, so its optimum
  // is the best candidate for both certificates.
  const LpAnswer lp = max_min_lp(r.m, r.a, r.w);
  if (!lp.ok) return Tri::unknown;
  if (lp.s > 0.0 && witness(r, lp.t)) return Tri::yes;
  const int all[6] = {0, 1, 2, 3, 4, 5};
  if (lp.s < 0.0 && farkas(r, all, lp.lambda, r.m)) return Tri::no;
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
                   const double* given, double r) noexcept {
  double lambda[3];
  if (k > 3 || !normalised(given, k, lambda)) return false;
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
  const double value_up = value + up(M::kFarkasCentre * kU * weight) + kUnderflow;
  if (!(value_up < 0.0)) return false;
  const double len_up =
      up(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]) * (1.0 + 4.0 * kU) + M::kFarkasNormal * kU * na) + kUnderflow;
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
  // The nearest feasible projection onto the planes of a subset of J, feasible to within a strict
  // tolerance (a few dozen units of u of the magnitude) and to within a loose one (1e-9 of it,
  // for ill-conditioned planes whose projections round more): the strict one is tried first.
  struct Nearest {
    double dist2 = std::numeric_limits<double>::infinity();
    double x[3] = {0, 0, 0};
    double lambda[3] = {0, 0, 0};
    int S[3] = {0, 0, 0};
    int k = -1;
  } strict, loose;
  auto consider = [&](const int* S, int k, const double* mu) {
    double x[3] = {c[0], c[1], c[2]}, dist2 = 0.0;
    for (int q = 0; q < k; ++q) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(S[q])];
      x[0] -= mu[q] * p.nx;
      x[1] -= mu[q] * p.ny;
      x[2] -= mu[q] * p.nz;
      dist2 += mu[q] * sc[S[q]];
    }
    if (!(dist2 < loose.dist2 || dist2 < strict.dist2)) return;
    // Each plane's value against its magnitude p.a xm + p.ad (positive), compared without
    // dividing: within 64 u of it (strict), within 1e-9 of it (loose).
    const double xm = max_abs3(x);
    bool in_strict = true, in_loose = true;
    for (int q = 0; q < m; ++q) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(js[q])];
      const double v = plane_at(p, x), size = p.a * xm + p.ad;
      in_strict = in_strict && v >= -64.0 * kU * size;
      in_loose = in_loose && v >= -1e-9 * size;
    }
    auto keep = [&](Nearest& n) {
      n.dist2 = dist2;
      n.k = k;
      for (int i = 0; i < 3; ++i) n.x[i] = x[i];
      for (int q = 0; q < k; ++q) n.S[q] = S[q], n.lambda[q] = std::max(0.0, -mu[q]);
    };
    if (in_strict && dist2 < strict.dist2) keep(strict);
    if (in_loose && dist2 < loose.dist2) keep(loose);
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
      const double inv = 1.0 / D;  // (the multipliers only propose: one division, not two)
      const double mu2[2] = {(G[b][b] * sc[a] - G[a][b] * sc[b]) * inv, (G[a][a] * sc[b] - G[a][b] * sc[a]) * inv};
      consider(S2, 2, mu2);
      for (int qc = qb + 1; qc < m; ++qc) {
        const int cc = js[qc];
        const double e00 = G[a][a], e01 = G[a][b], e02 = G[a][cc], e11 = G[b][b], e12 = G[b][cc], e22 = G[cc][cc];
        const double c00 = e11 * e22 - e12 * e12, c01 = e02 * e12 - e01 * e22, c02 = e01 * e12 - e02 * e11;
        const double c11 = e00 * e22 - e02 * e02, c12 = e01 * e02 - e00 * e12, c22 = e00 * e11 - e01 * e01;
        const double D3 = e00 * c00 + e01 * c01 + e02 * c02;
        if (!(D3 > 1e-12 * e00 * e11 * e22)) continue;
        const int S3[3] = {a, b, cc};
        const double inv3 = 1.0 / D3;
        const double mu3[3] = {(c00 * sc[a] + c01 * sc[b] + c02 * sc[cc]) * inv3,
                               (c01 * sc[a] + c11 * sc[b] + c12 * sc[cc]) * inv3,
                               (c02 * sc[a] + c12 * sc[b] + c22 * sc[cc]) * inv3};
        consider(S3, 3, mu3);
      }
    }
  }
  const double r2 = r * r;
  auto prove = [&](const Nearest& n) {
    if (n.k < 0) return Tri::unknown;
    if (n.dist2 < r2) {
      if (!f.has_interior) return Tri::unknown;
      // Pull the projection towards g by half the room left in the ball.
      const double d = std::sqrt(std::max(0.0, n.dist2));
      double gx[3], gl = 0.0;
      for (int i = 0; i < 3; ++i) gx[i] = f.interior[std::size_t(i)] - n.x[i], gl += gx[i] * gx[i];
      gl = std::sqrt(gl);
      if (!(gl > 0.0)) return Tri::unknown;
      const double eta = std::min(1.0, 0.5 * (r - d) / gl);
      double x[3];
      for (int i = 0; i < 3; ++i) x[i] = n.x[i] + eta * gx[i];
      return sphere_witness(f, J, s, x) ? Tri::yes : Tri::unknown;
    }
    if (n.dist2 > r2 && sphere_farkas(f, sc, wc, n.S, n.k, n.lambda, r)) return Tri::no;
    return Tri::unknown;
  };
  const Tri first = prove(strict);
  if (first != Tri::unknown || (loose.k == strict.k && loose.dist2 == strict.dist2)) return first;
  return prove(loose);
}

}  // namespace

// ---- Stage 1 and the cascades ------------------------------------------------------------------

namespace {

// Row n's bounds for plane j: W = A'_j X + |d'_j| and eps = kRow u W (1 + kSlack), X the volume's
// magnitude (AABB: M; OBB: M_c + H).
inline void row_bounds(const ExactCertifiedFrustum& f, BoxRows& r, int n, int j, double X) noexcept {
  const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
  r.plane[n] = j;
  r.w[n] = p.a * X + p.ad;
  r.eps[n] = r.w[n] * kEpsRow;
}

// The bounds of the rows of the planes in J (computed once stage 1 has not decided), the rows
// kept in order.
void finish_rows(const ExactCertifiedFrustum& f, BoxRows& r, double X, unsigned J) {
  int n = 0;
  for (int j = 0; j < r.m; ++j) {
    if (!(J >> j & 1)) continue;
    if (n != j)
      for (int i = 0; i < 4; ++i) r.a[n][i] = r.a[j][i];
    row_bounds(f, r, n++, j, X);
  }
  r.m = n;
}

// Whether the box holds one of the frame's anchors (none when it misses their bounding box).
bool holds_anchor(const ExactCertifiedFrustum& f, const Aabb& b) noexcept {
  const double lx = b.min.x, ly = b.min.y, lz = b.min.z, hx = b.max.x, hy = b.max.y, hz = b.max.z;
  if (!(lx <= f.anchor_hi[0] && f.anchor_lo[0] <= hx && ly <= f.anchor_hi[1] && f.anchor_lo[1] <= hy &&
        lz <= f.anchor_hi[2] && f.anchor_lo[2] <= hz))
    return false;
  for (int k = 0; k < f.anchor_count; ++k) {
    const double x = f.anchor_x[std::size_t(k)], y = f.anchor_y[std::size_t(k)], z = f.anchor_z[std::size_t(k)];
    if (lx <= x && x <= hx && ly <= y && y <= hy && lz <= z && z <= hz) return true;
  }
  return false;
}

// An AABB in centre-extent form: c = fl((lo + hi) / 2), h = fl((hi - lo) / 2), one rounding each.
struct CentreExtent {
  double c0, c1, c2, h0, h1, h2;
};
inline CentreExtent centre_extent(const Aabb& b) noexcept {
  const double lo0 = b.min.x, lo1 = b.min.y, lo2 = b.min.z, hi0 = b.max.x, hi1 = b.max.y, hi2 = b.max.z;
  return {0.5 * (lo0 + hi0), 0.5 * (lo1 + hi1), 0.5 * (lo2 + hi2), 0.5 * (hi0 - lo0), 0.5 * (hi1 - lo1), 0.5 * (hi2 - lo2)};
}

// Stage 1 of an AABB: per plane s = n'.c and rad = sum |n'_i h_i|, so that the p-vertex value is
// s + d + rad and the n-vertex value s + d - rad, with no per-axis choice (see "Stage 1" in the
// file comment). Bit j of J: plane j not proved to hold the box; of crossing: proved to cut it;
// of p_in: its p-vertex proved inside it. Returns false when a plane proves the box outside.
template <bool kSix>
bool aabb_planes(const ExactCertifiedFrustum& f, const Aabb& b, const CentreExtent& e, double& m, unsigned& J,
                 unsigned& crossing, unsigned& p_in) noexcept {
  m = std::max(std::max(std::max(double(b.max.x), double(b.max.y)), double(b.max.z)),
               -std::min(std::min(double(b.min.x), double(b.min.y)), double(b.min.z)));
  const double T = f.t_box * m, neg_t = -T;
  unsigned jm = 0, cm = 0, pm = 0;
  const int count = kSix ? 6 : f.count;
#pragma GCC unroll 6
  for (int j = 0; j < count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    const double s = (p.nx * e.c0 + p.ny * e.c1) + p.nz * e.c2;
    const double rad = (std::abs(p.nx * e.h0) + std::abs(p.ny * e.h1)) + std::abs(p.nz * e.h2);
    const double so = s + p.d_out_box, si = s + p.d_in_box;
    if (so + rad < neg_t) return false;
    jm |= unsigned(!(si - rad >= T)) << j;
    cm |= unsigned(so - rad < neg_t) << j;
    pm |= unsigned(si + rad >= T) << j;
  }
  J = jm;
  crossing = cm;
  p_in = pm & jm;
  return true;
}

// The rows of every plane for an AABB (stage 2, "Stage 2 rows" in the file comment).
void aabb_rows(const ExactCertifiedFrustum& f, const CentreExtent& e, BoxRows& r) noexcept {
  for (int j = 0; j < f.count; ++j) {
    const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
    double* a = r.a[j];
    a[0] = ((p.nx * e.c0 + p.ny * e.c1) + p.nz * e.c2) + p.d;
    a[1] = p.nx * e.h0, a[2] = p.ny * e.h1, a[3] = p.nz * e.h2;
  }
  r.m = f.count;
}

// Stage 2 of an AABB on the frame's combinations within J (see "AABBs, the frame's
// combinations"): no when one proves the box outside; yes when the list is complete, every plane
// of J has its p-vertex proved inside (`singles`) and every combination proves the box on its
// inner side; unknown otherwise. m: the box's magnitude (stage 1's).
Tri aabb_combinations(const ExactCertifiedFrustum& f, const CentreExtent& e, double m, unsigned J, bool singles) noexcept {
  bool positive = singles && f.comb_complete;
  for (std::size_t w = 0; w < 2; ++w)
    for (std::uint64_t bits = f.comb_in[J][w]; bits != 0; bits &= bits - 1) {
      const ExactCertifiedFrustum::Combination& q = f.comb[64 * w + std::size_t(__builtin_ctzll(bits))];
      const double v = ((q.cx * e.c0 + q.cy * e.c1) + (q.cz * e.c2 + q.d)) +
                       ((std::abs(q.cx) * e.h0 + std::abs(q.cy) * e.h1) + std::abs(q.cz) * e.h2);
      const double t = up(q.k1 * m + q.k0);
      if (v < -t) return Tri::no;
      positive = positive && v > t;
    }
  return positive ? Tri::yes : Tri::unknown;
}

}  // namespace

Visibility exact_certified_aabb(const ExactCertifiedFrustum& f, const Aabb& b, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  unsigned J, crossing, p_in;
  double m;
  const CentreExtent e = centre_extent(b);
  if (!(f.count == 6 ? aabb_planes<true>(f, b, e, m, J, crossing, p_in) : aabb_planes<false>(f, b, e, m, J, crossing, p_in)))
    return Visibility::outside;
  if (J == 0) return Visibility::inside;
  if (crossing) {
    // The planes of J whose normals agree in sign on every axis share their p-vertex: when each
    // proved it inside, it is a common point (one plane: its own p-vertex).
    if (p_in == J && f.same_p_vertex[J]) return Visibility::intersecting;
    set_stage(stage, ExactStage::axes);
    // An anchor of the frame (a point certified inside every plane) that the box holds, compared
    // exactly: first when three or more planes are left (a large box; many combinations), after
    // the combinations when two are (one to three combinations, and rarely an anchor held).
    const unsigned rest = J & (J - 1);  // J without its lowest plane
    const bool two = (rest & (rest - 1)) == 0;
    if (!two && holds_anchor(f, b)) return Visibility::intersecting;
    const Tri meets = aabb_combinations(f, e, m, J, p_in == J);
    if (meets != Tri::unknown) return meets == Tri::yes ? Visibility::intersecting : Visibility::outside;
    if (two && holds_anchor(f, b)) return Visibility::intersecting;
  }
  BoxRows r;
  aabb_rows(f, e, r);
  finish_rows(f, r, m, J);
  return box_rest(f, BoxIn{&b, nullptr}, r, crossing, stage);
}

namespace {

// The rows of the planes in J for stage 2, from the plane stage's lanes (as finish_rows).
void obb_rows(const ExactCertifiedFrustum& f, const exact_lanes::ObbPlaneStage& q, double X, BoxRows& r) noexcept {
  int n = 0;
  for (unsigned bits = q.J; bits != 0; bits &= bits - 1, ++n) {
    const int j = __builtin_ctz(bits);
    for (int i = 0; i < 4; ++i) r.a[n][i] = q.a[i][j];
    row_bounds(f, r, n, j, X);
  }
  r.m = n;
}

}  // namespace

Visibility exact_certified_obb(const ExactCertifiedFrustum& f, const Obb& b, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  // e_i = h_i u_i is exact in double (a product of two floats).
  const double c[3] = {b.center.x, b.center.y, b.center.z};
  double e[3][3], H = 0.0;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3& u = b.axes[i];
    const double h = b.half[i];
    e[i][0] = h * u.x, e[i][1] = h * u.y, e[i][2] = h * u.z;
    H += h * std::max(std::abs(double(u.x)), std::max(std::abs(double(u.y)), std::abs(double(u.z))));
  }
  const double X = max_abs3(c) + H;
  // Stage 1 on every plane at once (exact_lanes.cpp: the operations of the derivation, per lane).
  exact_lanes::ObbPlaneStage q;
  exact_lanes::obb_plane_stage(f, c, e, f.t_box * X, q);
  if (q.outside) return Visibility::outside;
  if (q.J == 0) return Visibility::inside;
  // Rows of J agreeing in sign on every axis share their p-vertex (see the AABB).
  if (q.shared) return Visibility::intersecting;
  // Five or six planes left (a box about as large as the frustum): the point of the box nearest
  // the frame's interior point, then those nearest the other anchors, are stage 2's witnesses for
  // most such boxes; tried before box_rest rechecks and filters the rows (a row it drops is at
  // least eps_j on the whole cube, so the answer is the same). The first on the rows in lanes,
  // before they are copied out.
  unsigned fifth = q.J;  // J with its four lowest planes removed: not empty with five or more
  for (int k = 0; k < 4; ++k) fifth &= fifth - 1;
  const bool large = q.crossing && f.has_interior && fifth != 0;
  if (large) {
    set_stage(stage, ExactStage::axes);
    double t[3];
    obb_coordinates(b, f.interior, t);
    if ((exact_lanes::obb_rows_short(f, q, t, X, kEpsRow) & q.J) == 0) return Visibility::intersecting;
  }
  BoxRows r;
  obb_rows(f, q, X, r);
  if (large && exact_lanes::obb_anchor_witness(f, b, r.m, r.a, r.eps)) return Visibility::intersecting;
  return box_rest(f, BoxIn{nullptr, &b, large}, r, q.crossing, stage);
}

Visibility exact_certified_sphere(const ExactCertifiedFrustum& f, const Sphere& s, ExactStage* stage) {
  set_stage(stage, ExactStage::planes);
  if (f.empty) return Visibility::outside;
  const double c[3] = {s.center.x, s.center.y, s.center.z}, r = s.radius;
  const double mc = max_abs3(c);
  const double T = f.t_sphere * (mc + r);
  // Stage 1 on every plane at once (exact_lanes.cpp: per plane v = n'.c, rho = r norm', the
  // comparisons below, and the centre's values sc = v + d' with their bounds wc).
  exact_lanes::SpherePlaneStage q;
  exact_lanes::sphere_plane_stage(f, c, r, mc, T, q);
  if (q.outside) return Visibility::outside;
  const unsigned J = q.J, crossing = q.crossing, reach = q.reach, centre_in = q.centre_in;
  const double* sc = q.sc;
  const double* wc = q.wc;
  if (J == 0) return Visibility::inside;
  if (crossing) {
    // One plane left, reached by the ball: it meets the frustum inside that plane. The centre in
    // every plane of J: the centre is a common point.
    if (((J & (J - 1)) == 0 && reach == J) || centre_in == J) return Visibility::intersecting;
  }
  set_stage(stage, ExactStage::axes);
  if (crossing) {
    // An anchor of the frame (certified inside every plane) within the ball: all at once.
    if (exact_lanes::anchor_in_ball(f, c, r * r)) return Visibility::intersecting;
  }
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

}  // namespace cullproof

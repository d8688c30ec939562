// Certified conservative plane tests: point, sphere, AABB (n/p-vertex), OBB (n/p-vertex).
//
// Sources: the tests are Assarsson & Möller 2000 §3.1 (n/p vertex, normal projected on the box
// axes for OBBs) and Lighthouse3D's sphere test; the error analysis is the standard model of
// floating-point arithmetic (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
// §2.2 and §3.1): fl(x op y) = (x op y)(1 + e), |e| <= u = 2^-24 for binary32, plus an absolute
// error of at most 2^-150 for a product that underflows (sums of floats that underflow are exact).
// Claim: certified-conservative.
//
// Derivation (the notation of cullproof/core/certified.hpp: float plane (n^, d^), true plane (n, d),
// bound a >= |true coefficients| with |n^_i - n_i| <= u a_i, |d^ - d| <= u a_d):
//
//  Plane value at a float point p, S = n.p + d (true). The code computes
//  s^ = fl(n^_x p_x + n^_y p_y + n^_z p_z + d^) in any order, with or without FMA. A length-4
//  inner product satisfies |s^ - (n^.p + d^)| <= g4 (sum |n^_i p_i| + |d^|), g_k = k u/(1 - k u)
//  (Higham (3.4); an FMA only removes roundings, so the bound holds both ways). With
//  |n^_i| <= (1 + u) a_i:
//      |s^ - S| <= (g4 (1 + u) + u) B <= 5.0001 u B,   B = sum a_i |p_i| + a_d <= A M + a_d,
//  where A = a_x + a_y + a_z and M bounds |p_i|. The threshold is computed in float as
//      t = 2^-21 fl(fl(A' M) + a_d) + 2^-126       (A' = A rounded up)
//  Each of the two roundings loses at most a factor (1 - u); the power-of-two scaling is exact
//  unless subnormal (error <= 2^-150); 2^-126 covers every absolute underflow error (a few
//  2^-150) and the final rounding. So t >= 8 u (1 - u)^3 B > 5.0001 u B + underflow: whenever
//  s^ < -t, S < 0 (the point is outside), and whenever s^ >= t, S > 0 (inside).
//
//  AABB: the p- and n-vertices are chosen by the sign of n^_i, which is the sign of n_i (a
//  rounded sum has the sign of the exact sum, and is zero only when it is exact zero), so they
//  are the true extreme vertices; M = max |min_j|, |max_j|.
//
//  Sphere: outside iff n.c + d + r |n| < 0. nu = |n^| is computed in double (the squares of
//  floats are exact there, never below 2^-298; two sums and the root: within 2^-51 |n^|), and
//  rho^ = fl(r nu) in double, rounded to float once: within (u + 2^-50) r |n^| + 2^-150 (the
//  float rounding, subnormal or not) of r |n^|. (In float, fl(n^.n^) would lose every square
//  below 2^-149, which is all of them when |n^| < 2^-75.) With ||n^| - |n|| <= |n^ - n| <= u A,
//  rho^ is within 2.01 u r A + 2^-150 of r |n|; the final sum rounds once more. In all
//  |fl(s^ +- rho^) - (S +- r|n|)| <= 11 u (A (M + r) + a_d), covered by
//      t = 2^-20 fl(fl(A' fl(M + r)) + a_d) + 2^-126   (16 u).
//
//  OBB: S_max/min = n.c + d +- sum_i h_i |n.u_i|. q^_i = fl(n^.u_i) is within
//  (g3 (1 + u) + u) A U_i <= 4.0001 u A U_i of n.u_i (U_i = max_j |u_ij|); r^ = fl(sum h_i |q^_i|)
//  is within 7.01 u A H of sum h_i |n.u_i| (H = sum h_i U_i); with s^ at c and the final sum:
//  |error| <= 13.1 u (A (M_c + H) + a_d), covered by t = 2^-20 fl(fl(A' fl(M_c + H)) + a_d) + 2^-126
//  (16 u (1 - u)^4 > 13.1 u).
//
//  Fast path (AABBs and spheres, M <= m_safe): the margin above costs a product and a sum per
//  plane and volume. It is split instead into a part that does not depend on the volume, folded
//  into the plane's offset once per frame, and a part proportional to M made uniform over the
//  planes, so that a volume pays one product T = fl(t M) in all:
//  - plane k is scaled by 2^-e (e = ilogb A_k): n' = n^ 2^-e rounded away from zero (exact
//    unless subnormal; the rounding error, if any, is added to the bound, a'_i >= a_i 2^-e +
//    |n'_i - n^_i 2^-e| / u, and the sign is n^'s, so the p- and n-vertices are still the true
//    ones), d^ 2^-e kept exact in double, a'_d = a_d 2^-e. The scaled plane is the same half
//    space; its bound sum A' is in [1, 2) unless |d| forces a larger e (then A' < 1).
//  - d_out >= d^ 2^-e + delta and d_in <= d^ 2^-e - delta (rounded outwards in double, then to
//    float), with delta = 2^-21 a'_d + 2^-126 (boxes) or 2^-20 a'_d + 2^-126 (spheres);
//  - t = 2^-21 max_k A'_k (boxes) or 2^-20 max_k A'_k (spheres), rounded up.
//  Box: outside if some fl(n'.p + d_out) < -T at the p-vertex p, inside if every
//  fl(n'.q + d_in) >= T at the n-vertex q. With v the computed value, E = n'.p + d_out and S'
//  the true scaled plane's value: |v - E| <= g4 ((1 + u) A' M + |d_out|), |n'.p + d^ 2^-e - S'|
//  <= u (A' M + a'_d) and d_out - d^ 2^-e >= delta, so v < -T gives
//      S' < -T - delta + g4 ((1 + u) A' M + (1 + u) a'_d + delta) + u (A' M + a'_d) < 0,
//  since T >= 8 u (1 - u) A' M > 5.0001 u A' M and delta (1 - g4) >= 8 u a'_d > 5.0001 u a'_d
//  (2^-126 absorbs the underflow errors: a few 2^-150 in the products and in T). The inside
//  test is the mirror image. Sphere: the same with m = fl(M + r), rho = fl(r nu') and the 11 u
//  bound, covered by 16 u in t and delta; nu' = |n'| in double rounded to float is within
//  u |n'| + 2^-150 of it, the second term only when nu' is subnormal (A' < 2^-126), and then
//  t gets 2^-149 more, so that T >= 2^-149 (M + r) covers r 2^-150. Both are sound with or without FMA, like the
//  per-plane margins; they are at most 2x wider than those on the A M part (A'_k >= 1 >
//  max A'/2 for scaled planes) and equal on the constant part.
//  M of a box is max_j max(max_j, -min_j), equal to max_j max(|min_j|, |max_j|) for a valid
//  box and free of sign tests.
//
//  Overflow: a non-finite s^ or t decides nothing (the answer is `intersecting`). If t is finite
//  every term and partial sum is at most about t 2^20 < FLT_MAX, so s^ is exact to the bound.
//
//  Degenerate planes: n^ == 0 exactly iff n == 0 (a rounded sum is zero only when exact), and
//  sign(d^) == sign(d): such a plane is decided exactly (all space when d^ >= 0, nothing when
//  d^ < 0).
//
//  End to end (CaseFrustum::matrix): n^ = fl(r4 +- rk) has |n^_i - n_i| <= u |r4_i +- rk_i|
//  <= u (|r4_i| + |rk_i|) =: u a_i (the [0,1] near plane is a row itself: exact, a = |r3|).
//  Where the rows reach past FLT_MAX, frustum_from_matrix extracts half the plane instead,
//  n^ = fl(fl(r4/2) +- fl(rk/2)), and the true plane is taken as (r4 +- rk)/2 (the same
//  half-space). Halving is exact unless an entry is subnormal (then it rounds by at most
//  2^-150), so |n^_i - n_i| <= u (|r4_i| + |rk_i|)/2 + 2^-149 (1 + u) <= u a_i with
//  a_i = (|r4_i| + |rk_i|)/2, plus 2^-124 where an entry is subnormal. Every a_i is then at most
//  FLT_MAX: the bounds of a finite matrix are finite.
#include "cullproof/core/certified.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cullproof {

// The factors of CertifiedMargins against the derivation above, from u = 2^-24 alone (in long
// double: a 64-bit significand): a changed factor, or a changed computation whose derivation is
// not redone here, does not compile.
namespace margin_derivation {

using L = long double;
constexpr L u = 0x1p-24L;
constexpr L gamma(int k) { return k * u / (1 - k * u); }
constexpr L root(L x) {  // Newton's iteration from above: converges to sqrt(x) for x near 1
  L r = x > 1 ? x : 1;
  for (int i = 0; i < 64; ++i) r = (r + x / r) / 2;
  return r;
}
constexpr L cube(L x) { return x * x * x; }

// The plane value s = fl(n^.p + d^) in any order, with or without FMA, against the true plane: a
// four-term inner product (gamma_4) of terms within (1 + u) of the bound, plus the float
// coefficients' own error u.
constexpr L plane_value = gamma(4) * (1 + u) + u;
static_assert(L(CertifiedMargins::kNarrow) == 8 * u && L(CertifiedMargins::kWide) == 16 * u &&
              CertifiedMargins::kUnderflow == 0x1p-126f, "the factors are powers of two of u");

// Points and boxes: t = kNarrow fl(fl(A' M) + a_d), two roundings of the bound and the product
// with kNarrow, (1 - u)^3 at worst.
static_assert(plane_value <= 5.0001L * u, "a plane value errs by at most 5.0001 u");
static_assert(L(CertifiedMargins::kNarrow) * cube(1 - u) > plane_value, "kNarrow covers points and boxes");

// Spheres: nu = fl(sqrt(fl(n^.n^))): the sum of squares within gamma_3, the root halves it, one
// more rounding; with ||n^| - |n|| <= u A; rho = fl(r nu); the final fl(s +- rho).
constexpr L sqrt_err = std::max((1 + u) * root(1 + gamma(3)) - 1, 1 - (1 - u) * root(1 - gamma(3)));
static_assert(sqrt_err <= 2.6L * u, "|nu - |n^|| <= 2.6 u |n^|");
constexpr L nu_err = sqrt_err * (1 + u) + u;
static_assert(nu_err <= 3.7L * u, "nu within 3.7 u A of |n|");
constexpr L rho_err = u * (1 + nu_err) + nu_err;
static_assert(rho_err <= 4.8L * u, "rho within 4.8 u r A of r |n|");
constexpr L sphere_total = plane_value + rho_err + u * (1 + 6 * u);
static_assert(sphere_total <= 11 * u, "a sphere's test errs by at most 11 u");
static_assert(L(CertifiedMargins::kWide) * cube(1 - u) > sphere_total, "kWide covers spheres (three roundings)");

// OBBs: q_i = fl(n^.u_i), r = fl(sum h_i |q_i|), the centre's plane value, the final sum.
constexpr L q_err = gamma(3) * (1 + u) + u;
static_assert(q_err <= 4.0001L * u, "q_i within 4.0001 u A U_i");
constexpr L r_err = gamma(3) * (1 + q_err) + q_err * (1 + gamma(3));
static_assert(r_err <= 7.01L * u, "the projected half-width within 7.01 u");
constexpr L obb_total = plane_value + r_err + u * (1 + 13 * u);
static_assert(obb_total <= 13.1L * u, "an OBB's test errs by at most 13.1 u");
static_assert(L(CertifiedMargins::kWide) * cube(1 - u) * (1 - u) > obb_total, "kWide covers OBBs (four roundings)");

// The batch's fast path: T >= kNarrow (1 - u) A' M and delta (1 - gamma_4) >= kNarrow a'_d exceed
// the plane value's error on each part; spheres the 11 u bound under kWide.
static_assert(L(CertifiedMargins::kNarrow) * (1 - u) > plane_value, "T covers the A' M part");
static_assert(L(CertifiedMargins::kNarrow) * (1 - gamma(4)) > plane_value, "delta covers the constant part");
static_assert(L(CertifiedMargins::kWide) * (1 - u) * (1 - u) > 11 * u, "spheres' T");
static_assert(L(CertifiedMargins::kWide) * (1 - gamma(4)) > 11 * u, "spheres' delta");

// Ball membership: fl(fl(s K) + E) < fl(r r) proves sum (x_i - c_i)^2 < r^2: the differences (u
// each), three squares and two sums (gamma_3, and 2^-150 per square that underflows), fl(r r) (u,
// and 2^-150), and the check's own two roundings; E / 2 (what the roundings keep of it) covers
// 5 2^-150, each grown by at most 1 / ((1 - gamma_3)(1 - u)^2).
static_assert((1 + u) / (L(CertifiedMargins::kBallScale) * cube(1 - u) * (1 - u) * (1 - gamma(3))) <= 1,
              "kBallScale covers the roundings of the ball test");
static_assert(L(CertifiedMargins::kBallAbsolute) / 2 >= 5 * 0x1p-150L / ((1 - gamma(3)) * (1 - u) * (1 - u)),
              "kBallAbsolute covers the underflows of the ball test");

}  // namespace margin_derivation

namespace {

constexpr float kTiny = CertifiedMargins::kUnderflow;
constexpr double kNarrow = CertifiedMargins::kNarrow, kWide = CertifiedMargins::kWide;

// x rounded to a float away from zero: never 0 for x != 0, so the sign survives any scaling.
float away_from_zero(double x) noexcept { return x > 0.0 ? float_at_least(x) : x < 0.0 ? float_at_most(x) : 0.0f; }

// A double sum or product of a few terms, rounded up to a float with room for the double
// roundings (each at most 2^-53 relative).
float up(double x) noexcept { return float_at_least(x + std::abs(x) * 0x1p-50); }

// The fast path's per-frame data (see "Fast path" in the file comment). Plane k is scaled by
// 2^-e with e = ilogb(A) (A = a_x + a_y + a_z), so that its scaled bound sum is in [1, 2),
// unless that would take |d| 2^-e above 2^100 (then e is raised). In double, n^ 2^-e and
// d^ 2^-e are exact; the float normal is rounded away from zero, and its rounding error (only
// when subnormal) is added to the bound: a'_i >= a_i 2^-e + |n'_i - n^_i 2^-e| / u, so that
// |n'_i - n_i 2^-e| <= u a'_i still holds for the true plane's scaled normal.
void derive_fast(CertifiedFrustum::Data& c) {
  double a_max = 0.0, d_max = 0.0;
  bool subnormal_norm = false;
  for (int i = 0; i < c.active_count; ++i) {
    const int k = c.active[static_cast<std::size_t>(i)];
    const Plane& p = c.planes[k];
    const glm::vec4& a = c.bound[k];
    int e = std::ilogb(c.bound_sum[k]);
    if (a.w > 0.0f) e = std::max(e, std::ilogb(a.w) - 100);
    const double sc = std::ldexp(1.0, -e);
    CertifiedPlane q;
    float* out[3] = {&q.nx, &q.ny, &q.nz};
    double a_sum = 0.0;
    for (int j = 0; j < 3; ++j) {
      const double x = double(p.n[j]) * sc;
      *out[j] = away_from_zero(x);
      a_sum += double(up(double(a[j]) * sc + std::abs(double(*out[j]) - x) * 0x1p24));
    }
    const double ad = double(a.w) * sc, dx = double(p.d) * sc;
    const double a_scaled = double(up(a_sum));
    a_max = std::max(a_max, a_scaled);
    CertifiedPlane& box = c.fast_box[static_cast<std::size_t>(i)];
    CertifiedPlane& sph = c.fast_sphere[static_cast<std::size_t>(i)];
    box = sph = q;
    const double delta_box = kNarrow * ad + double(kTiny), delta_sphere = kWide * ad + double(kTiny);
    box.d_out = up(dx + delta_box);
    box.d_in = -up(-(dx - delta_box));
    sph.d_out = up(dx + delta_sphere);
    sph.d_in = -up(-(dx - delta_sphere));
    sph.norm = box.norm = float(std::sqrt(double(q.nx) * q.nx + double(q.ny) * q.ny + double(q.nz) * q.nz));
    subnormal_norm = subnormal_norm || sph.norm < std::numeric_limits<float>::min();
    d_max = std::max({d_max, std::abs(double(sph.d_out)), std::abs(double(sph.d_in))});
  }
  c.t_box = float_at_least(kNarrow * a_max);
  c.t_sphere = float_at_least(kWide * a_max + (subnormal_norm ? 0x1p-149 : 0.0));
  // No overflow on the fast path: every partial sum is at most (1 + u)^5 (A' M + |d|) <= 2^121.
  const double room = 0x1p120 - d_max;
  const float m_fast = a_max > 0.0 ? float_at_most(room / a_max) : std::numeric_limits<float>::max();
  c.m_safe = room > 0.0 ? std::min(c.m_safe, m_fast) : 0.0f;
}

// Per-frame derivation of the margins (see the header): alpha = 2^-21 A and 2^-20 A rounded up
// to a float (exact power-of-two scalings of A' unless subnormal; rounded up, never to zero,
// since alpha multiplies M, which can be 2^127); beta = 2^-21 a_d + kTiny.
// Computing t = alpha M + beta rounds twice, a factor (1 - u)^2 the margins above allow for.
// m_safe: with M <= m_safe, A M + a_d <= 2^120 for every plane, so no product, partial sum or
// margin can overflow (every partial sum is at most (1 + u)^4 times the sum of the magnitudes).
void derive(CertifiedFrustum::Data& c) {
  double a_max = 0.0, d_max = 0.0;
  c.active_count = 0;
  c.empty = false;
  for (int k = 0; k < 6; ++k) {
    c.bound_sum[k] = float_at_least(double(c.bound[k].x) + double(c.bound[k].y) + double(c.bound[k].z));
    c.alpha_narrow[k] = float_at_least(kNarrow * double(c.bound_sum[k]));
    c.beta_narrow[k] = float_at_least(kNarrow * double(c.bound[k].w) + double(kTiny));
    c.alpha_wide[k] = float_at_least(kWide * double(c.bound_sum[k]));
    c.beta_wide[k] = float_at_least(kWide * double(c.bound[k].w) + double(kTiny));
    const Plane& p = c.planes[k];
    c.norm[k] = std::sqrt(double(p.n.x) * p.n.x + double(p.n.y) * p.n.y + double(p.n.z) * p.n.z);
    if (p.is_degenerate()) {
      // n^ == 0 exactly iff n == 0, and sign(d^) == sign(d): decided exactly.
      if (p.d < 0.0f) c.empty = true;
      continue;
    }
    c.active[static_cast<std::size_t>(c.active_count++)] = k;
    a_max = std::max(a_max, double(c.bound_sum[k]));
    d_max = std::max(d_max, double(c.bound[k].w));
  }
  const double room = 0x1p120 - d_max;
  c.m_safe = a_max > 0.0 ? float_at_most(room / a_max) : std::numeric_limits<float>::max();
  if (!(room > 0.0)) c.m_safe = 0.0f;
  derive_fast(c);
}

// Guarded decision for one plane: -1 certainly outside, +1 certainly inside, 0 undecided.
int decide_guarded(float lo, float hi, float t) noexcept {
  if (!std::isfinite(t) || !std::isfinite(lo) || !std::isfinite(hi)) return 0;
  if (hi < -t) return -1;
  if (lo >= t) return 1;
  return 0;
}

// The per-plane loop shared by every test. `range(k, t_out)` returns {lo, hi} of the plane's
// computed value over the volume and the margin for it.
template <class Range>
Visibility certified_loop(const CertifiedFrustum::Data& f, bool guarded, Range&& range) {
  if (f.empty) return Visibility::outside;
  bool inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const int k = f.active[static_cast<std::size_t>(i)];
    float t;
    const auto [lo, hi] = range(k, t);
    if (guarded) {
      const int r = decide_guarded(lo, hi, t);
      if (r < 0) return Visibility::outside;
      inside = inside && r > 0;
    } else {
      if (hi < -t) return Visibility::outside;
      inside = inside && lo >= t;
    }
  }
  return inside ? Visibility::inside : Visibility::intersecting;
}

// |v| componentwise with std::fabs (a sign-bit mask). glm::abs is `x >= 0 ? x : -x`, which GCC
// compiled into branches on the sign here (seen in the object code).
inline glm::vec3 fabs3(const glm::vec3& v) noexcept { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }

// certified_pn_vertex's fast path (M <= m_safe, not empty): Assarsson & Möller's fig. 4 loop
// with one uniform margin; the p-vertex decides "outside" first, the n-vertex verdict is folded
// in without a branch ("inside still possible" is data-dependent, a branch on it mispredicts).
// The vertices are chosen by the sign of the scaled normal, which is the sign of n^ (rounded
// away from zero), hence of the true n. With all six planes active the loop unrolls.
template <bool kAllSix>
Visibility pn_vertex_fast(const CertifiedFrustum::Data& f, const Aabb& b, float m) noexcept {
  const float t = f.t_box * m;
  const float neg_t = -t;
  bool inside = true;
  const int count = kAllSix ? 6 : f.active_count;
#pragma GCC unroll 6
  for (int i = 0; i < count; ++i) {
    const CertifiedPlane& p = f.fast_box[static_cast<std::size_t>(i)];
    const float px = p.nx >= 0.0f ? b.max.x : b.min.x, qx = p.nx >= 0.0f ? b.min.x : b.max.x;
    const float py = p.ny >= 0.0f ? b.max.y : b.min.y, qy = p.ny >= 0.0f ? b.min.y : b.max.y;
    const float pz = p.nz >= 0.0f ? b.max.z : b.min.z, qz = p.nz >= 0.0f ? b.min.z : b.max.z;
    if (((p.nx * px + p.ny * py) + p.nz * pz) + p.d_out < neg_t) return Visibility::outside;
    inside &= ((p.nx * qx + p.ny * qy) + p.nz * qz) + p.d_in >= t;
  }
  return inside ? Visibility::inside : Visibility::intersecting;
}

// certified_sphere's fast path (M + r <= m_safe, not empty).
template <bool kAllSix>
Visibility sphere_fast(const CertifiedFrustum::Data& f, const Sphere& sp, float m) noexcept {
  const float t = f.t_sphere * m;
  const float neg_t = -t;
  const glm::vec3& c = sp.center;
  bool inside = true;
  const int count = kAllSix ? 6 : f.active_count;
#pragma GCC unroll 6
  for (int i = 0; i < count; ++i) {
    const CertifiedPlane& p = f.fast_sphere[static_cast<std::size_t>(i)];
    const float s = (p.nx * c.x + p.ny * c.y) + p.nz * c.z;
    const float rho = sp.radius * p.norm;
    if ((s + p.d_out) + rho < neg_t) return Visibility::outside;
    inside &= (s + p.d_in) - rho >= t;
  }
  return inside ? Visibility::inside : Visibility::intersecting;
}

// M of a box: max over axes of max(|min_j|, |max_j|), computed as max(max_j, -min_j), which is
// the same for min_j <= max_j (a valid box) and has no sign test (the SIMD batch does the same).
inline float box_magnitude(const Aabb& b) noexcept {
  return std::max(std::max(std::max(b.max.x, b.max.y), b.max.z), -std::min(std::min(b.min.x, b.min.y), b.min.z));
}

}  // namespace

CertifiedFrustum certify_planes(const Frustum& f) {
  CertifiedFrustum::Data c;
  c.planes = f;
  for (int k = 0; k < 6; ++k) c.bound[k] = glm::vec4(glm::abs(f[k].n), std::abs(f[k].d));
  derive(c);
  return CertifiedFrustum(std::move(c));
}

CertifiedFrustum certify_matrix(const glm::mat4& m, DepthConvention depth) {
  CertifiedFrustum::Data c;
  c.planes = frustum_from_matrix(m, depth);
  const glm::vec4 r[4] = {glm::abs(matrix_row(m, 0)), glm::abs(matrix_row(m, 1)), glm::abs(matrix_row(m, 2)),
                          glm::abs(matrix_row(m, 3))};
  // The bound of fl(r4 +- rk), or of fl(fl(r4/2) +- fl(rk/2)) where frustum_from_matrix halves
  // the rows (they reach past FLT_MAX): half the plane, with 2^-124 added to a coefficient whose
  // entries may be subnormal (halving one rounds by up to 2^-150; see "End to end" above).
  auto sum = [](const glm::vec4& a, const glm::vec4& b) {
    const bool halved = gribb_hartmann_halves(a, b);
    glm::vec4 out;
    for (int i = 0; i < 4; ++i) {
      double s = double(a[i]) + double(b[i]);
      if (halved) {
        s *= 0.5;
        if ((a[i] != 0.0f && a[i] < 0x1p-126f) || (b[i] != 0.0f && b[i] < 0x1p-126f)) s += 0x1p-124;
      }
      out[i] = float_at_least(s);
    }
    return out;
  };
  c.bound[kLeft] = c.bound[kRight] = sum(r[3], r[0]);
  c.bound[kBottom] = c.bound[kTop] = sum(r[3], r[1]);
  const glm::vec4 lower = depth.range == DepthRange::negative_one_to_one ? sum(r[3], r[2]) : r[2];
  const glm::vec4 upper = sum(r[3], r[2]);
  c.bound[kNear] = depth.reversed_z ? upper : lower;
  c.bound[kFar] = depth.reversed_z ? lower : upper;
  derive(c);
  return CertifiedFrustum(std::move(c));
}

CertifiedFrustum certify(const CaseFrustum& f) {
  return f.matrix ? certify_matrix(*f.matrix, f.depth) : certify_planes(f.planes);
}

Visibility certified_point(const CertifiedFrustum& frustum, const Point& p) noexcept {
  const CertifiedFrustum::Data& f = frustum.data();
  const float m = std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z)));
  return certified_loop(f, !(m <= f.m_safe), [&](int k, float& t) {
    t = f.alpha_narrow[k] * m + f.beta_narrow[k];
    const float s = f.planes[k].eval(p);
    return std::pair<float, float>(s, s);
  });
}

Visibility certified_sphere(const CertifiedFrustum& frustum, const Sphere& sp) noexcept {
  const CertifiedFrustum::Data& f = frustum.data();
  const glm::vec3& c = sp.center;
  const float m = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z))) + sp.radius;
  if (!(m <= f.m_safe) || f.empty) {
    return certified_loop(f, true, [&](int k, float& t) {
      const Plane& p = f.planes[k];
      t = f.alpha_wide[k] * m + f.beta_wide[k];
      const float s = p.eval(c);
      const float rho = float(double(sp.radius) * f.norm[k]);
      return std::pair<float, float>(s - rho, s + rho);
    });
  }
  return f.active_count == 6 ? sphere_fast<true>(f, sp, m) : sphere_fast<false>(f, sp, m);
}

Visibility certified_pn_vertex(const CertifiedFrustum& frustum, const Aabb& b) noexcept {
  const CertifiedFrustum::Data& f = frustum.data();
  const float m = box_magnitude(b);
  if (!(m <= f.m_safe) || f.empty) {
    return certified_loop(f, true, [&](int k, float& t) {
      const Plane& p = f.planes[k];
      t = f.alpha_narrow[k] * m + f.beta_narrow[k];
      const glm::vec3 pv(p.n.x >= 0.0f ? b.max.x : b.min.x, p.n.y >= 0.0f ? b.max.y : b.min.y,
                         p.n.z >= 0.0f ? b.max.z : b.min.z);
      const glm::vec3 nv(p.n.x >= 0.0f ? b.min.x : b.max.x, p.n.y >= 0.0f ? b.min.y : b.max.y,
                         p.n.z >= 0.0f ? b.min.z : b.max.z);
      return std::pair<float, float>(p.eval(nv), p.eval(pv));
    });
  }
  return f.active_count == 6 ? pn_vertex_fast<true>(f, b, m) : pn_vertex_fast<false>(f, b, m);
}

Visibility certified_obb_pn_vertex(const CertifiedFrustum& frustum, const Obb& b) noexcept {
  const CertifiedFrustum::Data& f = frustum.data();
  const glm::vec3& c = b.center;
  float h = 0.0f;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 u = fabs3(b.axes[i]);
    h += b.half[i] * std::max(u.x, std::max(u.y, u.z));
  }
  const float m = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z))) + h;
  return certified_loop(f, !(m <= f.m_safe), [&](int k, float& t) {
    const Plane& p = f.planes[k];
    t = f.alpha_wide[k] * m + f.beta_wide[k];
    const float s = p.eval(c);
    const float r = b.half.x * std::abs(glm::dot(p.n, b.axes[0])) + b.half.y * std::abs(glm::dot(p.n, b.axes[1])) +
                    b.half.z * std::abs(glm::dot(p.n, b.axes[2]));
    return std::pair<float, float>(s - r, s + r);
  });
}

}  // namespace cullproof

// Certified conservative plane tests: point, sphere, AABB (n/p-vertex), OBB (n/p-vertex).
//
// Sources: the tests are Assarsson & Möller 2000 §3.1 (n/p vertex, normal projected on the box
// axes for OBBs) and Lighthouse3D's sphere test; the error analysis is the standard model of
// floating-point arithmetic (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
// §2.2 and §3.1): fl(x op y) = (x op y)(1 + e), |e| <= u = 2^-24 for binary32, plus an absolute
// error of at most 2^-150 for a product that underflows (sums of floats that underflow are exact).
// Claim: certified-conservative.
//
// Derivation (the notation of cullproof/certified.hpp: float plane (n^, d^), true plane (n, d),
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
//  Sphere: outside iff n.c + d + r |n| < 0. nu^ = fl(sqrt(fl(n^.n^))) has
//  |nu^ - |n^|| <= 2.6 u |n^| and ||n^| - |n|| <= |n^ - n| <= u A, so |nu^ - |n|| <= 3.7 u A;
//  rho^ = fl(r nu^) is within 4.8 u r A of r |n|; the final sum rounds once more. In all
//  |fl(s^ +- rho^) - (S +- r|n|)| <= 11 u (A (M + r) + a_d), covered by
//      t = 2^-20 fl(fl(A' fl(M + r)) + a_d) + 2^-126   (16 u).
//
//  OBB: S_max/min = n.c + d +- sum_i h_i |n.u_i|. q^_i = fl(n^.u_i) is within
//  (g3 (1 + u) + u) A U_i <= 4.0001 u A U_i of n.u_i (U_i = max_j |u_ij|); r^ = fl(sum h_i |q^_i|)
//  is within 7.01 u A H of sum h_i |n.u_i| (H = sum h_i U_i); with s^ at c and the final sum:
//  |error| <= 13.1 u (A (M_c + H) + a_d), covered by t = 2^-20 fl(fl(A' fl(M_c + H)) + a_d) + 2^-126
//  (16 u (1 - u)^4 > 13.1 u).
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
#include "cullproof/certified.hpp"

#include <cmath>
#include <limits>

namespace cullproof {

namespace {

constexpr float kTiny = 0x1p-126f;  // covers absolute underflow errors

// Per-frame derivation of the margins (see the header): alpha = 2^-21 A and 2^-20 A are exact
// power-of-two scalings of A' (unless subnormal, covered by kTiny); beta = 2^-21 a_d + kTiny.
// Computing t = alpha M + beta rounds twice, a factor (1 - u)^2 the margins above allow for.
// m_safe: with M <= m_safe, A M + a_d <= 2^120 for every plane, so no product, partial sum or
// margin can overflow (every partial sum is at most (1 + u)^4 times the sum of the magnitudes).
void derive(CertifiedFrustum& c) {
  double a_max = 0.0, d_max = 0.0;
  c.active_count = 0;
  c.empty = false;
  for (int k = 0; k < 6; ++k) {
    c.bound_sum[k] = float_at_least(double(c.bound[k].x) + double(c.bound[k].y) + double(c.bound[k].z));
    c.alpha_narrow[k] = 0x1p-21f * c.bound_sum[k];
    c.beta_narrow[k] = float_at_least(0x1p-21 * double(c.bound[k].w) + double(kTiny));
    c.alpha_wide[k] = 0x1p-20f * c.bound_sum[k];
    c.beta_wide[k] = float_at_least(0x1p-20 * double(c.bound[k].w) + double(kTiny));
    const Plane& p = c.planes[k];
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
Visibility certified_loop(const CertifiedFrustum& f, bool guarded, Range&& range) {
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

}  // namespace

CertifiedFrustum certify_planes(const Frustum& f) {
  CertifiedFrustum c;
  c.planes = f;
  for (int k = 0; k < 6; ++k) c.bound[k] = glm::vec4(glm::abs(f[k].n), std::abs(f[k].d));
  derive(c);
  return c;
}

CertifiedFrustum certify_matrix(const glm::mat4& m, DepthConvention depth) {
  CertifiedFrustum c;
  c.planes = frustum_from_matrix(m, depth);
  const glm::vec4 r[4] = {glm::abs(matrix_row(m, 0)), glm::abs(matrix_row(m, 1)), glm::abs(matrix_row(m, 2)),
                          glm::abs(matrix_row(m, 3))};
  auto sum = [](const glm::vec4& a, const glm::vec4& b) {
    glm::vec4 out;
    for (int i = 0; i < 4; ++i) out[i] = float_at_least(double(a[i]) + double(b[i]));
    return out;
  };
  c.bound[kLeft] = c.bound[kRight] = sum(r[3], r[0]);
  c.bound[kBottom] = c.bound[kTop] = sum(r[3], r[1]);
  const glm::vec4 lower = depth.range == DepthRange::negative_one_to_one ? sum(r[3], r[2]) : r[2];
  const glm::vec4 upper = sum(r[3], r[2]);
  c.bound[kNear] = depth.reversed_z ? upper : lower;
  c.bound[kFar] = depth.reversed_z ? lower : upper;
  derive(c);
  return c;
}

CertifiedFrustum certify(const CaseFrustum& f) {
  return f.matrix ? certify_matrix(*f.matrix, f.depth) : certify_planes(f.planes);
}

Visibility certified_point(const CertifiedFrustum& f, const Point& p) noexcept {
  const float m = std::max(std::abs(p.x), std::max(std::abs(p.y), std::abs(p.z)));
  return certified_loop(f, !(m <= f.m_safe), [&](int k, float& t) {
    t = f.alpha_narrow[k] * m + f.beta_narrow[k];
    const float s = f.planes[k].eval(p);
    return std::pair<float, float>(s, s);
  });
}

Visibility certified_sphere(const CertifiedFrustum& f, const Sphere& sp) noexcept {
  const glm::vec3& c = sp.center;
  const float m = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z))) + sp.radius;
  return certified_loop(f, !(m <= f.m_safe), [&](int k, float& t) {
    const Plane& p = f.planes[k];
    t = f.alpha_wide[k] * m + f.beta_wide[k];
    const float s = p.eval(c);
    const float rho = sp.radius * std::sqrt(glm::dot(p.n, p.n));
    return std::pair<float, float>(s - rho, s + rho);
  });
}

Visibility certified_pn_vertex(const CertifiedFrustum& f, const Aabb& b) noexcept {
  const glm::vec3 mags = glm::max(glm::abs(b.min), glm::abs(b.max));
  const float m = std::max(mags.x, std::max(mags.y, mags.z));
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
  // Hot path (no overflow possible): the p-vertex decides "outside" first, as in Assarsson &
  // Möller's fig. 4; the n-vertex is evaluated only while "inside" is still possible.
  bool inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const int k = f.active[static_cast<std::size_t>(i)];
    const Plane& p = f.planes[k];
    const float t = f.alpha_narrow[k] * m + f.beta_narrow[k];
    const glm::vec3 pv(p.n.x >= 0.0f ? b.max.x : b.min.x, p.n.y >= 0.0f ? b.max.y : b.min.y,
                       p.n.z >= 0.0f ? b.max.z : b.min.z);
    if (p.eval(pv) < -t) return Visibility::outside;
    if (inside) {
      const glm::vec3 nv(p.n.x >= 0.0f ? b.min.x : b.max.x, p.n.y >= 0.0f ? b.min.y : b.max.y,
                         p.n.z >= 0.0f ? b.min.z : b.max.z);
      inside = p.eval(nv) >= t;
    }
  }
  return inside ? Visibility::inside : Visibility::intersecting;
}

Visibility certified_obb_pn_vertex(const CertifiedFrustum& f, const Obb& b) noexcept {
  const glm::vec3& c = b.center;
  float h = 0.0f;
  for (int i = 0; i < 3; ++i) {
    const glm::vec3 u = glm::abs(b.axes[i]);
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

// Vector lanes for the exact-certified cascade (exact_lanes.hpp; Highway runtime dispatch): the
// plane stages of OBBs and spheres, the anchors, the small programme's pivots. A lane per plane,
// per anchor or per column of a tableau; every value is computed as the scalar derivation of
// exact_certified.cpp has it, by separate multiplies and adds in the same order (no fused
// multiply-add), so that each target gives the same values, stages and verdicts.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "exact_lanes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "exact_lanes.hpp"

#include <algorithm>
#include <cmath>

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using F = ExactCertifiedFrustum;

// Lanes k.. of row `row` of f.lanes (one plane per lane).
template <class D>
HWY_INLINE hn::Vec<D> plane_lanes(D d, const F& f, F::Lane row, int k) {
  return hn::LoadU(d, f.lanes[std::size_t(row)].data() + k);
}

// Stage 1 of an OBB (exact_certified.cpp, "Stage 1: planes" and "Spheres and OBBs"): per plane
// s = (n'_x c_x + n'_y c_y) + n'_z c_z, the rows n'.e_i, rad = (|a_1| + |a_2|) + |a_3|, and the
// comparisons of s + d_out +- rad and s + d_in +- rad with -T and T.
void ObbPlaneKernel(const F& f, const double* c, const double (*e)[3], double T,
                    exact_lanes::ObbPlaneStage& q) {
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
  const auto t = hn::Set(d, T), neg_t = hn::Set(d, -T);
  unsigned outside = 0, held = 0, crossing = 0, p_in = 0;
  // All eight lanes of f.lanes, a fixed number of whole vectors (the compiler unrolls them and
  // their chains of dependent operations overlap); the lanes past count are masked off once, in
  // the bits, at the end.
#pragma GCC unroll 8
  for (int k = 0; k < 8; k += n) {
    const auto nx = plane_lanes(d, f, F::kLaneNx, k), ny = plane_lanes(d, f, F::kLaneNy, k),
               nz = plane_lanes(d, f, F::kLaneNz, k);
    const auto s = hn::Add(hn::Add(hn::Mul(nx, hn::Set(d, c[0])), hn::Mul(ny, hn::Set(d, c[1]))),
                           hn::Mul(nz, hn::Set(d, c[2])));
    hn::Vec<decltype(d)> a[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = hn::Add(hn::Add(hn::Mul(nx, hn::Set(d, e[i][0])), hn::Mul(ny, hn::Set(d, e[i][1]))),
                     hn::Mul(nz, hn::Set(d, e[i][2])));
      hn::StoreU(a[i], d, q.a[i + 1] + k);
    }
    hn::StoreU(hn::Add(s, plane_lanes(d, f, F::kLaneD, k)), d, q.a[0] + k);
    const auto rad = hn::Add(hn::Add(hn::Abs(a[0]), hn::Abs(a[1])), hn::Abs(a[2]));
    const auto so = hn::Add(s, plane_lanes(d, f, F::kLaneDOutBox, k)), si = hn::Add(s, plane_lanes(d, f, F::kLaneDInBox, k));
    outside |= unsigned(mask_bits(d, hn::Lt(hn::Add(so, rad), neg_t))) << k;
    held |= unsigned(mask_bits(d, hn::Ge(hn::Sub(si, rad), t))) << k;  // not for a NaN, as in the scalar test
    crossing |= unsigned(mask_bits(d, hn::Lt(hn::Sub(so, rad), neg_t))) << k;
    p_in |= unsigned(mask_bits(d, hn::Ge(hn::Add(si, rad), t))) << k;
  }
  const unsigned valid = (1u << f.count) - 1u;  // count <= 8
  q.outside = (outside & valid) != 0;
  if (q.outside) return;
  q.J = valid & ~held;
  q.crossing = crossing & valid;
  q.p_in = p_in & q.J;
  q.shared = false;
  if (q.crossing == 0 || q.p_in != q.J) return;
  // The signs of the rows of J, read back from q.a (only the boxes this can decide pay for it).
  unsigned pos[3] = {0, 0, 0}, neg[3] = {0, 0, 0};
  const auto zero = hn::Zero(d);
  for (int k = 0; k < 8; k += n)
    for (int i = 0; i < 3; ++i) {
      const auto a = hn::LoadU(d, q.a[i + 1] + k);
      pos[i] |= unsigned(mask_bits(d, hn::Gt(a, zero))) << k;
      neg[i] |= unsigned(mask_bits(d, hn::Lt(a, zero))) << k;
    }
  const unsigned J = q.J;
  q.shared = ((pos[0] & J) == 0 || (neg[0] & J) == 0) && ((pos[1] & J) == 0 || (neg[1] & J) == 0) &&
             ((pos[2] & J) == 0 || (neg[2] & J) == 0);
}

// The witness test on q's rows, one per lane, as row_at and row_bounds compute them.
unsigned ObbRowsShortKernel(const F& f, const exact_lanes::ObbPlaneStage& q, const double* t, double X, double eps_row) {
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
  const auto t0 = hn::Set(d, t[0]), t1 = hn::Set(d, t[1]), t2 = hn::Set(d, t[2]), x = hn::Set(d, X), k = hn::Set(d, eps_row);
  unsigned bits = 0;
  for (int j = 0; j < 8; j += n) {
    const auto v = hn::Add(hn::Add(hn::Add(hn::LoadU(d, q.a[0] + j), hn::Mul(hn::LoadU(d, q.a[1] + j), t0)),
                                   hn::Mul(hn::LoadU(d, q.a[2] + j), t1)),
                           hn::Mul(hn::LoadU(d, q.a[3] + j), t2));
    const auto eps = hn::Mul(hn::Add(hn::Mul(plane_lanes(d, f, F::kLaneA, j), x), plane_lanes(d, f, F::kLaneAd, j)), k);
    bits |= unsigned(mask_bits(d, hn::Not(hn::Ge(v, eps)))) << j;
  }
  return bits;
}

// Stage 1 of a sphere (exact_certified.cpp, "Spheres"), the scalar loop's operations per lane:
// v = (n'_x c_x + n'_y c_y) + n'_z c_z, rho = r norm', (v + d_out) + rho against -T and so on;
// the bound wc = up(A' mc + |d'|) with up(x) = x (1 + kSlack).
void SpherePlaneKernel(const F& f, const double* c, double r, double mc, double T,
                       exact_lanes::SpherePlaneStage& q) {
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
  const auto t = hn::Set(d, T), neg_t = hn::Set(d, -T), radius = hn::Set(d, r), m = hn::Set(d, mc);
  const auto slack = hn::Set(d, 1.0 + ExactMargins::kSlack);
  unsigned J = 0, crossing = 0, reach = 0, centre_in = 0;
  for (int k = 0; k < f.count; k += n) {
    const auto load = [&](F::Lane row) { return plane_lanes(d, f, row, k); };
    const auto v = hn::Add(hn::Add(hn::Mul(load(F::kLaneNx), hn::Set(d, c[0])), hn::Mul(load(F::kLaneNy), hn::Set(d, c[1]))),
                           hn::Mul(load(F::kLaneNz), hn::Set(d, c[2])));
    const auto rho = hn::Mul(radius, load(F::kLaneNorm));
    const auto w_out = hn::Add(v, load(F::kLaneDOutSphere)), w_in = hn::Add(v, load(F::kLaneDInSphere));
    const auto valid = hn::FirstN(d, std::size_t(f.count - k));
    if (!hn::AllFalse(d, hn::And(valid, hn::Lt(hn::Add(w_out, rho), neg_t)))) {
      q.outside = true;
      return;
    }
    const auto in_j = hn::AndNot(hn::Ge(hn::Sub(w_in, rho), t), valid);  // NaN: in J, as the loop
    J |= unsigned(mask_bits(d, in_j)) << k;
    crossing |= unsigned(mask_bits(d, hn::And(in_j, hn::Lt(hn::Sub(w_out, rho), neg_t)))) << k;
    reach |= unsigned(mask_bits(d, hn::And(in_j, hn::Ge(hn::Add(w_in, rho), t)))) << k;
    centre_in |= unsigned(mask_bits(d, hn::And(in_j, hn::Ge(w_in, t)))) << k;
    hn::StoreU(hn::Add(v, load(F::kLaneD)), d, q.sc + k);
    hn::StoreU(hn::Mul(hn::Add(hn::Mul(load(F::kLaneA), m), load(F::kLaneAd)), slack), d, q.wc + k);
  }
  q.outside = false;
  q.J = J;
  q.crossing = crossing;
  q.reach = reach;
  q.centre_in = centre_in;
}

// The anchors against a ball (exact_certified.cpp, sphere stage 2), the scalar test per lane.
bool AnchorInBallKernel(const ExactCertifiedFrustum& f, const double* c, double r2) {
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
  const auto scale = hn::Set(d, 1.0 + ExactMargins::kDistance * ExactMargins::u), limit = hn::Set(d, r2);
  for (int k = 0; k < f.anchor_count; k += n) {
    const auto dx = hn::Sub(hn::LoadU(d, f.anchor_x.data() + k), hn::Set(d, c[0]));
    const auto dy = hn::Sub(hn::LoadU(d, f.anchor_y.data() + k), hn::Set(d, c[1]));
    const auto dz = hn::Sub(hn::LoadU(d, f.anchor_z.data() + k), hn::Set(d, c[2]));
    const auto s = hn::Mul(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)), scale);
    if (!hn::AllFalse(d, hn::And(hn::FirstN(d, std::size_t(f.anchor_count - k)), hn::Le(s, limit)))) return true;
  }
  return false;
}

// The anchors in the OBB's coordinates: t_i = (x - c).u_i / (h_i |u_i|^2), a NaN taken as 0, then
// clamped to [-1, 1]. Any t of the cube is a point of the box, so t need not be exact; the rows
// a_j0 + a_j1 t_1 + a_j2 t_2 + a_j3 t_3 (that order) are compared with eps_j, whose bound holds on
// the whole cube.
bool ObbAnchorKernel(const ExactCertifiedFrustum& f, const Obb& b, int m, const double (*a)[4], const double* eps) {
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
  double axis[3][3];  // u_i / (h_i |u_i|^2)
  for (int i = 0; i < 3; ++i) {
    const glm::vec3& u = b.axes[i];
    const double h = b.half[i], uu = double(u.x) * u.x + double(u.y) * u.y + double(u.z) * u.z;
    const double inv = h > 0.0 && uu > 0.0 ? 1.0 / (h * uu) : 0.0;
    axis[i][0] = u.x * inv, axis[i][1] = u.y * inv, axis[i][2] = u.z * inv;
  }
  const auto one = hn::Set(d, 1.0), minus_one = hn::Set(d, -1.0), zero = hn::Zero(d);
  for (int k = 0; k < f.anchor_count; k += n) {
    const auto x = hn::Sub(hn::LoadU(d, f.anchor_x.data() + k), hn::Set(d, double(b.center.x)));
    const auto y = hn::Sub(hn::LoadU(d, f.anchor_y.data() + k), hn::Set(d, double(b.center.y)));
    const auto z = hn::Sub(hn::LoadU(d, f.anchor_z.data() + k), hn::Set(d, double(b.center.z)));
    hn::Vec<decltype(d)> t[3];
    for (int i = 0; i < 3; ++i) {
      const auto ti = hn::Add(hn::Add(hn::Mul(x, hn::Set(d, axis[i][0])), hn::Mul(y, hn::Set(d, axis[i][1]))),
                              hn::Mul(z, hn::Set(d, axis[i][2])));
      t[i] = hn::Min(hn::Max(hn::IfThenElse(hn::Eq(ti, ti), ti, zero), minus_one), one);
    }
    auto ok = hn::FirstN(d, std::size_t(f.anchor_count - k));
    for (int j = 0; j < m && !hn::AllFalse(d, ok); ++j) {
      const auto v = hn::Add(hn::Add(hn::Add(hn::Set(d, a[j][0]), hn::Mul(hn::Set(d, a[j][1]), t[0])),
                                     hn::Mul(hn::Set(d, a[j][2]), t[1])),
                             hn::Mul(hn::Set(d, a[j][3]), t[2]));
      ok = hn::And(ok, hn::Ge(v, hn::Set(d, eps[j])));
    }
    if (!hn::AllFalse(d, ok)) return true;
  }
  return false;
}

// The programme of exact_lanes.hpp (max_min_lp), the pivots on whole rows of the tableau.
void MaxMinLpKernel(int m, const double (*a_in)[4], const double* w_in, exact_lanes::LpAnswer& out) {
  constexpr int kMaxRows = 9, kCols = 16;  // 4 + kMaxRows + 1 columns, padded to a multiple of 8
  const int rows = m + 3, rhs = 4 + rows;
  alignas(64) double T[kMaxRows][kCols] = {};
  alignas(64) double obj[kCols] = {};
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
  const hn::CappedTag<double, 8> d;
  const int n = int(hn::Lanes(d));
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
    if (leave < 0) return;  // unbounded: cannot happen with w > 0; give up
    // The pivot on whole rows (the columns past rhs are zero and stay zero).
    const auto p = hn::Set(d, T[leave][enter]);
    for (int c = 0; c < kCols; c += n) hn::Store(hn::Div(hn::Load(d, T[leave] + c), p), d, T[leave] + c);
    auto eliminate = [&](double* row) {
      const auto f = hn::Set(d, row[enter]);
      for (int c = 0; c < kCols; c += n)
        hn::Store(hn::Sub(hn::Load(d, row + c), hn::Mul(f, hn::Load(d, T[leave] + c))), d, row + c);
    };
    for (int r = 0; r < rows; ++r)
      if (r != leave && T[r][enter] != 0.0) eliminate(T[r]);
    eliminate(obj);
    basis[leave] = enter;
  }
  if (!out.ok) return;
  double y[4] = {0, 0, 0, 0};
  for (int r = 0; r < rows; ++r)
    if (basis[r] < 4) y[basis[r]] = T[r][rhs];
  for (int i = 0; i < 3; ++i) out.t[i] = std::min(1.0, std::max(-1.0, y[i] - 1.0));
  out.s = y[3] - z0;
  for (int j = 0; j < m; ++j) out.lambda[j] = std::max(0.0, obj[4 + j]) * sigma[j];
}

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof::exact_lanes {

HWY_EXPORT(ObbPlaneKernel);
HWY_EXPORT(ObbAnchorKernel);
HWY_EXPORT(ObbRowsShortKernel);
HWY_EXPORT(SpherePlaneKernel);
HWY_EXPORT(AnchorInBallKernel);
HWY_EXPORT(MaxMinLpKernel);

void obb_plane_stage(const ExactCertifiedFrustum& f, const double* c, const double (*e)[3], double T,
                     ObbPlaneStage& out) {
  HWY_DYNAMIC_DISPATCH(ObbPlaneKernel)(f, c, e, T, out);
}

unsigned obb_rows_short(const ExactCertifiedFrustum& f, const ObbPlaneStage& q, const double* t, double X, double eps_row) {
  return HWY_DYNAMIC_DISPATCH(ObbRowsShortKernel)(f, q, t, X, eps_row);
}

void sphere_plane_stage(const ExactCertifiedFrustum& f, const double* c, double r, double mc, double T,
                        SpherePlaneStage& out) {
  HWY_DYNAMIC_DISPATCH(SpherePlaneKernel)(f, c, r, mc, T, out);
}

bool anchor_in_ball(const ExactCertifiedFrustum& f, const double* c, double r2) {
  return HWY_DYNAMIC_DISPATCH(AnchorInBallKernel)(f, c, r2);
}

bool obb_anchor_witness(const ExactCertifiedFrustum& f, const Obb& b, int m, const double (*a)[4], const double* eps) {
  return HWY_DYNAMIC_DISPATCH(ObbAnchorKernel)(f, b, m, a, eps);
}

LpAnswer max_min_lp(int m, const double (*a)[4], const double* w) {
  LpAnswer out;
  HWY_DYNAMIC_DISPATCH(MaxMinLpKernel)(m, a, w, out);
  return out;
}

}  // namespace cullproof::exact_lanes
#endif  // HWY_ONCE

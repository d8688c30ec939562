// The sphere array form's double pass (batch_spheres.hpp; Highway runtime dispatch): what the
// certified batch and its witness pass leave, tested again with the scalar cascade's own proofs
// (exact_certified.cpp, "Spheres"), a ball per lane. Every proof is computed as the scalar
// derivation has it, by separate multiplies and adds in the same order (no fused multiply-add),
// so its bound holds as derived there:
//  - stage 1: per plane v = (n'_x c_x + n'_y c_y) + n'_z c_z, rho = r norm', the comparisons of
//    v + d_out +- rho and v + d_in +- rho with -T and T (outside, J, crossing, reach, centre in),
//    and what they decide alone (J empty: inside; one plane reached, or the centre in every plane
//    of J, with a plane crossed: intersecting);
//  - witness points, for balls with a plane crossed (so not inside): the anchors within the ball,
//    the point of the segment from the centre to the interior point just past its entry into
//    P_J, and the projection of the centre onto the planes of each subset S of J (|S| <= 3)
//    pulled towards the interior point by half the room left in the ball; each proved inside
//    every plane of J (kPoint) and within the ball (kDistance);
//  - Farkas multipliers lambda = max(0, -mu) from each projection (mu = G_S^-1 s_S), times the
//    reciprocal of the largest (any finite lambda >= 0 is a certificate; the largest is then
//    about 1, as the derivation's scaling makes it), proving the ball outside the half-space
//    sum lambda_j (n'_j, d'_j).
// The scalar cascade proves the nearest feasible projection only; here every subset's projection
// is tried, which proves at least as much in lanes. The projections and multipliers only
// propose: a wrong one costs a proof, never a verdict. A ball left unproved goes to the cascade.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch_spheres.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/batch_spheres.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using F = ExactCertifiedFrustum;
using M = ExactMargins;

// A subset S of J and the matrix taking s_S (the centre's values on its planes) to the
// projection's mu = G_S^-1 s_S (rows past k zero).
struct Subset {
  int k = 0;
  int S[3] = {0, 0, 0};
  double m[3][3] = {};
};

// The subsets of the planes js[0..m) with at most three planes whose Gram matrix is well
// conditioned (the scalar search's tests): pairs first (the edges, which prove most balls near
// the frustum outside or meeting it), then single planes, then triples.
int subsets_of(const F& f, const int* js, int m, Subset* out) {
  const auto& G = f.gram;
  int n = 0;
  for (int qa = 0; qa < m; ++qa)
    for (int qb = qa + 1; qb < m; ++qb) {
      const int a = js[qa], b = js[qb];
      const double D = G[a][a] * G[b][b] - G[a][b] * G[a][b];
      if (!(D > 1e-12 * G[a][a] * G[b][b])) continue;
      const double inv = 1.0 / D;
      Subset& s = out[n++];
      s.k = 2, s.S[0] = a, s.S[1] = b;
      s.m[0][0] = G[b][b] * inv, s.m[0][1] = -G[a][b] * inv;
      s.m[1][0] = -G[a][b] * inv, s.m[1][1] = G[a][a] * inv;
    }
  for (int qa = 0; qa < m; ++qa) {
    const int a = js[qa];
    if (!(G[a][a] > 0.0)) continue;
    out[n].k = 1, out[n].S[0] = a, out[n].m[0][0] = 1.0 / G[a][a];
    ++n;
  }
  for (int qa = 0; qa < m; ++qa)
    for (int qb = qa + 1; qb < m; ++qb)
      for (int qc = qb + 1; qc < m; ++qc) {
        const int a = js[qa], b = js[qb], c = js[qc];
        const double e00 = G[a][a], e01 = G[a][b], e02 = G[a][c], e11 = G[b][b], e12 = G[b][c], e22 = G[c][c];
        const double c00 = e11 * e22 - e12 * e12, c01 = e02 * e12 - e01 * e22, c02 = e01 * e12 - e02 * e11;
        const double c11 = e00 * e22 - e02 * e02, c12 = e01 * e02 - e00 * e12, c22 = e00 * e11 - e01 * e01;
        const double D3 = e00 * c00 + e01 * c01 + e02 * c02;
        if (!(D3 > 1e-12 * e00 * e11 * e22)) continue;
        const double inv = 1.0 / D3;
        Subset& s = out[n++];
        s.k = 3, s.S[0] = a, s.S[1] = b, s.S[2] = c;
        const double cof[3][3] = {{c00, c01, c02}, {c01, c11, c12}, {c02, c12, c22}};
        for (int i = 0; i < 3; ++i)
          for (int t = 0; t < 3; ++t) s.m[i][t] = cof[i][t] * inv;
      }
  return n;
}

constexpr std::size_t kCap = detail::PassProofs::kCapacity;

void BallPassKernel(const F& f, const SphereSoa& balls, const std::uint64_t* todo, detail::PassProofs& res) {
  const hn::CappedTag<double, 8> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d), n = balls.count, words = bitset_words(n);
  for (std::size_t w = 0; w < kCap / 64; ++w) res.outside[w] = res.inside[w] = res.meets[w] = 0;
  if (f.empty || f.count == 0 || n == 0) return;
  const int count = f.count;
  const V slack = hn::Set(d, 1.0 + M::kSlack), zero = hn::Zero(d);

  // The balls of `todo`, side by side in double (ball t is ball idx[t] of the chunk).
  std::uint32_t idx[kCap];
  alignas(64) double bx[kCap + 8], by[kCap + 8], bz[kCap + 8], br[kCap + 8];
  std::size_t nt = 0;
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t b = todo[w] & detail::low_bits(n - w * 64); b != 0; b &= b - 1) {
      const std::size_t q = w * 64 + std::size_t(__builtin_ctzll(b));
      idx[nt] = std::uint32_t(q);
      bx[nt] = balls.x[q], by[nt] = balls.y[q], bz[nt] = balls.z[q], br[nt] = balls.radius[q];
      ++nt;
    }
  if (nt == 0) return;
  for (std::size_t t = nt; t < nt + N; ++t) bx[t] = by[t] = bz[t] = br[t] = 0.0;

  // Stage 1: J, crossing, reach and centre-in bits per ball, and outside.
  alignas(64) std::uint64_t Jb[kCap + 8], crossb[kCap + 8], reachb[kCap + 8], inb[kCap + 8];
  std::uint64_t out_bits[kCap / 64] = {};
  for (std::size_t i = 0; i < nt; i += N) {
    const V cx = hn::Load(d, bx + i), cy = hn::Load(d, by + i), cz = hn::Load(d, bz + i), r = hn::Load(d, br + i);
    const V mc = hn::Max(hn::Abs(cx), hn::Max(hn::Abs(cy), hn::Abs(cz)));
    const V t = hn::Mul(hn::Set(d, f.t_sphere), hn::Add(mc, r)), neg_t = hn::Neg(t);
    auto J = hn::Zero(du), crossing = hn::Zero(du), reach = hn::Zero(du), centre_in = hn::Zero(du);
    auto outside = hn::Lt(zero, zero);
    for (int j = 0; j < count; ++j) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
      const V v = hn::Add(hn::Add(hn::Mul(hn::Set(d, p.nx), cx), hn::Mul(hn::Set(d, p.ny), cy)), hn::Mul(hn::Set(d, p.nz), cz));
      const V rho = hn::Mul(r, hn::Set(d, p.norm));
      const V w_out = hn::Add(v, hn::Set(d, p.d_out_sphere)), w_in = hn::Add(v, hn::Set(d, p.d_in_sphere));
      outside = hn::Or(outside, hn::Lt(hn::Add(w_out, rho), neg_t));
      const auto in_j = hn::Not(hn::Ge(hn::Sub(w_in, rho), t));  // NaN: in J, as the scalar test
      const auto bit = hn::Set(du, std::uint64_t{1} << j);
      J = hn::Or(J, hn::IfThenElseZero(hn::RebindMask(du, in_j), bit));
      crossing = hn::Or(crossing, hn::IfThenElseZero(hn::RebindMask(du, hn::And(in_j, hn::Lt(hn::Sub(w_out, rho), neg_t))), bit));
      reach = hn::Or(reach, hn::IfThenElseZero(hn::RebindMask(du, hn::And(in_j, hn::Ge(hn::Add(w_in, rho), t))), bit));
      centre_in = hn::Or(centre_in, hn::IfThenElseZero(hn::RebindMask(du, hn::And(in_j, hn::Ge(w_in, t))), bit));
    }
    hn::Store(J, du, Jb + i);
    hn::Store(crossing, du, crossb + i);
    hn::Store(reach, du, reachb + i);
    hn::Store(centre_in, du, inb + i);
    out_bits[i / 64] |= mask_bits(d, outside) << (i % 64);
  }

  // What stage 1 decides alone; the rest sorted by J (a counting sort) and copied side by side.
  std::uint32_t open[kCap];
  std::size_t n_open = 0;
  std::uint32_t per_j[65] = {};
  for (std::size_t t = 0; t < nt; ++t) {
    const std::uint32_t q = idx[t];
    const std::uint64_t J = Jb[t], bit = std::uint64_t{1} << (q % 64);
    if (out_bits[t / 64] >> (t % 64) & 1u) {
      res.outside[q / 64] |= bit;
    } else if (J == 0) {
      res.inside[q / 64] |= bit;
    } else if (crossb[t] != 0 && (((J & (J - 1)) == 0 && reachb[t] == J) || inb[t] == J)) {
      res.meets[q / 64] |= bit;
    } else {
      open[n_open++] = std::uint32_t(t);
      ++per_j[J + 1];
    }
  }
  if (n_open == 0) return;
  for (int j = 1; j <= 64; ++j) per_j[j] += per_j[j - 1];  // per_j[J]: first position of J
  std::uint32_t order[kCap];
  alignas(64) double sx[kCap + 8], sy[kCap + 8], sz[kCap + 8], sr[kCap + 8];
  alignas(64) std::uint64_t scross[kCap + 8];
  {
    std::uint32_t next[64];
    std::memcpy(next, per_j, sizeof(next));
    for (std::size_t o = 0; o < n_open; ++o) {
      const std::uint32_t t = open[o];
      const std::uint32_t p = next[Jb[t]]++;
      order[p] = idx[t];
      sx[p] = bx[t], sy[p] = by[t], sz[p] = bz[t], sr[p] = br[t];
      scross[p] = crossb[t] != 0 ? ~std::uint64_t{0} : 0;
    }
    for (std::size_t p = n_open; p < n_open + N; ++p) sx[p] = sy[p] = sz[p] = sr[p] = 0.0, scross[p] = 0;
  }

  const V kappa_point = hn::Set(d, M::kPoint * M::u), kappa_distance = hn::Set(d, 1.0 + M::kDistance * M::u);
  const V kappa_centre = hn::Set(d, M::kFarkasCentre * M::u), kappa_normal = hn::Set(d, M::kFarkasNormal * M::u);
  const V underflow = hn::Set(d, M::kFarkasUnderflow), len_scale = hn::Set(d, 1.0 + 4.0 * M::u), value_scale = hn::Set(d, 1.0 - 4.0 * M::u);
  const V one = hn::Set(d, 1.0), half = hn::Set(d, 0.5), inf = hn::Set(d, std::numeric_limits<double>::infinity());
  const V gx = hn::Set(d, f.interior[0]), gy = hn::Set(d, f.interior[1]), gz = hn::Set(d, f.interior[2]);

  Subset subsets[41];
  for (unsigned J = 1; J < 64; ++J) {
    const std::size_t begin = per_j[J], end = per_j[J + 1];
    if (begin == end) continue;
    int js[6], m = 0;
    for (int j = 0; j < count; ++j)
      if (J >> j & 1) js[m++] = j;
    int n_sub = -1;  // the subsets, once a ball needs them
    for (std::size_t p = begin; p < end; p += N) {
      const auto valid = hn::FirstN(d, end - p);
      const V cx = hn::LoadU(d, sx + p), cy = hn::LoadU(d, sy + p), cz = hn::LoadU(d, sz + p), r = hn::LoadU(d, sr + p);
      const auto crossing = hn::RebindMask(d, hn::Ne(hn::LoadU(du, scross + p), hn::Zero(du)));
      const V r2 = hn::Mul(r, r);
      const V mc = hn::Max(hn::Abs(cx), hn::Max(hn::Abs(cy), hn::Abs(cz)));
      V sc[6], wc[6];
      for (int q = 0; q < m; ++q) {
        const ExactCertifiedPlane& pl = f.plane[std::size_t(js[q])];
        const V v = hn::Add(hn::Add(hn::Mul(hn::Set(d, pl.nx), cx), hn::Mul(hn::Set(d, pl.ny), cy)), hn::Mul(hn::Set(d, pl.nz), cz));
        sc[js[q]] = hn::Add(v, hn::Set(d, pl.d));
        wc[js[q]] = hn::Mul(hn::Add(hn::Mul(hn::Set(d, pl.a), mc), hn::Set(d, pl.ad)), slack);
      }
      // A point x proved in the ball and in every plane of J (sphere_witness).
      auto witness = [&](V x0, V x1, V x2) {
        const V dx = hn::Sub(x0, cx), dy = hn::Sub(x1, cy), dz = hn::Sub(x2, cz);
        const V q = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
        auto ok = hn::Le(hn::Mul(q, kappa_distance), r2);
        const V xm = hn::Max(hn::Abs(x0), hn::Max(hn::Abs(x1), hn::Abs(x2)));
        for (int k = 0; k < m; ++k) {
          const ExactCertifiedPlane& pl = f.plane[std::size_t(js[k])];
          const V v = hn::Add(hn::Add(hn::Add(hn::Mul(hn::Set(d, pl.nx), x0), hn::Mul(hn::Set(d, pl.ny), x1)),
                                      hn::Mul(hn::Set(d, pl.nz), x2)),
                              hn::Set(d, pl.d));
          const V margin = hn::Mul(hn::Mul(kappa_point, hn::Add(hn::Mul(hn::Set(d, pl.a), xm), hn::Set(d, pl.ad))), slack);
          ok = hn::And(ok, hn::Ge(v, margin));
        }
        return ok;
      };
      auto outside = hn::Lt(zero, zero), meets = outside;
      auto can_meet = hn::And(valid, crossing);  // a plane crossed: a common point proves intersecting
      if (!hn::AllFalse(d, can_meet)) {
        for (int k = 0; k < f.anchor_count; ++k) {
          const V dx = hn::Sub(hn::Set(d, f.anchor_x[std::size_t(k)]), cx), dy = hn::Sub(hn::Set(d, f.anchor_y[std::size_t(k)]), cy),
                  dz = hn::Sub(hn::Set(d, f.anchor_z[std::size_t(k)]), cz);
          const V s = hn::Mul(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)), kappa_distance);
          meets = hn::Or(meets, hn::And(can_meet, hn::Le(s, r2)));
        }
        can_meet = hn::AndNot(meets, can_meet);
      }
      if (f.has_interior && !hn::AllFalse(d, can_meet)) {
        V eta = zero;
        for (int q = 0; q < m; ++q) {
          const int j = js[q];
          const V denom = hn::Sub(hn::Set(d, f.interior_value[std::size_t(j)]), sc[j]);
          const auto use = hn::And(hn::Lt(sc[j], zero), hn::Gt(denom, zero));
          eta = hn::IfThenElse(use, hn::Max(eta, hn::Div(hn::Neg(sc[j]), denom)), eta);
        }
        eta = hn::Min(one, hn::Add(hn::Mul(eta, hn::Set(d, 1.0 + 0x1p-20)), hn::Set(d, 0x1p-30)));
        const V x0 = hn::Add(cx, hn::Mul(eta, hn::Sub(gx, cx))), x1 = hn::Add(cy, hn::Mul(eta, hn::Sub(gy, cy))),
                x2 = hn::Add(cz, hn::Mul(eta, hn::Sub(gz, cz)));
        meets = hn::Or(meets, hn::And(can_meet, witness(x0, x1, x2)));
        can_meet = hn::AndNot(meets, can_meet);
      }
      auto open_lanes = hn::AndNot(meets, valid);
      if (n_sub < 0 && !hn::AllFalse(d, open_lanes)) n_sub = subsets_of(f, js, m, subsets);
      for (int t = 0; t < n_sub && !hn::AllFalse(d, open_lanes); ++t) {
        const Subset& s = subsets[t];
        V mu[3];
        for (int i = 0; i < s.k; ++i) {
          V acc = hn::Mul(hn::Set(d, s.m[i][0]), sc[s.S[0]]);
          for (int q = 1; q < s.k; ++q) acc = hn::Add(acc, hn::Mul(hn::Set(d, s.m[i][q]), sc[s.S[q]]));
          mu[i] = acc;
        }
        V x0 = cx, x1 = cy, x2 = cz, dist2 = zero;
        for (int q = 0; q < s.k; ++q) {
          const ExactCertifiedPlane& pl = f.plane[std::size_t(s.S[q])];
          x0 = hn::Sub(x0, hn::Mul(mu[q], hn::Set(d, pl.nx)));
          x1 = hn::Sub(x1, hn::Mul(mu[q], hn::Set(d, pl.ny)));
          x2 = hn::Sub(x2, hn::Mul(mu[q], hn::Set(d, pl.nz)));
          dist2 = hn::Add(dist2, hn::Mul(mu[q], sc[s.S[q]]));
        }
        // Farkas (sphere_farkas): lambda = max(0, -mu) / its largest.
        V lambda[3], largest = zero;
        for (int q = 0; q < s.k; ++q) lambda[q] = hn::Max(zero, hn::Neg(mu[q])), largest = hn::Max(largest, lambda[q]);
        const auto farkas = hn::And(hn::And(open_lanes, hn::Gt(dist2, r2)), hn::And(hn::Gt(largest, zero), hn::Lt(largest, inf)));
        if (!hn::AllFalse(d, farkas)) {
          V value = zero, weight = zero, na = zero, n0 = zero, n1 = zero, n2 = zero;
          const V scale = hn::Div(one, largest);
          for (int q = 0; q < s.k; ++q) {
            const ExactCertifiedPlane& pl = f.plane[std::size_t(s.S[q])];
            const V l = hn::Mul(lambda[q], scale);
            value = hn::Add(value, hn::Mul(l, sc[s.S[q]]));
            weight = hn::Add(weight, hn::Mul(l, wc[s.S[q]]));
            na = hn::Add(na, hn::Mul(l, hn::Set(d, pl.a)));
            n0 = hn::Add(n0, hn::Mul(l, hn::Set(d, pl.nx)));
            n1 = hn::Add(n1, hn::Mul(l, hn::Set(d, pl.ny)));
            n2 = hn::Add(n2, hn::Mul(l, hn::Set(d, pl.nz)));
          }
          const V value_up = hn::Add(hn::Add(value, hn::Mul(hn::Mul(kappa_centre, weight), slack)), underflow);
          const V len = hn::Sqrt(hn::Add(hn::Add(hn::Mul(n0, n0), hn::Mul(n1, n1)), hn::Mul(n2, n2)));
          const V len_up = hn::Add(hn::Mul(hn::Add(hn::Mul(len, len_scale), hn::Mul(kappa_normal, na)), slack), underflow);
          const auto proved = hn::And(hn::And(farkas, hn::Lt(value_up, zero)),
                                      hn::Lt(hn::Mul(hn::Mul(r, len_up), slack), hn::Mul(hn::Neg(value_up), value_scale)));
          outside = hn::Or(outside, proved);
          open_lanes = hn::AndNot(proved, open_lanes);
        }
        // The projection pulled towards the interior point by half the room left in the ball.
        const auto pull = hn::And(hn::And(open_lanes, can_meet), hn::Lt(dist2, r2));
        if (f.has_interior && !hn::AllFalse(d, pull)) {
          const V dd = hn::Sqrt(hn::Max(zero, dist2));
          const V g0 = hn::Sub(gx, x0), g1 = hn::Sub(gy, x1), g2 = hn::Sub(gz, x2);
          const V gl = hn::Sqrt(hn::Add(hn::Add(hn::Mul(g0, g0), hn::Mul(g1, g1)), hn::Mul(g2, g2)));
          const V eta = hn::Min(one, hn::Div(hn::Mul(half, hn::Sub(r, dd)), gl));
          const auto proved = hn::And(pull, witness(hn::Add(x0, hn::Mul(eta, g0)), hn::Add(x1, hn::Mul(eta, g1)),
                                                    hn::Add(x2, hn::Mul(eta, g2))));
          meets = hn::Or(meets, proved);
          open_lanes = hn::AndNot(proved, open_lanes);
          can_meet = hn::AndNot(proved, can_meet);
        }
      }
      const std::uint64_t out_m = mask_bits(d, outside), meet_m = mask_bits(d, meets);
      for (std::size_t l = 0; l < N && p + l < end; ++l) {
        const std::uint32_t q = order[p + l];
        if (out_m >> l & 1u) res.outside[q / 64] |= std::uint64_t{1} << (q % 64);
        else if (meet_m >> l & 1u) res.meets[q / 64] |= std::uint64_t{1} << (q % 64);
      }
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

HWY_EXPORT(BallPassKernel);

void exact_ball_pass(const ExactCertifiedFrustum& f, const SphereSoa& balls, const std::uint64_t* todo,
                     detail::PassProofs& r) {
  HWY_DYNAMIC_DISPATCH(BallPassKernel)(f, balls, todo, r);
}

}  // namespace cullproof
#endif  // HWY_ONCE

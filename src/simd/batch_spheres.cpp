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
constexpr std::size_t kPad = 8;  // a vector's lanes past the last ball, read as zeros
using D = hn::CappedTag<double, 8>;
using DU = hn::RebindToUnsigned<D>;
using V = hn::Vec<D>;
using Mask = hn::Mask<D>;

Mask none() { return hn::FirstN(D(), 0); }

// The balls of `todo`, side by side in double: ball t is ball idx[t] of the chunk.
struct Gathered {
  std::uint32_t idx[kCap];
  alignas(64) double x[kCap + kPad], y[kCap + kPad], z[kCap + kPad], r[kCap + kPad];
  std::size_t count = 0;
};

void gather(const SphereSoa& balls, const std::uint64_t* todo, Gathered& g) {
  const std::size_t n = balls.count;
  g.count = 0;
  for (std::size_t w = 0; w < bitset_words(n); ++w)
    for (std::uint64_t b = todo[w] & detail::low_bits(n - w * 64); b != 0; b &= b - 1) {
      const std::size_t q = w * 64 + std::size_t(__builtin_ctzll(b));
      const std::size_t t = g.count++;
      g.idx[t] = std::uint32_t(q);
      g.x[t] = balls.x[q], g.y[t] = balls.y[q], g.z[t] = balls.z[q], g.r[t] = balls.radius[q];
    }
  for (std::size_t t = g.count; t < g.count + kPad; ++t) g.x[t] = g.y[t] = g.z[t] = g.r[t] = 0.0;
}

// Stage 1's bits per gathered ball: J (the planes it is not proved inside), the planes it
// crosses, reaches and has its centre in; and whether one plane proves it outside.
struct StageOne {
  alignas(64) std::uint64_t J[kCap + kPad], crossing[kCap + kPad], reach[kCap + kPad], centre_in[kCap + kPad];
  std::uint64_t outside[kCap / 64] = {};
};

void stage_one(const F& f, const Gathered& g, StageOne& s) {
  const D d;
  const DU du;
  const std::size_t N = hn::Lanes(d);
  for (std::size_t i = 0; i < g.count; i += N) {
    const V cx = hn::Load(d, g.x + i), cy = hn::Load(d, g.y + i), cz = hn::Load(d, g.z + i), r = hn::Load(d, g.r + i);
    const V mc = hn::Max(hn::Abs(cx), hn::Max(hn::Abs(cy), hn::Abs(cz)));
    const V t = hn::Mul(hn::Set(d, f.t_sphere), hn::Add(mc, r)), neg_t = hn::Neg(t);
    auto J = hn::Zero(du), crossing = hn::Zero(du), reach = hn::Zero(du), centre_in = hn::Zero(du);
    Mask outside = none();
    for (int j = 0; j < f.count; ++j) {
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
    hn::Store(J, du, s.J + i);
    hn::Store(crossing, du, s.crossing + i);
    hn::Store(reach, du, s.reach + i);
    hn::Store(centre_in, du, s.centre_in + i);
    s.outside[i / 64] |= mask_bits(d, outside) << (i % 64);
  }
}

// The balls stage 1 leaves open, grouped by J (a counting sort) and side by side: positions
// first[J] to first[J + 1] hold the balls of J; `crossing` is all ones for a ball with a plane
// crossed.
struct OpenBalls {
  std::uint32_t order[kCap];
  alignas(64) double x[kCap + kPad], y[kCap + kPad], z[kCap + kPad], r[kCap + kPad];
  alignas(64) std::uint64_t crossing[kCap + kPad];
  std::uint32_t first[65] = {};
  std::size_t count = 0;
};

// Records what stage 1 decides alone (outside; J empty: inside; one plane reached, or the centre
// in every plane of J, with a plane crossed: meets) and groups the rest.
void settle_stage_one(const Gathered& g, const StageOne& s, detail::PassProofs& res, OpenBalls& o) {
  std::uint32_t open[kCap];
  o.count = 0;
  for (std::size_t t = 0; t < g.count; ++t) {
    const std::uint32_t q = g.idx[t];
    const std::uint64_t J = s.J[t], bit = std::uint64_t{1} << (q % 64);
    if (s.outside[t / 64] >> (t % 64) & 1u) {
      res.outside[q / 64] |= bit;
    } else if (J == 0) {
      res.inside[q / 64] |= bit;
    } else if (s.crossing[t] != 0 && (((J & (J - 1)) == 0 && s.reach[t] == J) || s.centre_in[t] == J)) {
      res.meets[q / 64] |= bit;
    } else {
      open[o.count++] = std::uint32_t(t);
      ++o.first[J + 1];
    }
  }
  for (int j = 1; j <= 64; ++j) o.first[j] += o.first[j - 1];
  std::uint32_t next[64];
  std::memcpy(next, o.first, sizeof(next));
  for (std::size_t k = 0; k < o.count; ++k) {
    const std::uint32_t t = open[k];
    const std::uint32_t p = next[s.J[t]]++;
    o.order[p] = g.idx[t];
    o.x[p] = g.x[t], o.y[p] = g.y[t], o.z[p] = g.z[t], o.r[p] = g.r[t];
    o.crossing[p] = s.crossing[t] != 0 ? ~std::uint64_t{0} : 0;
  }
  for (std::size_t p = o.count; p < o.count + kPad; ++p) o.x[p] = o.y[p] = o.z[p] = o.r[p] = 0.0, o.crossing[p] = 0;
}

// The margins of the proofs (exact_certified.cpp, "Spheres"), in lanes.
struct ProofConstants {
  V slack, kappa_point, kappa_distance, kappa_centre, kappa_normal, underflow, len_scale, value_scale, gx, gy, gz;
  explicit ProofConstants(const F& f) {
    const D d;
    slack = hn::Set(d, 1.0 + M::kSlack);
    kappa_point = hn::Set(d, M::kPoint * M::u), kappa_distance = hn::Set(d, 1.0 + M::kDistance * M::u);
    kappa_centre = hn::Set(d, M::kFarkasCentre * M::u), kappa_normal = hn::Set(d, M::kFarkasNormal * M::u);
    underflow = hn::Set(d, M::kFarkasUnderflow), len_scale = hn::Set(d, 1.0 + 4.0 * M::u), value_scale = hn::Set(d, 1.0 - 4.0 * M::u);
    gx = hn::Set(d, f.interior[0]), gy = hn::Set(d, f.interior[1]), gz = hn::Set(d, f.interior[2]);
  }
};

// A vector of balls of one J: the planes js[0..m) of J; each ball's centre values sc and their
// rounding weights wc on those planes (indexed by plane); what is proved so far.
struct BallLanes {
  const F& f;
  const ProofConstants& k;
  const int* js;
  int m;
  V cx, cy, cz, r, r2, sc[6], wc[6];
  Mask outside, meets, can_meet, open;

  // A point x proved in the ball and in every plane of J (sphere_witness).
  Mask witness(V x0, V x1, V x2) const {
    const D d;
    const V dx = hn::Sub(x0, cx), dy = hn::Sub(x1, cy), dz = hn::Sub(x2, cz);
    const V q = hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz));
    Mask ok = hn::Le(hn::Mul(q, k.kappa_distance), r2);
    const V xm = hn::Max(hn::Abs(x0), hn::Max(hn::Abs(x1), hn::Abs(x2)));
    for (int i = 0; i < m; ++i) {
      const ExactCertifiedPlane& pl = f.plane[std::size_t(js[i])];
      const V v = hn::Add(
          hn::Add(hn::Add(hn::Mul(hn::Set(d, pl.nx), x0), hn::Mul(hn::Set(d, pl.ny), x1)), hn::Mul(hn::Set(d, pl.nz), x2)),
          hn::Set(d, pl.d));
      const V margin = hn::Mul(hn::Mul(k.kappa_point, hn::Add(hn::Mul(hn::Set(d, pl.a), xm), hn::Set(d, pl.ad))), k.slack);
      ok = hn::And(ok, hn::Ge(v, margin));
    }
    return ok;
  }

  void proved_meets(Mask proved) {
    meets = hn::Or(meets, proved);
    can_meet = hn::AndNot(meets, can_meet);
    open = hn::AndNot(proved, open);
  }

  // Witnesses for balls with a plane crossed: the anchors within the ball.
  void anchors() {
    const D d;
    Mask found = none();
    for (int a = 0; a < f.anchor_count; ++a) {
      const V dx = hn::Sub(hn::Set(d, f.anchor_x[std::size_t(a)]), cx), dy = hn::Sub(hn::Set(d, f.anchor_y[std::size_t(a)]), cy),
              dz = hn::Sub(hn::Set(d, f.anchor_z[std::size_t(a)]), cz);
      const V s = hn::Mul(hn::Add(hn::Add(hn::Mul(dx, dx), hn::Mul(dy, dy)), hn::Mul(dz, dz)), k.kappa_distance);
      found = hn::Or(found, hn::And(can_meet, hn::Le(s, r2)));
    }
    proved_meets(found);
  }

  // The point of the segment from the centre to the interior point just past its entry into P_J.
  void entry_point() {
    const D d;
    V eta = hn::Zero(d);
    for (int q = 0; q < m; ++q) {
      const int j = js[q];
      const V denom = hn::Sub(hn::Set(d, f.interior_value[std::size_t(j)]), sc[j]);
      const auto use = hn::And(hn::Lt(sc[j], hn::Zero(d)), hn::Gt(denom, hn::Zero(d)));
      eta = hn::IfThenElse(use, hn::Max(eta, hn::Div(hn::Neg(sc[j]), denom)), eta);
    }
    eta = hn::Min(hn::Set(d, 1.0), hn::Add(hn::Mul(eta, hn::Set(d, 1.0 + 0x1p-20)), hn::Set(d, 0x1p-30)));
    const V x0 = hn::Add(cx, hn::Mul(eta, hn::Sub(k.gx, cx))), x1 = hn::Add(cy, hn::Mul(eta, hn::Sub(k.gy, cy))),
            x2 = hn::Add(cz, hn::Mul(eta, hn::Sub(k.gz, cz)));
    proved_meets(hn::And(can_meet, witness(x0, x1, x2)));
  }

  // The projection of the centre onto the planes of S: mu = G_S^-1 s_S, the point x, and the
  // squared distance dist2 from the centre.
  void project(const Subset& s, V (&mu)[3], V& x0, V& x1, V& x2, V& dist2) const {
    const D d;
    for (int i = 0; i < s.k; ++i) {
      V acc = hn::Mul(hn::Set(d, s.m[i][0]), sc[s.S[0]]);
      for (int q = 1; q < s.k; ++q) acc = hn::Add(acc, hn::Mul(hn::Set(d, s.m[i][q]), sc[s.S[q]]));
      mu[i] = acc;
    }
    x0 = cx, x1 = cy, x2 = cz, dist2 = hn::Zero(d);
    for (int q = 0; q < s.k; ++q) {
      const ExactCertifiedPlane& pl = f.plane[std::size_t(s.S[q])];
      x0 = hn::Sub(x0, hn::Mul(mu[q], hn::Set(d, pl.nx)));
      x1 = hn::Sub(x1, hn::Mul(mu[q], hn::Set(d, pl.ny)));
      x2 = hn::Sub(x2, hn::Mul(mu[q], hn::Set(d, pl.nz)));
      dist2 = hn::Add(dist2, hn::Mul(mu[q], sc[s.S[q]]));
    }
  }

  // Farkas (sphere_farkas): lambda = max(0, -mu) / its largest proves the ball outside the
  // half-space sum lambda_j (n'_j, d'_j).
  void farkas(const Subset& s, const V (&mu)[3], V dist2) {
    const D d;
    const V zero = hn::Zero(d);
    V lambda[3], largest = zero;
    for (int q = 0; q < s.k; ++q) lambda[q] = hn::Max(zero, hn::Neg(mu[q])), largest = hn::Max(largest, lambda[q]);
    const Mask candidates = hn::And(hn::And(open, hn::Gt(dist2, r2)),
                                    hn::And(hn::Gt(largest, zero), hn::Lt(largest, hn::Set(d, std::numeric_limits<double>::infinity()))));
    if (hn::AllFalse(d, candidates)) return;
    V value = zero, weight = zero, na = zero, n0 = zero, n1 = zero, n2 = zero;
    const V scale = hn::Div(hn::Set(d, 1.0), largest);
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
    const V value_up = hn::Add(hn::Add(value, hn::Mul(hn::Mul(k.kappa_centre, weight), k.slack)), k.underflow);
    const V len = hn::Sqrt(hn::Add(hn::Add(hn::Mul(n0, n0), hn::Mul(n1, n1)), hn::Mul(n2, n2)));
    const V len_up = hn::Add(hn::Mul(hn::Add(hn::Mul(len, k.len_scale), hn::Mul(k.kappa_normal, na)), k.slack), k.underflow);
    const Mask proved = hn::And(hn::And(candidates, hn::Lt(value_up, zero)),
                                hn::Lt(hn::Mul(hn::Mul(r, len_up), k.slack), hn::Mul(hn::Neg(value_up), k.value_scale)));
    outside = hn::Or(outside, proved);
    open = hn::AndNot(proved, open);
  }

  // The projection x pulled towards the interior point by half the room left in the ball.
  void pulled_projection(V x0, V x1, V x2, V dist2) {
    const D d;
    const Mask pull = hn::And(hn::And(open, can_meet), hn::Lt(dist2, r2));
    if (!f.has_interior || hn::AllFalse(d, pull)) return;
    const V dd = hn::Sqrt(hn::Max(hn::Zero(d), dist2));
    const V g0 = hn::Sub(k.gx, x0), g1 = hn::Sub(k.gy, x1), g2 = hn::Sub(k.gz, x2);
    const V gl = hn::Sqrt(hn::Add(hn::Add(hn::Mul(g0, g0), hn::Mul(g1, g1)), hn::Mul(g2, g2)));
    const V eta = hn::Min(hn::Set(d, 1.0), hn::Div(hn::Mul(hn::Set(d, 0.5), hn::Sub(r, dd)), gl));
    proved_meets(hn::And(pull, witness(hn::Add(x0, hn::Mul(eta, g0)), hn::Add(x1, hn::Mul(eta, g1)), hn::Add(x2, hn::Mul(eta, g2)))));
  }
};

// The balls of J at positions [p, end) of `o`, one vector: witnesses, then each subset's
// Farkas multipliers and pulled projection, until every lane is proved or the subsets run out.
// The subsets are found (n_sub >= 0) when a ball first needs them.
void prove_lanes(const F& f, const ProofConstants& k, const OpenBalls& o, std::size_t p, std::size_t end, const int* js,
                 int m, Subset* subsets, int& n_sub, detail::PassProofs& res) {
  const D d;
  const DU du;
  const std::size_t N = hn::Lanes(d);
  BallLanes b{f, k, js, m, hn::LoadU(d, o.x + p), hn::LoadU(d, o.y + p), hn::LoadU(d, o.z + p), hn::LoadU(d, o.r + p),
              hn::Zero(d), {}, {}, none(), none(), none(), none()};
  const Mask valid = hn::FirstN(d, end - p);
  b.r2 = hn::Mul(b.r, b.r);
  const V mc = hn::Max(hn::Abs(b.cx), hn::Max(hn::Abs(b.cy), hn::Abs(b.cz)));
  for (int q = 0; q < m; ++q) {
    const ExactCertifiedPlane& pl = f.plane[std::size_t(js[q])];
    const V v = hn::Add(hn::Add(hn::Mul(hn::Set(d, pl.nx), b.cx), hn::Mul(hn::Set(d, pl.ny), b.cy)), hn::Mul(hn::Set(d, pl.nz), b.cz));
    b.sc[js[q]] = hn::Add(v, hn::Set(d, pl.d));
    b.wc[js[q]] = hn::Mul(hn::Add(hn::Mul(hn::Set(d, pl.a), mc), hn::Set(d, pl.ad)), k.slack);
  }
  // A plane crossed: a common point proves intersecting.
  b.can_meet = hn::And(valid, hn::RebindMask(d, hn::Ne(hn::LoadU(du, o.crossing + p), hn::Zero(du))));
  b.open = valid;
  if (!hn::AllFalse(d, b.can_meet)) b.anchors();
  if (f.has_interior && !hn::AllFalse(d, b.can_meet)) b.entry_point();
  if (n_sub < 0 && !hn::AllFalse(d, b.open)) n_sub = subsets_of(f, js, m, subsets);
  for (int t = 0; t < n_sub && !hn::AllFalse(d, b.open); ++t) {
    V mu[3], x0, x1, x2, dist2;
    b.project(subsets[t], mu, x0, x1, x2, dist2);
    b.farkas(subsets[t], mu, dist2);
    b.pulled_projection(x0, x1, x2, dist2);
  }
  const std::uint64_t out_m = mask_bits(d, b.outside), meet_m = mask_bits(d, b.meets);
  for (std::size_t l = 0; l < N && p + l < end; ++l) {
    const std::uint32_t q = o.order[p + l];
    if (out_m >> l & 1u) res.outside[q / 64] |= std::uint64_t{1} << (q % 64);
    else if (meet_m >> l & 1u) res.meets[q / 64] |= std::uint64_t{1} << (q % 64);
  }
}

void BallPassKernel(const F& f, const SphereSoa& balls, const std::uint64_t* todo, detail::PassProofs& res) {
  for (std::size_t w = 0; w < kCap / 64; ++w) res.outside[w] = res.inside[w] = res.meets[w] = 0;
  if (f.empty || f.count == 0 || balls.count == 0) return;
  Gathered g;
  gather(balls, todo, g);
  if (g.count == 0) return;
  StageOne s;
  stage_one(f, g, s);
  OpenBalls o;
  settle_stage_one(g, s, res, o);
  if (o.count == 0) return;
  const ProofConstants k(f);
  const std::size_t N = hn::Lanes(D());
  Subset subsets[41];
  for (unsigned J = 1; J < 64; ++J) {
    const std::size_t begin = o.first[J], end = o.first[J + 1];
    if (begin == end) continue;
    int js[6], m = 0;
    for (int j = 0; j < f.count; ++j)
      if (J >> j & 1) js[m++] = j;
    int n_sub = -1;
    for (std::size_t p = begin; p < end; p += N) prove_lanes(f, k, o, p, end, js, m, subsets, n_sub, res);
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

// The AABB array form's float pass (Highway, runtime dispatch): boxes tested in float, several
// per instruction, on the exact frustum's planes and the frame's combinations of planes, each
// with its own certified threshold (the derivation is src/simd/exact_certified.cpp, "The
// AABB array form's float pass"). Every bit it sets is a proof. What the float thresholds cannot
// resolve (boxes within a float rounding of a plane, or small against their distance from the
// origin) the box pass tests again in double, the scalar cascade's stage 1 a box per lane; a box
// none of them decides is left to the scalar cascade.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch_combinations.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/batch_combinations.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// The magnitude X of the boxes at i (the largest |coordinate|; a NaN sorts high) and their
// corners: box[0] the minima, box[1] the maxima.
template <class D>
HWY_INLINE hn::Vec<D> load_box(D d, const float* const* lo, const float* const* hi, std::size_t i,
                               hn::Vec<D> (&box)[2][3]) {
  const hn::RebindToUnsigned<D> du;
  auto xb = hn::Zero(du);
  for (int k = 0; k < 3; ++k) {
    box[0][k] = hn::LoadU(d, lo[k] + i);
    box[1][k] = hn::LoadU(d, hi[k] + i);
    xb = hn::Max(xb, hn::Max(abs_bits(du, box[0][k]), abs_bits(du, box[1][k])));
  }
  return hn::BitCast(d, xb);
}

// An item's value at the vertex of the box that maximises its C.x (its p-vertex).
template <class V>
HWY_INLINE V p_vertex_value(const ExactCertifiedFrustum::FloatItem& it, V cx, V cy, V cz, V dd, const V (&box)[2][3]) {
  return hn::MulAdd(cz, box[it.max[2]][2], hn::MulAdd(cy, box[it.max[1]][1], hn::MulAdd(cx, box[it.max[0]][0], dd)));
}

// The value of an item at a point x: fl(C.x + D), the multiply-adds in one order (any is sound).
template <class V>
HWY_INLINE V point_value(V cx, V cy, V cz, V dd, const V (&x)[3]) {
  return hn::MulAdd(cz, x[2], hn::MulAdd(cy, x[1], hn::MulAdd(cx, x[0], dd)));
}

// The planes' items and the arrays of their p- and n-vertex coordinates. The coefficients stay
// scalars, broadcast where used (an operand of the multiply-add): held as vectors, thirty of them
// would not fit the registers.
template <class D>
struct FirstPlanes {
  using V = hn::Vec<D>;
  float cx[6], cy[6], cz[6], d[6], t[6], delta[6];
  const float* pv[6][3];
  const float* nv[6][3];
  FirstPlanes(const ExactCertifiedFrustum::FloatItem* items, int planes, const float* const* lo, const float* const* hi) {
    for (int q = 0; q < planes; ++q) {
      const ExactCertifiedFrustum::FloatItem& it = items[q];
      cx[q] = it.cx, cy[q] = it.cy, cz[q] = it.cz, d[q] = it.d, t[q] = it.t, delta[q] = it.delta;
      for (int k = 0; k < 3; ++k) pv[q][k] = it.max[std::size_t(k)] ? hi[k] : lo[k], nv[q][k] = it.max[std::size_t(k)] ? lo[k] : hi[k];
    }
  }
  // fl(c.x + d) at the vertex whose coordinates are read from x (x[k] + i).
  V at(int q, const float* const* x, std::size_t i) const {
    const D dd;
    return hn::MulAdd(hn::Set(dd, cz[q]), hn::LoadU(dd, x[2] + i),
                      hn::MulAdd(hn::Set(dd, cy[q]), hn::LoadU(dd, x[1] + i),
                                 hn::MulAdd(hn::Set(dd, cx[q]), hn::LoadU(dd, x[0] + i), hn::Set(dd, d[q]))));
  }
  V at_point(int q, const V (&x)[3]) const {
    const D dd;
    return point_value(hn::Set(dd, cx[q]), hn::Set(dd, cy[q]), hn::Set(dd, cz[q]), hn::Set(dd, d[q]), x);
  }
};

// Boxes [0, n) (arrays readable up to n rounded up to N) on the planes, items [0, planes), each
// value compared with its item's threshold theta = fl(t X + delta): bits of `outside` (some
// p-vertex value below -theta), `inside` (every n-vertex value at least theta), `meets`
// (intersecting, proved), `open` (none of these) and, for an open box, J[i] (bit j: plane j not
// proved to hold it) and bit i of `meet_ok` (the box meets the frustum if every combination
// within J is proved positive on it: see exact_certified.cpp). `meets`: the box is not inside
// (some n-vertex value below -theta: a vertex strictly outside) and either a float point of it,
// the seed clamped to it or its centre fl(fl(lo + hi) 0.5) (both in the box exactly), is proved
// strictly inside every plane (a point is a box, with X its own magnitude), or meet_ok holds
// (every plane of J has the p-vertex strictly inside) and no combination lies within J (bit J of
// `no_combination`). Boxes with X > x_safe (or a NaN) are open, with meet_ok clear. The witness
// points are not tried for boxes whose bit is set in `tried` (may be null).
template <int kCount>
HWY_INLINE void FloatFirstImpl(const ExactCertifiedFrustum::FloatItem* items, int count, bool complete, float x_safe,
                               std::uint64_t no_combination, const float* seed, const std::uint64_t* tried,
                               const float* const* lo, const float* const* hi, std::size_t n, std::uint32_t* J,
                               std::uint64_t* outside, std::uint64_t* inside, std::uint64_t* meets,
                               std::uint64_t* open, std::uint64_t* meet_ok) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using Mk = hn::Mask<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  const int planes = kCount > 0 ? kCount : count;
  const FirstPlanes<decltype(d)> pl(items, planes, lo, hi);
  const V safe = hn::Set(d, x_safe), half = hn::Set(d, 0.5f);
  const V g[3] = {hn::Set(d, seed[0]), hn::Set(d, seed[1]), hn::Set(d, seed[2])};
  const Mk none = hn::Lt(half, half);
  for (std::size_t w = 0; w < bitset_words(n); ++w) outside[w] = inside[w] = meet_ok[w] = meets[w] = open[w] = 0;
  const auto none_lo = hn::Set(du, std::uint32_t(no_combination)), none_hi = hn::Set(du, std::uint32_t(no_combination >> 32));
  for (std::size_t i = 0; i < n; i += N) {
    auto xb = hn::Zero(du);
    for (int k = 0; k < 3; ++k)
      xb = hn::Max(xb, hn::Max(abs_bits(du, hn::LoadU(d, lo[k] + i)), abs_bits(du, hn::LoadU(d, hi[k] + i))));
    const V x = hn::BitCast(d, xb);  // the magnitude X (a NaN sorts high)
    // Each comparison through the sign of a sum or difference (a sum of floats rounds to zero
    // only when it is zero, and never changes sign; theta > 0): v < -theta iff fl(v + theta) < 0,
    // v >= theta iff fl(v - theta) >= 0, so the smallest over the planes decides for all of them.
    V low_out = hn::Set(d, 1.0f), low_held = low_out, low_strict = low_out, low_p_in = low_out;
    auto jbits = hn::Zero(du);
#pragma GCC unroll 6
    for (int q = 0; q < planes; ++q) {
      const V theta = hn::MulAdd(hn::Set(d, pl.t[q]), x, hn::Set(d, pl.delta[q]));
      const V vp = pl.at(q, pl.pv[q], i), vn = pl.at(q, pl.nv[q], i);
      const V held = hn::Sub(vn, theta);  // >= 0: the plane holds the box
      low_out = hn::Min(low_out, hn::Add(vp, theta));
      low_held = hn::Min(low_held, held);
      low_p_in = hn::Min(low_p_in, hn::Max(held, hn::Sub(vp, theta)));  // a plane of J: its p-vertex inside
      low_strict = hn::Min(low_strict, hn::Add(vn, theta));
      jbits = hn::Or(jbits, hn::ShiftLeftSame(hn::ShiftRight<31>(hn::BitCast(du, held)), q));  // the sign: not held
    }
    const V zero = hn::Zero(d);
    const Mk out = hn::Lt(low_out, zero), held_all = hn::Ge(low_held, zero), p_in = hn::Ge(low_p_in, zero),
             strictly_out = hn::Lt(low_strict, zero);
    const Mk ok = hn::Le(x, safe);  // false for NaN
    const Mk proved_out = hn::And(out, ok);
    const Mk rest = hn::AndNot(proved_out, ok);
    const Mk proved_in = hn::And(rest, held_all);
    const Mk cut = hn::AndNot(held_all, hn::And(rest, strictly_out));  // in the frame, not inside
    Mk proved_meet = none, may_meet = none;
    if (!hn::AllFalse(d, cut)) {
      may_meet = complete ? hn::And(cut, p_in) : none;
      const auto low5 = hn::And(jbits, hn::Set(du, 31u));  // J < 64: bit 5 picks the word
      const auto shifted = hn::IfThenElse(hn::TestBit(jbits, hn::Set(du, 32u)), none_hi >> low5, none_lo >> low5);
      const Mk alone = hn::RebindMask(d, hn::TestBit(shifted, hn::Set(du, 1u)));  // no combination within J
      proved_meet = hn::And(may_meet, alone);
      Mk witness = hn::AndNot(proved_meet, cut);
      if (tried != nullptr) {  // boxes whose witness points were tried before
        std::uint8_t bytes[8];
        const std::uint64_t word = tried[i / 64] >> (i % 64);
        std::memcpy(bytes, &word, sizeof word);
        witness = hn::AndNot(hn::LoadMaskBits(d, bytes), witness);
      }
      if (!hn::AllFalse(d, witness)) {  // the witness points
        V p[3], c[3];
        auto xp = hn::Zero(du), xc = hn::Zero(du);
        for (int k = 0; k < 3; ++k) {
          const V a = hn::LoadU(d, lo[k] + i), b = hn::LoadU(d, hi[k] + i);
          p[k] = hn::Min(hn::Max(g[k], a), b);
          c[k] = hn::Mul(hn::Add(a, b), half);
          xp = hn::Max(xp, abs_bits(du, p[k]));
          xc = hn::Max(xc, abs_bits(du, c[k]));
        }
        V low_p = hn::Set(d, 1.0f), low_c = low_p;  // as above: the smallest fl(v - theta) over the planes
        for (int q = 0; q < planes; ++q) {
          const V t = hn::Set(d, pl.t[q]), delta = hn::Set(d, pl.delta[q]);
          low_p = hn::Min(low_p, hn::Sub(pl.at_point(q, p), hn::MulAdd(t, hn::BitCast(d, xp), delta)));
          low_c = hn::Min(low_c, hn::Sub(pl.at_point(q, c), hn::MulAdd(t, hn::BitCast(d, xc), delta)));
        }
        proved_meet = hn::Or(proved_meet, hn::And(witness, hn::Ge(hn::Max(low_p, low_c), zero)));
      }
    }
    const std::uint64_t keep = detail::low_bits(std::min(N, n - i));
    const std::uint64_t ob = mask_bits(d, proved_out) & keep, ib = mask_bits(d, proved_in) & keep,
                        mb = mask_bits(d, proved_meet) & keep, open_bits = keep & ~(ob | ib | mb);
    hn::StoreU(jbits, du, J + i);
    outside[i / 64] |= ob << (i % 64);
    inside[i / 64] |= ib << (i % 64);
    meets[i / 64] |= mb << (i % 64);
    open[i / 64] |= open_bits << (i % 64);
    meet_ok[i / 64] |= (mask_bits(d, may_meet) & open_bits) << (i % 64);
  }
}

void FloatFirstKernel(const ExactCertifiedFrustum::FloatItem* items, int planes, bool complete, float x_safe,
                      std::uint64_t no_combination, const float* seed, const std::uint64_t* tried,
                      const float* const* lo, const float* const* hi, std::size_t n, std::uint32_t* J,
                      std::uint64_t* outside, std::uint64_t* inside, std::uint64_t* meets, std::uint64_t* open,
                      std::uint64_t* meet_ok) {
  if (planes == 6)
    return FloatFirstImpl<6>(items, planes, complete, x_safe, no_combination, seed, tried, lo, hi, n, J, outside,
                             inside, meets, open, meet_ok);
  FloatFirstImpl<0>(items, planes, complete, x_safe, no_combination, seed, tried, lo, hi, n, J, outside, inside,
                    meets, open, meet_ok);
}

// The open boxes, sorted by J (J[i] for box i of lo / hi; [0, n) padded with zeros, J = 0, to
// whole vectors), on the combinations within the union of a vector's J: bit i of `outside` where
// one within box i's J proves it outside (X <= x_safe), of `positive` where every one within its
// J is proved positive on it. Only within J does a combination prove anything (outside J, one of
// its planes holds the box, and where the others are >= 0 so is it) or need to be positive.
void FloatOpenKernel(const ExactCertifiedFrustum::FloatItem* items, int planes, const std::uint64_t* comb_in,
                     float x_safe, const float* const* lo, const float* const* hi, const std::uint32_t* J,
                     std::size_t n, std::uint64_t* outside, std::uint64_t* positive) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using Mk = hn::Mask<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  const ExactCertifiedFrustum::FloatItem* combination = items + planes;
  const V zero = hn::Zero(d), safe = hn::Set(d, x_safe);
  for (std::size_t w = 0; w < bitset_words(n); ++w) outside[w] = positive[w] = 0;
  for (std::size_t i = 0; i < n; i += N) {
    std::uint32_t any = 0, every = 63;
    for (std::size_t k = 0; k < std::min(N, n - i); ++k) any |= J[i + k], every &= J[i + k];
    V box[2][3];
    const V x = load_box(d, lo, hi, i, box);
    // Combination q (bit q % 64 of word q / 64) at each box's vertex its signs choose, and its
    // threshold.
    auto value = [&](std::size_t q, V& theta) {
      const ExactCertifiedFrustum::FloatItem& it = combination[q];
      theta = hn::MulAdd(hn::Set(d, it.t), x, hn::Set(d, it.delta));
      return p_vertex_value(it, hn::Set(d, it.cx), hn::Set(d, it.cy), hn::Set(d, it.cz), hn::Set(d, it.d), box);
    };
    // The combinations within every box's J (most, the boxes sorted by J): fl(v + theta) < 0 iff
    // v < -theta and fl(v - theta) < 0 iff v < theta (a sum of floats rounds to zero only when
    // it is zero), so the smallest of each decides over all of them.
    V low_out = hn::Set(d, 1.0f), low_fail = low_out;
    for (std::size_t w = 0; w < 2; ++w)
      for (std::uint64_t bits = comb_in[2 * every + w]; bits != 0; bits &= bits - 1) {
        V theta;
        const V vp = value(64 * w + std::size_t(__builtin_ctzll(bits)), theta);
        low_out = hn::Min(low_out, hn::Add(vp, theta));
        low_fail = hn::Min(low_fail, hn::Sub(vp, theta));
      }
    Mk out = hn::Lt(low_out, zero), fail = hn::Lt(low_fail, zero);
    // The others, each on the boxes whose J holds its planes.
    if (any != every) {
      const auto jv = hn::LoadU(du, J + i);
      Mk not_held[6];
      for (int j = 0; j < 6; ++j) not_held[j] = hn::RebindMask(d, hn::TestBit(jv, hn::Set(du, 1u << j)));
      for (std::size_t w = 0; w < 2; ++w)
        for (std::uint64_t bits = comb_in[2 * any + w] & ~comb_in[2 * every + w]; bits != 0; bits &= bits - 1) {
          const std::size_t q = 64 * w + std::size_t(__builtin_ctzll(bits));
          const ExactCertifiedFrustum::FloatItem& it = combination[q];
          V theta;
          const V vp = value(q, theta);
          const Mk within = hn::And(not_held[it.member[0]], hn::And(not_held[it.member[1]], not_held[it.member[2]]));
          out = hn::Or(out, hn::And(within, hn::Lt(vp, hn::Neg(theta))));
          fail = hn::Or(fail, hn::And(within, hn::Lt(vp, theta)));
        }
    }
    const std::uint64_t keep = detail::low_bits(std::min(N, n - i));
    outside[i / 64] |= (mask_bits(d, hn::And(out, hn::Le(x, safe))) & keep) << (i % 64);  // false for NaN
    positive[i / 64] |= (mask_bits(d, hn::Not(fail)) & keep) << (i % 64);
  }
}

// exact_box_planes: the scalar stage 1's operations per lane (aabb_planes and centre_extent in
// exact_certified.cpp, in their order, no fused multiply-add), so each lane's J, crossing and
// p-vertex bits are the scalar function's.
void BoxPlanesKernel(const ExactCertifiedFrustum& f, const AabbSoa& boxes, const std::uint64_t* todo,
                     detail::PassProofs& res) {
  const hn::CappedTag<double, 8> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  constexpr std::size_t kCap = detail::PassProofs::kCapacity;
  const std::size_t N = hn::Lanes(d), n = boxes.count, words = bitset_words(n);
  for (std::size_t w = 0; w < kCap / 64; ++w) res.outside[w] = res.inside[w] = res.meets[w] = 0;
  if (f.empty || n == 0) return;  // no plane at all (count 0): every box inside, as the scalar test
  // The boxes of `todo`, side by side in double (box t is box idx[t] of `boxes`).
  std::uint32_t idx[kCap];
  alignas(64) double c[6][kCap + 8];
  const float* src[6] = {boxes.min_x, boxes.min_y, boxes.min_z, boxes.max_x, boxes.max_y, boxes.max_z};
  std::size_t nt = 0;
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t b = todo[w] & detail::low_bits(n - w * 64); b != 0; b &= b - 1) {
      const std::size_t q = w * 64 + std::size_t(__builtin_ctzll(b));
      idx[nt] = std::uint32_t(q);
      for (int k = 0; k < 6; ++k) c[k][nt] = src[k][q];
      ++nt;
    }
  if (nt == 0) return;
  for (std::size_t t = nt; t < nt + N; ++t)
    for (int k = 0; k < 6; ++k) c[k][t] = 0.0;
  alignas(64) std::uint64_t Jb[kCap + 8], crossb[kCap + 8], pinb[kCap + 8];
  std::uint64_t out_bits[kCap / 64] = {}, finite_bits[kCap / 64] = {};
  const V half = hn::Set(d, 0.5), t_box = hn::Set(d, f.t_box);
  for (std::size_t i = 0; i < nt; i += N) {
    V lo[3], hi[3], ce[3], he[3];
    auto finite = hn::Eq(hn::Zero(d), hn::Zero(d));
    for (int k = 0; k < 3; ++k) {
      lo[k] = hn::Load(d, c[k] + i), hi[k] = hn::Load(d, c[k + 3] + i);
      finite = hn::And(finite, hn::And(hn::IsFinite(lo[k]), hn::IsFinite(hi[k])));
      ce[k] = hn::Mul(half, hn::Add(lo[k], hi[k]));
      he[k] = hn::Mul(half, hn::Sub(hi[k], lo[k]));
    }
    // m as the scalar test has it; for a finite box only the sign of a zero could differ, and
    // T = t_box m is compared, never its sign.
    const V m = hn::Max(hn::Max(hn::Max(hi[0], hi[1]), hi[2]), hn::Neg(hn::Min(hn::Min(lo[0], lo[1]), lo[2])));
    const V T = hn::Mul(t_box, m), neg_t = hn::Neg(T);
    auto J = hn::Zero(du), crossing = hn::Zero(du), p_in = hn::Zero(du);
    auto outside = hn::Lt(T, T);  // false
    for (int j = 0; j < f.count; ++j) {
      const ExactCertifiedPlane& p = f.plane[std::size_t(j)];
      const V nx = hn::Set(d, p.nx), ny = hn::Set(d, p.ny), nz = hn::Set(d, p.nz);
      const V s = hn::Add(hn::Add(hn::Mul(nx, ce[0]), hn::Mul(ny, ce[1])), hn::Mul(nz, ce[2]));
      const V rad = hn::Add(hn::Add(hn::Abs(hn::Mul(nx, he[0])), hn::Abs(hn::Mul(ny, he[1]))), hn::Abs(hn::Mul(nz, he[2])));
      const V so = hn::Add(s, hn::Set(d, p.d_out_box)), si = hn::Add(s, hn::Set(d, p.d_in_box));
      outside = hn::Or(outside, hn::Lt(hn::Add(so, rad), neg_t));
      const auto bit = hn::Set(du, std::uint64_t{1} << j);
      J = hn::Or(J, hn::IfThenElseZero(hn::RebindMask(du, hn::Not(hn::Ge(hn::Sub(si, rad), T))), bit));
      crossing = hn::Or(crossing, hn::IfThenElseZero(hn::RebindMask(du, hn::Lt(hn::Sub(so, rad), neg_t)), bit));
      p_in = hn::Or(p_in, hn::IfThenElseZero(hn::RebindMask(du, hn::Ge(hn::Add(si, rad), T)), bit));
    }
    hn::Store(J, du, Jb + i);
    hn::Store(crossing, du, crossb + i);
    hn::Store(p_in, du, pinb + i);
    out_bits[i / 64] |= mask_bits(d, outside) << (i % 64);
    finite_bits[i / 64] |= mask_bits(d, finite) << (i % 64);
  }
  for (std::size_t t = 0; t < nt; ++t) {
    if (!(finite_bits[t / 64] >> (t % 64) & 1u)) continue;
    const std::uint64_t bit = std::uint64_t{1} << (idx[t] % 64);
    const std::size_t w = idx[t] / 64;
    const std::uint64_t J = Jb[t];
    if (out_bits[t / 64] >> (t % 64) & 1u) res.outside[w] |= bit;
    else if (J == 0) res.inside[w] |= bit;
    else if (crossb[t] != 0 && (pinb[t] & J) == J && f.same_p_vertex[J]) res.meets[w] |= bit;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

static_assert(HWY_MAX_BYTES / sizeof(float) <= kReadable, "a vector reads at most kReadable floats");

HWY_EXPORT(FloatFirstKernel);
HWY_EXPORT(FloatOpenKernel);
HWY_EXPORT(BoxPlanesKernel);

void exact_box_planes(const ExactCertifiedFrustum& f, const AabbSoa& boxes, const std::uint64_t* todo,
                      detail::PassProofs& r) {
  HWY_DYNAMIC_DISPATCH(BoxPlanesKernel)(f, boxes, todo, r);
}
void exact_float_first(const ExactCertifiedFrustum& f, const AabbSoa& part, const glm::vec3& seed,
                       FloatFirstResult& r, const std::uint64_t* tried) {
  const float g[3] = {seed.x, seed.y, seed.z};
  const float* lo[3] = {part.min_x, part.min_y, part.min_z};
  const float* hi[3] = {part.max_x, part.max_y, part.max_z};
  HWY_DYNAMIC_DISPATCH(FloatFirstKernel)(f.float_item.data(), f.float_planes, f.float_complete, f.float_x_safe,
                                         f.float_no_combination, g, tried, lo, hi, part.count, r.J, r.outside,
                                         r.inside, r.meets, r.open, r.meet_ok);
}

void exact_float_open(const ExactCertifiedFrustum& f, const AabbSoa& boxes, const FloatFirstResult& r,
                      FloatOpenResult& o) {
  constexpr std::size_t kCap = FloatFirstResult::kCapacity, kPad = kReadable;
  const std::size_t words = bitset_words(boxes.count);
  // The open boxes sorted by J (a counting sort), copied side by side.
  std::uint32_t count[64] = {}, start[64];
  std::size_t open = 0;
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t b = r.open[w]; b != 0; b &= b - 1) ++count[r.J[w * 64 + std::size_t(__builtin_ctzll(b))]], ++open;
  o.count = open;
  if (open == 0) return;
  for (std::uint32_t J = 0, at = 0; J < 64; ++J) start[J] = at, at += count[J];
  alignas(64) float box[6][kCap + kPad];
  alignas(64) std::uint32_t J[kCap + kPad];
  std::uint64_t meet_ok[kCap / 64] = {};  // by position
  const float* src[6] = {boxes.min_x, boxes.min_y, boxes.min_z, boxes.max_x, boxes.max_y, boxes.max_z};
  for (std::size_t w = 0; w < words; ++w)
    for (std::uint64_t b = r.open[w]; b != 0; b &= b - 1) {
      const std::size_t q = w * 64 + std::size_t(__builtin_ctzll(b));
      const std::uint32_t p = start[r.J[q]]++;
      o.order[p] = std::uint32_t(q), J[p] = r.J[q];
      meet_ok[p / 64] |= (r.meet_ok[w] >> (q % 64) & 1u) << (p % 64);
      for (int k = 0; k < 6; ++k) box[k][p] = src[k][q];
    }
  for (std::size_t p = open; p < open + kPad; ++p) {  // whole vectors: zeros, J = 0
    J[p] = 0;
    for (int k = 0; k < 6; ++k) box[k][p] = 0.0f;
  }
  std::uint64_t positive[kCap / 64];
  const float* lo[3] = {box[0], box[1], box[2]};
  const float* hi[3] = {box[3], box[4], box[5]};
  HWY_DYNAMIC_DISPATCH(FloatOpenKernel)(f.float_item.data(), f.float_planes, f.comb_in[0].data(),
                                        f.float_x_safe, lo, hi, J, open, o.outside, positive);
  for (std::size_t w = 0; w < bitset_words(open); ++w) o.meets[w] = positive[w] & meet_ok[w] & ~o.outside[w];
}

}  // namespace cullproof
#endif  // HWY_ONCE

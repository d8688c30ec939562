// Certified SIMD batch culling of AABBs and spheres (Highway, runtime dispatch).
//
// Sources: the n/p-vertex test of Assarsson & Möller 2000 §3.1 with the min/max choice hoisted
// per plane (as src/simd/batch_soa.cpp), and the fast path of certified.cpp: scaled planes, the
// constant part of the margin folded into d_out / d_in, one uniform T = fl(t M) per volume.
// Claim: certified-conservative.
//
// Why this kernel may use FMA and the plain one may not: the certified bound holds for any
// evaluation order with or without fused multiply-adds (certified.cpp), so each plane value is
// three fused multiply-adds, v = fl(n_z z + fl(n_y y + fl(n_x x + d_out))). Where the dispatched
// target has no FMA (Highway's HWY_NATIVE_FMA: SSE2-SSE4 and the scalar fallbacks) the volumes go
// through the same operations one by one with std::fma (correctly rounded, slow), so the
// verdicts are the same on every machine (the corpus replays them). The plain batch must give pn_vertex's
// verdicts bit for bit, which rules FMA out for it; it is bound by its 18 loads per vector
// anyway, not by arithmetic (bench/cull/NOTES.md). So the verdicts here are those of the scalar certified tests except
// within the rounding margin, where either may answer `intersecting`; tests/certified checks the
// kernel bit for bit against a scalar model of these operations.
//
// Per volume: M (the largest coordinate magnitude; for a box taken from the p-vertex
// coordinates of two planes whose normals lie in opposite octants, which together read all six
// arrays, so M costs no extra load), T = fl(t M), visible iff min_k v_k >= -T, inside iff
// also min_k w_k >= T (w: the n-vertex value with d_in). A 64-volume word with a lane M > m_safe
// or NaN is flagged; those lanes are recomputed by the scalar functions, whose guarded path
// handles overflow. A tail shorter than 64 runs through the kernel in a padded copy, so a
// volume's verdict does not depend on its position in the batch.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch_certified.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/certified_batch.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#ifndef CULLPROOF_BATCH_CERTIFIED_SHARED
#define CULLPROOF_BATCH_CERTIFIED_SHARED
namespace cullproof::certified_batch_detail {
// A fast-path plane (CertifiedPlane) with the box arrays of its p- and n-vertex.
struct CertPlane {
  float nx, ny, nz, d_out, d_in, norm;
  const float* px;
  const float* py;
  const float* pz;
  const float* qx;
  const float* qy;
  const float* qz;
};
struct Arrays {
  const float* min[3];
  const float* max[3];
};

}  // namespace cullproof::certified_batch_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using certified_batch_detail::Arrays;
using certified_batch_detail::CertPlane;

// AVX-512 (32 vector registers, VRANGEPS): the covered kernel keeps the six box coordinates in
// registers and takes every plane's vertices from them (see CertAabbOctant).
#undef CULLPROOF_CERT_AVX512
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
#define CULLPROOF_CERT_AVX512 1
#else
#define CULLPROOF_CERT_AVX512 0
#endif

// fl(nz z + fl(ny y + fl(nx x + d))): the plane value with the offset first.
template <class V>
HWY_INLINE V plane3(V nx, V ny, V nz, V d, V x, V y, V z) {
  return hn::MulAdd(nz, z, hn::MulAdd(ny, y, hn::MulAdd(nx, x, d)));
}

// A loaded vector kept in a register: an empty asm the compiler cannot see through, so that the
// two uses of a covering plane's p-vertex coordinates (the plane value and M) share one load
// instead of each folding its own load from memory (the kernel is load-bound).
template <class V>
HWY_INLINE V in_register(V v) {
#if HWY_ARCH_X86 && HWY_TARGET != HWY_EMU128 && HWY_TARGET != HWY_SCALAR
  asm("" : "+v"(v.raw));
#endif
  return v;
}

// The fast planes as vectors: one broadcast per coefficient, once per kernel call.
template <class D>
struct PlaneVecs {
  using V = hn::Vec<D>;
  V nx[6], ny[6], nz[6], dout[6], din[6], len[6];
  PlaneVecs(D d, const CertPlane* p, int n) {
    for (int k = 0; k < n; ++k) {
      nx[k] = hn::Set(d, p[k].nx);
      ny[k] = hn::Set(d, p[k].ny);
      nz[k] = hn::Set(d, p[k].nz);
      dout[k] = hn::Set(d, p[k].d_out);
      din[k] = hn::Set(d, p[k].d_in);
      len[k] = hn::Set(d, p[k].norm);
    }
  }
};

// A vector's verdicts into the word's bits: visible iff min v >= -T, inside iff also min w >= T.
template <bool kInside, class D, class V>
HWY_INLINE void record(D d, V minp, V minn, V ntm, std::size_t j, std::uint64_t& vis, std::uint64_t& ins) {
  const auto v = hn::Ge(minp, ntm);
  vis |= mask_bits(d, v) << j;
  if (kInside) ins |= mask_bits(d, hn::And(v, hn::Ge(minn, hn::Neg(ntm)))) << j;
}

// A word's bits out, and its flag: some lane's M (the bits' maximum) above m_safe, or NaN.
template <bool kInside, class D, class VU>
HWY_INLINE void store_word(D d, std::size_t w, std::size_t w_begin, std::uint64_t vis, std::uint64_t ins, VU mword,
                           hn::Vec<D> msafe, std::uint64_t* visible, std::uint64_t* inside, std::uint8_t* unsafe) {
  visible[w] = vis;
  if (kInside) inside[w] = ins;
  unsafe[w - w_begin] = hn::AllTrue(d, hn::Le(hn::BitCast(d, mword), msafe)) ? 0u : 1u;
}

// Batches of more than 64k boxes (past L2) prefetch the six arrays 8 words ahead, as the plain
// batch does (src/simd/batch_soa.cpp); the p- and n-vertex arrays of plane 0 are the six.
constexpr std::size_t kPrefetchWords = 1024, kPrefetchAhead = 8;
HWY_INLINE void prefetch_ahead(const CertPlane& p0, std::size_t w, std::size_t total_words) {
  if (total_words <= kPrefetchWords || w + kPrefetchAhead >= total_words) return;
  const float* arr[6] = {p0.px, p0.py, p0.pz, p0.qx, p0.qy, p0.qz};
  for (int c = 0; c < 6; ++c)
    for (int l = 0; l < 64; l += 16) __builtin_prefetch(arr[c] + (w + kPrefetchAhead) * 64 + l);
}

// Boxes of words [w_begin, w_end), the general case (no two planes in opposite octants, or
// fewer than six active planes): M from the six arrays. kCount: 6 (unrolled) or 0 (count at
// run time).
template <bool kInside, int kCount>
HWY_INLINE void CertAabbImpl(const CertPlane* planes, int count, const Arrays& a, float t, float m_safe,
                             std::size_t w_begin, std::size_t w_end, std::size_t total_words, std::uint64_t* visible,
                             std::uint64_t* inside, std::uint8_t* unsafe) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using VU = hn::Vec<decltype(du)>;
  const std::size_t N = hn::Lanes(d);
  const int n = kCount > 0 ? kCount : count;
  const PlaneVecs<decltype(d)> pv(d, planes, n);
  const V(&nx)[6] = pv.nx, (&ny)[6] = pv.ny, (&nz)[6] = pv.nz, (&dout)[6] = pv.dout, (&din)[6] = pv.din;
  const V ntv = hn::Set(d, -t), msafe = hn::Set(d, m_safe), inf = hn::Set(d, HUGE_VALF);
  for (std::size_t w = w_begin; w < w_end; ++w) {
    std::uint64_t vis = 0, ins = 0;
    VU mword = hn::Zero(du);
    prefetch_ahead(planes[0], w, total_words);
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      VU mb = hn::Zero(du);
      for (int c = 0; c < 3; ++c)
        mb = hn::Max(mb, hn::Max(abs_bits(du, hn::LoadU(d, a.min[c] + i)), abs_bits(du, hn::LoadU(d, a.max[c] + i))));
      V minp = inf, minn = inf;
#pragma GCC unroll 6
      for (int k = 0; k < n; ++k) {
        const CertPlane& s = planes[k];
        minp = hn::Min(minp, plane3(nx[k], ny[k], nz[k], dout[k], hn::LoadU(d, s.px + i), hn::LoadU(d, s.py + i),
                                    hn::LoadU(d, s.pz + i)));
        if (kInside)
          minn = hn::Min(minn, plane3(nx[k], ny[k], nz[k], din[k], hn::LoadU(d, s.qx + i), hn::LoadU(d, s.qy + i),
                                      hn::LoadU(d, s.qz + i)));
      }
      mword = hn::Max(mword, mb);
      const V ntm = hn::Mul(ntv, hn::BitCast(d, mb));  // -T: fl(-t M) = -fl(t M)
      record<kInside>(d, minp, minn, ntm, j, vis, ins);
    }
    store_word<kInside>(d, w, w_begin, vis, ins, mword, msafe, visible, inside, unsafe);
  }
}

// The covering pair (planes 0 and 1, normals in opposite octants) for the boxes at i: returns the
// smaller of the two plane values, sets m to M and (AVX-512) uv[0] / uv[1] to the loaded p-vertex
// coordinates of plane 0 / plane 1. Of min_j and max_j one is the p-vertex coordinate of plane 0
// and the other that of plane 1, so the pair's six loads are all of M's inputs (held in
// registers: each is used more than once).
// AVX-512: axis by axis, VRANGEPS (imm 0b1011: the larger magnitude, sign cleared) gives
// max(|min_j|, |max_j|) in one instruction with no constant, and an unsigned maximum of the bits
// gathers them (a NaN sorts high, as in abs_bits), equal to magnitude_bits() for every box
// without NaN (a NaN coordinate flags the word either way);
// interleaved with the two planes' multiply-adds so that few values are live (24 plane
// constants fill most of the 32 registers, and a spilled value is a further load per vector:
// with the octant form below, 3 spills cost 16% in L2). Other targets: with plane 0's octant
// known at compile time, max(max_j) and -min(min_j), equal to the largest magnitude for a valid
// box.
template <int kOct, class D, class DU, class PV>
HWY_INLINE hn::Vec<D> covering_pair(D d, DU du, const PV& pv, const CertPlane* planes, std::size_t i,
                                    hn::Vec<D>& m, hn::Vec<D> (&uv)[2][3]) {
  using V = hn::Vec<D>;
  const float* const c0[3] = {planes[0].px, planes[0].py, planes[0].pz};
  const float* const c1[3] = {planes[1].px, planes[1].py, planes[1].pz};
#if CULLPROOF_CERT_AVX512
  const V* const n0[3] = {pv.nx, pv.ny, pv.nz};
  V a0 = pv.dout[0], a1 = pv.dout[1];
  hn::Vec<DU> mb;
  for (int j = 0; j < 3; ++j) {
    const V u = in_register(hn::LoadU(d, c0[j] + i)), v = in_register(hn::LoadU(d, c1[j] + i));
    uv[0][j] = u;
    uv[1][j] = v;
    const auto r = hn::BitCast(du, V{_mm512_range_ps(u.raw, v.raw, 0x0B)});
    mb = j == 0 ? r : hn::Max(mb, r);
    a0 = hn::MulAdd(n0[j][0], u, a0);
    a1 = hn::MulAdd(n0[j][1], v, a1);
  }
  m = hn::BitCast(d, mb);
  return hn::Min(a0, a1);
#else
  V p[2][3];
  for (int j = 0; j < 3; ++j) {
    p[0][j] = in_register(hn::LoadU(d, c0[j] + i));
    p[1][j] = in_register(hn::LoadU(d, c1[j] + i));
  }
  constexpr int kx = (kOct & 1) ? 0 : 1, ky = (kOct & 2) ? 0 : 1, kz = (kOct & 4) ? 0 : 1;  // plane with max_j
  const V hi = hn::Max(hn::Max(p[kx][0], p[ky][1]), p[kz][2]);
  const V lo = hn::Min(hn::Min(p[1 - kx][0], p[1 - ky][1]), p[1 - kz][2]);
  m = hn::Max(hi, hn::Neg(lo));
  (void)du;
  (void)uv;
  return hn::Min(plane3(pv.nx[0], pv.ny[0], pv.nz[0], pv.dout[0], p[0][0], p[0][1], p[0][2]),
                 plane3(pv.nx[1], pv.ny[1], pv.nz[1], pv.dout[1], p[1][0], p[1][1], p[1][2]));
#endif
}

// AVX-512: plane k's p-vertex value (and n-vertex value, kInside) from the registers of the
// covering pair. Bit j of E: plane k's p-vertex reads plane 1's array on axis j (its normal's
// sign differs from plane 0's there); its n-vertex reads the other one.
template <unsigned E, bool kInside, class PV, class V>
HWY_INLINE void side_plane(const PV& pv, int k, const V (&uv)[2][3], V& pval, V& nval) {
  constexpr unsigned ex = E & 1u, ey = (E >> 1) & 1u, ez = (E >> 2) & 1u;
  pval = plane3(pv.nx[k], pv.ny[k], pv.nz[k], pv.dout[k], uv[ex][0], uv[ey][1], uv[ez][2]);
  if (kInside) nval = plane3(pv.nx[k], pv.ny[k], pv.nz[k], pv.din[k], uv[1 - ex][0], uv[1 - ey][1], uv[1 - ez][2]);
}

// The covered case with all six planes. Other than AVX-512: specialised on the octant of plane
// 0's normal (bit 0: n_x >= 0, bit 1: n_y >= 0, bit 2: n_z >= 0): planes 0 and 1 lie in opposite
// octants, so their p-vertex loads are, register by register, known to be max_j or min_j, and
// M = max(max_j, -min_j) costs six operations (the same value as max |coordinate| for a valid
// box); planes 2-5 load their vertices. AVX-512: one instantiation (kOct unused); M by VRANGEPS
// and planes 2-5 from the pair's registers.
template <bool kInside, int kOct>
HWY_INLINE void CertAabbOctant(const CertPlane* planes, float t, float m_safe, std::size_t w_begin, std::size_t w_end,
                               std::size_t total_words, std::uint64_t* visible, std::uint64_t* inside,
                               std::uint8_t* unsafe) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using VU = hn::Vec<decltype(du)>;
  const std::size_t N = hn::Lanes(d);
  const PlaneVecs<decltype(d)> pv(d, planes, 6);
  const V(&nx)[6] = pv.nx, (&ny)[6] = pv.ny, (&nz)[6] = pv.nz, (&dout)[6] = pv.dout, (&din)[6] = pv.din;
  const V ntv = hn::Set(d, -t), msafe = hn::Set(d, m_safe);
#if CULLPROOF_CERT_AVX512
  // Bits 3 (k - 2) + j: plane k's p-vertex reads plane 1's array on axis j (side_plane).
  unsigned other = 0;
  for (int k = 2; k < 6; ++k) {
    const CertPlane &pk = planes[k], &p0 = planes[0];
    const unsigned e = (pk.px == p0.px ? 0u : 1u) | (pk.py == p0.py ? 0u : 2u) | (pk.pz == p0.pz ? 0u : 4u);
    other |= e << (3 * (k - 2));
  }
#endif
  for (std::size_t w = w_begin; w < w_end; ++w) {
    std::uint64_t vis = 0, ins = 0;
    VU mword = hn::Zero(du);
    prefetch_ahead(planes[0], w, total_words);
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      V m, uv[2][3], v[6], q[6];
      const V min01 = covering_pair<kOct>(d, du, pv, planes, i, m, uv);
#if CULLPROOF_CERT_AVX512
      // Planes 2-5 from the pair's registers: the six loads are all the loads (18 per vector
      // for the visible bits, 36 with the inside bits, otherwise; bench/cull/NOTES.md). Which array each plane reads is a run-time choice
      // (the octant of its normal), so it is a jump per plane to one of eight straight-line
      // evaluations; `sel` is made opaque per vector, or the compiler would unswitch the loop
      // into 8^4 copies. The indirect jumps always go the same way within a call.
      unsigned sel = other;
      asm volatile("" : "+r"(sel));
#pragma GCC unroll 4
      for (int k = 2; k < 6; ++k) {
        switch ((sel >> (3 * (k - 2))) & 7u) {
          case 0: side_plane<0, kInside>(pv, k, uv, v[k], q[k]); break;
          case 1: side_plane<1, kInside>(pv, k, uv, v[k], q[k]); break;
          case 2: side_plane<2, kInside>(pv, k, uv, v[k], q[k]); break;
          case 3: side_plane<3, kInside>(pv, k, uv, v[k], q[k]); break;
          case 4: side_plane<4, kInside>(pv, k, uv, v[k], q[k]); break;
          case 5: side_plane<5, kInside>(pv, k, uv, v[k], q[k]); break;
          case 6: side_plane<6, kInside>(pv, k, uv, v[k], q[k]); break;
          default: side_plane<7, kInside>(pv, k, uv, v[k], q[k]); break;
        }
      }
      if (kInside) {  // the n-vertex of plane 0 is plane 1's p-vertex, and the reverse
        q[0] = plane3(nx[0], ny[0], nz[0], din[0], uv[1][0], uv[1][1], uv[1][2]);
        q[1] = plane3(nx[1], ny[1], nz[1], din[1], uv[0][0], uv[0][1], uv[0][2]);
      }
#else
#pragma GCC unroll 4
      for (int k = 2; k < 6; ++k) {
        const CertPlane& s = planes[k];
        v[k] = plane3(nx[k], ny[k], nz[k], dout[k], hn::LoadU(d, s.px + i), hn::LoadU(d, s.py + i),
                      hn::LoadU(d, s.pz + i));
      }
      if (kInside)
        for (int k = 0; k < 6; ++k) {
          const CertPlane& s = planes[k];
          q[k] = plane3(nx[k], ny[k], nz[k], din[k], hn::LoadU(d, s.qx + i), hn::LoadU(d, s.qy + i),
                        hn::LoadU(d, s.qz + i));
        }
#endif
      // Trees, not chains: a short dependency path per vector keeps more vectors in flight while
      // the loads wait on L3 or memory.
      const V minp = hn::Min(hn::Min(min01, hn::Min(v[2], v[3])), hn::Min(v[4], v[5]));
      V minn = minp;
      if (kInside) minn = hn::Min(hn::Min(hn::Min(q[0], q[1]), hn::Min(q[2], q[3])), hn::Min(q[4], q[5]));
      mword = hn::Max(mword, hn::BitCast(du, m));  // a NaN sorts high
      const V ntm = hn::Mul(ntv, m);  // -T: fl(-t M) = -fl(t M)
      record<kInside>(d, minp, minn, ntm, j, vis, ins);
    }
    store_word<kInside>(d, w, w_begin, vis, ins, mword, msafe, visible, inside, unsafe);
  }
}

template <bool kInside>
HWY_INLINE void CertAabbOctantDispatch(const CertPlane* planes, float t, float m_safe, std::size_t w0, std::size_t w1,
                                       std::size_t tw, std::uint64_t* visible, std::uint64_t* inside,
                                       std::uint8_t* unsafe) {
#if CULLPROOF_CERT_AVX512
  return CertAabbOctant<kInside, 0>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);  // M needs no octant
#endif
  const int oct = (planes[0].nx >= 0.0f ? 1 : 0) | (planes[0].ny >= 0.0f ? 2 : 0) | (planes[0].nz >= 0.0f ? 4 : 0);
  switch (oct) {
    case 0: return CertAabbOctant<kInside, 0>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 1: return CertAabbOctant<kInside, 1>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 2: return CertAabbOctant<kInside, 2>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 3: return CertAabbOctant<kInside, 3>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 4: return CertAabbOctant<kInside, 4>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 5: return CertAabbOctant<kInside, 5>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    case 6: return CertAabbOctant<kInside, 6>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
    default: return CertAabbOctant<kInside, 7>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
  }
}

template <bool kInside>
HWY_INLINE void CertAabbDispatch(const CertPlane* planes, int count, bool covered, const Arrays& a, float t,
                                 float m_safe, std::size_t w0, std::size_t w1, std::size_t tw, std::uint64_t* visible,
                                 std::uint64_t* inside, std::uint8_t* unsafe) {
  if (count == 6 && covered)
    return CertAabbOctantDispatch<kInside>(planes, t, m_safe, w0, w1, tw, visible, inside, unsafe);
  if (count == 6)
    return CertAabbImpl<kInside, 6>(planes, count, a, t, m_safe, w0, w1, tw, visible, inside, unsafe);
  CertAabbImpl<kInside, 0>(planes, count, a, t, m_safe, w0, w1, tw, visible, inside, unsafe);
}

void CertAabbKernel(const CertPlane* planes, int count, bool covered, const Arrays& a, float t, float m_safe,
                    std::size_t w0, std::size_t w1, std::size_t total_words, std::uint64_t* visible,
                    std::uint64_t* inside, std::uint8_t* unsafe) {
  if (inside)
    return CertAabbDispatch<true>(planes, count, covered, a, t, m_safe, w0, w1, total_words, visible, inside, unsafe);
  CertAabbDispatch<false>(planes, count, covered, a, t, m_safe, w0, w1, total_words, visible, inside, unsafe);
}

// Spheres: M = fl(max |c_j| + r), T = fl(t M); visible iff min_k fl(r |n'_k| + s_k) >= -T with
// s_k = plane3(..., d_out, c); inside iff also min_k fl(-r |n'_k| + plane3(..., d_in, c)) >= T.
template <bool kInside, int kCount>
HWY_INLINE void CertSphereImpl(const CertPlane* planes, int count, const float* x, const float* y, const float* z,
                               const float* r, float t, float m_safe, std::size_t w_begin, std::size_t w_end,
                               std::uint64_t* visible, std::uint64_t* inside, std::uint8_t* unsafe) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using VU = hn::Vec<decltype(du)>;
  const std::size_t N = hn::Lanes(d);
  const int n = kCount > 0 ? kCount : count;
  const PlaneVecs<decltype(d)> pv(d, planes, n);
  const V(&nx)[6] = pv.nx, (&ny)[6] = pv.ny, (&nz)[6] = pv.nz, (&dout)[6] = pv.dout, (&din)[6] = pv.din,
      (&len)[6] = pv.len;
  const V ntv = hn::Set(d, -t), msafe = hn::Set(d, m_safe), inf = hn::Set(d, HUGE_VALF);
  for (std::size_t w = w_begin; w < w_end; ++w) {
    std::uint64_t vis = 0, ins = 0;
    VU mword = hn::Zero(du);
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      const V cx = hn::LoadU(d, x + i), cy = hn::LoadU(d, y + i), cz = hn::LoadU(d, z + i), rad = hn::LoadU(d, r + i);
      const V m = hn::Add(hn::Max(hn::Abs(cx), hn::Max(hn::Abs(cy), hn::Abs(cz))), rad);
      mword = hn::Max(mword, abs_bits(du, m));
      const V ntm = hn::Mul(ntv, m);
      V minp = inf, minn = inf;
#pragma GCC unroll 6
      for (int k = 0; k < n; ++k) {
        minp = hn::Min(minp, hn::MulAdd(rad, len[k], plane3(nx[k], ny[k], nz[k], dout[k], cx, cy, cz)));
        if (kInside) minn = hn::Min(minn, hn::NegMulAdd(rad, len[k], plane3(nx[k], ny[k], nz[k], din[k], cx, cy, cz)));
      }
      record<kInside>(d, minp, minn, ntm, j, vis, ins);
    }
    store_word<kInside>(d, w, w_begin, vis, ins, mword, msafe, visible, inside, unsafe);
  }
}

void CertSphereKernel(const CertPlane* planes, int count, const float* x, const float* y, const float* z,
                      const float* r, float t, float m_safe, std::size_t w0, std::size_t w1, std::uint64_t* visible,
                      std::uint64_t* inside, std::uint8_t* unsafe) {
  if (inside) {
    if (count == 6) return CertSphereImpl<true, 6>(planes, count, x, y, z, r, t, m_safe, w0, w1, visible, inside, unsafe);
    return CertSphereImpl<true, 0>(planes, count, x, y, z, r, t, m_safe, w0, w1, visible, inside, unsafe);
  }
  if (count == 6) return CertSphereImpl<false, 6>(planes, count, x, y, z, r, t, m_safe, w0, w1, visible, inside, unsafe);
  CertSphereImpl<false, 0>(planes, count, x, y, z, r, t, m_safe, w0, w1, visible, inside, unsafe);
}

// Boxes the plane test left undecided (bits of `todo`), proved to meet the frustum without being
// inside it: `meets` bit set iff some float point of the box, the seed point g clamped to it or
// its centre fl(fl(lo + hi) 0.5) (both exactly in the box), has fl(n'.x + d_in) >= fl(t M_x) on
// every plane (M_x bounding |x_i|: x strictly inside every plane), and some plane's n-vertex q has
// fl(n'.q + d_out) < -fl(t M) (q strictly outside it, so the box is not inside). These are the
// fast path's point tests (certified.cpp: the bound holds at any float point, fused or not), so
// every set bit is a proof; a box whose M exceeds m_safe (or holds a NaN) gets no bit.
void CertAabbMeetKernel(const CertPlane* planes, int count, const Arrays& a, const float* g, float t,
                        float m_safe, std::size_t w0, std::size_t w1, const std::uint64_t* todo,
                        std::uint64_t* meets) {
  const hn::ScalableTag<float> d;
  const hn::RebindToUnsigned<decltype(d)> du;
  using V = hn::Vec<decltype(d)>;
  using VU = hn::Vec<decltype(du)>;
  const std::size_t N = hn::Lanes(d);
  // The plane constants stay in memory, broadcast where used (an operand of the multiply-add):
  // held as 24 vectors besides the box, the points and the masks, they would not fit the
  // registers. The n-vertex reads min on axis j where n'_j >= 0.
  const float* q[6][3];
  for (int k = 0; k < count; ++k) {
    q[k][0] = planes[k].nx >= 0.0f ? a.min[0] : a.max[0];
    q[k][1] = planes[k].ny >= 0.0f ? a.min[1] : a.max[1];
    q[k][2] = planes[k].nz >= 0.0f ? a.min[2] : a.max[2];
  }
  const V tv = hn::Set(d, t), half = hn::Set(d, 0.5f), inf = hn::Set(d, HUGE_VALF);
  const V gv[3] = {hn::Set(d, g[0]), hn::Set(d, g[1]), hn::Set(d, g[2])};
  const V msafe = hn::Set(d, m_safe);
  for (std::size_t w = w0; w < w1; ++w) {
    std::uint64_t bits = 0;
    if (todo[w] != 0)
      for (std::size_t j = 0; j < 64; j += N) {
        const std::size_t i = w * 64 + j;
        V p[3], c[3];
        VU mb = hn::Zero(du), mp = hn::Zero(du);
        for (int k = 0; k < 3; ++k) {
          const V lo = hn::LoadU(d, a.min[k] + i), hi = hn::LoadU(d, a.max[k] + i);
          mb = hn::Max(mb, hn::Max(abs_bits(du, lo), abs_bits(du, hi)));
          p[k] = hn::Min(hn::Max(gv[k], lo), hi);
          mp = hn::Max(mp, abs_bits(du, p[k]));
          c[k] = hn::Mul(hn::Add(lo, hi), half);
        }
        V wp = inf, wc = inf, wq = inf;
        for (int k = 0; k < count; ++k) {
          const CertPlane& s = planes[k];
          const V nx = hn::Set(d, s.nx), ny = hn::Set(d, s.ny), nz = hn::Set(d, s.nz), din = hn::Set(d, s.d_in);
          wp = hn::Min(wp, plane3(nx, ny, nz, din, p[0], p[1], p[2]));
          wc = hn::Min(wc, plane3(nx, ny, nz, din, c[0], c[1], c[2]));
          wq = hn::Min(wq, plane3(nx, ny, nz, hn::Set(d, s.d_out), hn::LoadU(d, q[k][0] + i), hn::LoadU(d, q[k][1] + i),
                                  hn::LoadU(d, q[k][2] + i)));
        }
        const V tb = hn::Mul(tv, hn::BitCast(d, mb)), tp = hn::Mul(tv, hn::BitCast(d, mp));
        const auto inside_point = hn::Or(hn::Ge(wp, tp), hn::Ge(wc, tb));
        const auto proved = hn::And(hn::And(inside_point, hn::Lt(wq, hn::Neg(tb))),
                                    hn::Le(hn::BitCast(d, mb), msafe));  // false for NaN
        bits |= mask_bits(d, proved) << j;
      }
    meets[w] = bits & todo[w];
  }
}

// Spheres the plane test left undecided (bits of `todo`), proved to meet the frustum without
// being inside it: `meets` bit set iff some plane has fl(-r |n'| + fl(n'.c + d_out)) <
// -fl(t_sphere fl(M_c + r)) with the sphere planes' margins (c - r n/|n| strictly outside it, so
// the ball is not inside: the sphere test's own bound, which certified.cpp derives for r |n|
// taken with either sign), and a float point x of the ball is strictly inside every plane,
// fl(n'.x + d_in) >= fl(t_box M_x) with the box planes' margins (the point test). The points
// tried: the seed g (proved inside every plane once per call), the centre, and an estimate of the
// frustum's point nearest to it: the centre projected onto each plane it lies outside of in turn,
// twice round, then moved 1/512 of the way towards g (inwards), for the balls the seed does not
// prove; any float point, since it is certified, not the estimate. x lies in the
// ball when
//   fl(fl(s K) + E) < fl(r r),  s = fl(sum fl(x_i - c_i)^2),  K = 1 + 2^-20, E = 2^-140:
// a difference of floats is within u of the exact one (exact if it underflows), so the true
// squared distance D <= sum fl(x_i - c_i)^2 / (1 - u)^2; the three squares and two sums, in any
// order, fused or not, give s >= (1 - gamma_3) sum fl(x_i - c_i)^2 - 3 2^-150 (a square that
// underflows); fl(r r) <= r^2 (1 + u) + 2^-150; and the check's two roundings keep at least
// s K (1 - u)^2 + E / 2. So D < r^2 whenever (1 + u) / (K (1 - u)^4 (1 - gamma_3)) <= 1 and
// E / 2 covers the absolute terms (tests/certified/test_certified.cpp re-derives both). All hold
// fused or not; a sphere whose M passes m_safe (or holds a NaN) gets no bit.
void CertSphereMeetKernel(const CertPlane* box_planes, const CertPlane* sphere_planes, int count, const float* g,
                          const float* inv_norm2,
                          const float* x, const float* y, const float* z, const float* r, float t_box, float t_sphere,
                          float m_safe, std::size_t w0, std::size_t w1, const std::uint64_t* todo,
                          std::uint64_t* meets) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  // The plane constants stay in memory, broadcast where used (held as 72 vectors, they spilled).
  // fl(n'.x + d) of plane p at the point x (plane3's order), with d its d_in or d_out.
  auto value = [d](const CertPlane& p, float offset, const V (&pt)[3]) {
    return plane3(hn::Set(d, p.nx), hn::Set(d, p.ny), hn::Set(d, p.nz), hn::Set(d, offset), pt[0], pt[1], pt[2]);
  };
  const V tb = hn::Set(d, t_box), ts = hn::Set(d, t_sphere), msafe = hn::Set(d, m_safe), inf = hn::Set(d, HUGE_VALF);
  const V gv[3] = {hn::Set(d, g[0]), hn::Set(d, g[1]), hn::Set(d, g[2])};
  const V inward = hn::Set(d, 0x1p-9f), K = hn::Set(d, CertifiedMargins::kBallScale),
          E = hn::Set(d, CertifiedMargins::kBallAbsolute);
  // H vectors side by side: the projections are a chain of dependent operations, and H
  // independent chains keep the units busy (64 / (H N) whole steps per word).
  constexpr int H = 4;
  static_assert(64 % (H * (HWY_MAX_BYTES / sizeof(float))) == 0, "whole steps per 64-bit word");
  // Whether g is a point strictly inside every plane (the point test, as for x below).
  bool seed_in = false;
  {
    V wg = inf;
    for (int k = 0; k < count; ++k) wg = hn::Min(wg, value(box_planes[k], box_planes[k].d_in, gv));
    const V mg = hn::Max(hn::Abs(gv[0]), hn::Max(hn::Abs(gv[1]), hn::Abs(gv[2])));
    seed_in = hn::AllTrue(d, hn::And(hn::Ge(wg, hn::Mul(tb, mg)), hn::Le(mg, msafe)));
  }
  for (std::size_t w = w0; w < w1; ++w) {
    std::uint64_t bits = 0;
    if (todo[w] != 0)
      for (std::size_t j = 0; j < 64; j += H * N) {
        V c[H][3], rad[H], mc[H], wc[H], wq[H], p[H][3];
        for (int h = 0; h < H; ++h) {
          const std::size_t i = w * 64 + j + std::size_t(h) * N;
          c[h][0] = hn::LoadU(d, x + i), c[h][1] = hn::LoadU(d, y + i), c[h][2] = hn::LoadU(d, z + i);
          rad[h] = hn::LoadU(d, r + i);
          mc[h] = hn::Max(hn::Abs(c[h][0]), hn::Max(hn::Abs(c[h][1]), hn::Abs(c[h][2])));
          wc[h] = inf, wq[h] = inf;
          for (int k = 0; k < 3; ++k) p[h][k] = c[h][k];
        }
        for (int k = 0; k < count; ++k)
          for (int h = 0; h < H; ++h) {
            wc[h] = hn::Min(wc[h], value(box_planes[k], box_planes[k].d_in, c[h]));
            wq[h] = hn::Min(wq[h], hn::NegMulAdd(rad[h], hn::Set(d, sphere_planes[k].norm),
                                                 value(sphere_planes[k], sphere_planes[k].d_out, c[h])));
          }
        // The seed itself, where it is certified inside every plane: enough for the balls that
        // hold it (most of those that hold the frustum); the projections only for the others.
        std::uint64_t by_seed = 0;
        if (seed_in) {
          for (int h = 0; h < H; ++h) {
            V e[3];
            for (int k = 0; k < 3; ++k) e[k] = hn::Sub(gv[k], c[h][k]);
            const V sq = hn::MulAdd(e[2], e[2], hn::MulAdd(e[1], e[1], hn::Mul(e[0], e[0])));
            const V m = hn::Add(mc[h], rad[h]);
            const auto proved = hn::And(hn::And(hn::Lt(hn::MulAdd(sq, K, E), hn::Mul(rad[h], rad[h])),
                                                hn::Lt(wq[h], hn::Neg(hn::Mul(ts, m)))),
                                        hn::Le(m, msafe));
            by_seed |= mask_bits(d, proved) << (j + std::size_t(h) * N);
          }
          bits |= by_seed;
          const std::uint64_t step = detail::low_bits(H * N) << j;
          if ((todo[w] & step & ~by_seed) == 0) continue;
        }
        // The step towards g, and its magnitude.
        for (int round = 0; round < 2; ++round)
          for (int k = 0; k < count; ++k) {
            const CertPlane& pl = box_planes[k];
            for (int h = 0; h < H; ++h) {
              const V s = hn::Min(value(pl, pl.d_in, p[h]), hn::Zero(d));
              const V f = hn::Mul(s, hn::Set(d, inv_norm2[k]));  // <= 0: moves p onto the plane
              p[h][0] = hn::NegMulAdd(f, hn::Set(d, pl.nx), p[h][0]);
              p[h][1] = hn::NegMulAdd(f, hn::Set(d, pl.ny), p[h][1]);
              p[h][2] = hn::NegMulAdd(f, hn::Set(d, pl.nz), p[h][2]);
            }
          }
        for (int h = 0; h < H; ++h) {
          for (int k = 0; k < 3; ++k) p[h][k] = hn::MulAdd(inward, hn::Sub(gv[k], p[h][k]), p[h][k]);
          const V mp = hn::Max(hn::Abs(p[h][0]), hn::Max(hn::Abs(p[h][1]), hn::Abs(p[h][2])));
          V wp = inf;
          for (int k = 0; k < count; ++k) wp = hn::Min(wp, value(box_planes[k], box_planes[k].d_in, p[h]));
          V e[3];
          for (int k = 0; k < 3; ++k) e[k] = hn::Sub(p[h][k], c[h][k]);
          const V sq = hn::MulAdd(e[2], e[2], hn::MulAdd(e[1], e[1], hn::Mul(e[0], e[0])));
          const V m = hn::Add(mc[h], rad[h]);
          const auto in_ball = hn::Lt(hn::MulAdd(sq, K, E), hn::Mul(rad[h], rad[h]));
          const auto centre_in = hn::Ge(wc[h], hn::Mul(tb, mc[h]));
          const auto step_in = hn::And(in_ball, hn::And(hn::Ge(wp, hn::Mul(tb, mp)), hn::Le(mp, msafe)));
          const auto proved = hn::And(hn::And(hn::Or(centre_in, step_in), hn::Lt(wq[h], hn::Neg(hn::Mul(ts, m)))),
                                      hn::Le(m, msafe));  // false for NaN
          bits |= mask_bits(d, proved) << (j + std::size_t(h) * N);
        }
      }
    meets[w] = bits & todo[w];
  }
}

bool UsesFmaImpl() { return HWY_NATIVE_FMA != 0; }

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

HWY_EXPORT(CertAabbKernel);
HWY_EXPORT(CertSphereKernel);
HWY_EXPORT(CertAabbMeetKernel);
HWY_EXPORT(CertSphereMeetKernel);
HWY_EXPORT(UsesFmaImpl);

namespace {

using certified_batch_detail::CertPlane;

constexpr std::size_t kChunkWords = 256;  // 16,384 volumes per kernel call (flags on the stack)

// |x| as bits, as the kernels compute it (NaN above every number).
std::uint32_t abs_bits(float x) noexcept {
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u & 0x7fffffffu;
}

// Runs `kernel(w0, w1, visible, inside, flags)` over the full words in chunks, hands the lanes of
// flagged words whose M is too large (`unsafe_lane(i)`) to `scalar`, then runs the tail through
// the kernel on a padded copy (`pad(copy_begin, n)` returns a kernel bound to the copy).
template <class Kernel, class UnsafeLane, class Scalar>
void run_full_words(std::size_t full, std::uint64_t* visible, std::uint64_t* inside, Kernel&& kernel,
                    UnsafeLane&& unsafe_lane, Scalar&& scalar) {
  std::uint8_t flags[kChunkWords];
  for (std::size_t w0 = 0; w0 < full; w0 += kChunkWords) {
    const std::size_t w1 = std::min(full, w0 + kChunkWords);
    kernel(w0, w1, visible, inside, flags);
    for (std::size_t w = w0; w < w1; ++w) {
      if (!flags[w - w0]) continue;
      for (std::size_t j = 0; j < 64; ++j) {
        const std::size_t i = w * 64 + j;
        if (!unsafe_lane(i)) continue;
        const Visibility v = scalar(i);
        const std::uint64_t one = std::uint64_t{1} << j;
        visible[w] = (visible[w] & ~one) | (v != Visibility::outside ? one : 0);
        if (inside) inside[w] = (inside[w] & ~one) | (v == Visibility::inside ? one : 0);
      }
    }
  }
}

void clear(std::size_t words, std::uint64_t* visible, std::uint64_t* inside) {
  if (words == 0) return;  // the arrays may be null then
  std::memset(visible, 0, words * sizeof(std::uint64_t));
  if (inside) std::memset(inside, 0, words * sizeof(std::uint64_t));
}

// Puts two planes whose normals lie in opposite octants (every component's sign differs, with
// the kernel's >= 0 convention) first, if there are such planes: their p-vertices read all six
// box arrays. The verdict does not depend on the order of the planes (a minimum).
bool put_covering_pair_first(CertPlane* p, int count) {
  auto octant = [](const CertPlane& q) { return (q.nx >= 0.0f ? 1 : 0) | (q.ny >= 0.0f ? 2 : 0) | (q.nz >= 0.0f ? 4 : 0); };
  for (int i = 0; i < count; ++i)
    for (int j = i + 1; j < count; ++j)
      if ((octant(p[i]) ^ octant(p[j])) == 7) {
        std::swap(p[0], p[i]);  // j > i >= 0: p[j] is not moved by this swap
        std::swap(p[1], p[j]);
        return true;
      }
  return false;
}

// M of a box as the kernels compute it: the largest |coordinate|, as bits (NaN above all).
std::uint32_t magnitude_bits(const Aabb& b) noexcept {
  return std::max({abs_bits(b.min.x), abs_bits(b.min.y), abs_bits(b.min.z), abs_bits(b.max.x), abs_bits(b.max.y),
                   abs_bits(b.max.z)});
}

// The kernels' operations for one volume, with std::fma: the batch's verdicts where the SIMD
// target has no fused multiply-add (and the reference the tests compare the kernels with).
float plane3_fma(const CertifiedPlane& p, float d, float x, float y, float z) {
  return std::fma(p.nz, z, std::fma(p.ny, y, std::fma(p.nx, x, d)));
}

Visibility box_fma(const CertifiedFrustum& frustum, const Aabb& b) {
  const CertifiedFrustum::Data& f = frustum.data();
  const std::uint32_t mb = magnitude_bits(b);
  if (mb > abs_bits(f.m_safe)) return certified_pn_vertex(frustum, b);  // the kernels hand these over
  float m;
  std::memcpy(&m, &mb, sizeof m);
  const float t = f.t_box * m;
  bool outside = false, inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_box[static_cast<std::size_t>(i)];
    const glm::vec3 pv(p.nx >= 0 ? b.max.x : b.min.x, p.ny >= 0 ? b.max.y : b.min.y, p.nz >= 0 ? b.max.z : b.min.z);
    const glm::vec3 nv(p.nx >= 0 ? b.min.x : b.max.x, p.ny >= 0 ? b.min.y : b.max.y, p.nz >= 0 ? b.min.z : b.max.z);
    outside = outside || plane3_fma(p, p.d_out, pv.x, pv.y, pv.z) < -t;
    inside = inside && plane3_fma(p, p.d_in, nv.x, nv.y, nv.z) >= t;
  }
  return outside ? Visibility::outside : inside ? Visibility::inside : Visibility::intersecting;
}

Visibility sphere_fma(const CertifiedFrustum& frustum, const Sphere& s) {
  const CertifiedFrustum::Data& f = frustum.data();
  const glm::vec3& c = s.center;
  const float m = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z))) + s.radius;
  if (abs_bits(m) > abs_bits(f.m_safe)) return certified_sphere(frustum, s);
  const float t = f.t_sphere * m;
  bool outside = false, inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_sphere[static_cast<std::size_t>(i)];
    outside = outside || std::fma(s.radius, p.norm, plane3_fma(p, p.d_out, c.x, c.y, c.z)) < -t;
    inside = inside && std::fma(-s.radius, p.norm, plane3_fma(p, p.d_in, c.x, c.y, c.z)) >= t;
  }
  return outside ? Visibility::outside : inside ? Visibility::inside : Visibility::intersecting;
}

// Every volume through `one` (no SIMD FMA on this machine).
template <class One>
void one_by_one(std::size_t count, std::uint64_t* visible, std::uint64_t* inside, One&& one) {
  for (std::size_t w = 0; w < bitset_words(count); ++w) {
    std::uint64_t vis = 0, ins = 0;
    for (std::size_t j = 0; j < 64 && w * 64 + j < count; ++j) {
      const Visibility v = one(w * 64 + j);
      vis |= std::uint64_t{v != Visibility::outside} << j;
      ins |= std::uint64_t{v == Visibility::inside} << j;
    }
    visible[w] = vis;
    if (inside) inside[w] = ins;
  }
}

struct Padded {  // the tail's copy, padded with zeros (a point box / sphere at the origin)
  float v[6][64];
};

// Volumes [full * 64, full * 64 + rest) copied into pad: one word of volumes, the rest zero.
AabbSoa padded_tail(const AabbSoa& b, std::size_t full, std::size_t rest, Padded& pad) {
  const float* src[6] = {b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z};
  for (int k = 0; k < 6; ++k) std::memcpy(pad.v[k], src[k] + full * 64, rest * sizeof(float));
  return AabbSoa{pad.v[0], pad.v[1], pad.v[2], pad.v[3], pad.v[4], pad.v[5], 64};
}

SphereSoa padded_tail(const SphereSoa& s, std::size_t full, std::size_t rest, Padded& pad) {
  const float* src[4] = {s.x, s.y, s.z, s.radius};
  for (int k = 0; k < 4; ++k) std::memcpy(pad.v[k], src[k] + full * 64, rest * sizeof(float));
  return SphereSoa{pad.v[0], pad.v[1], pad.v[2], pad.v[3], 64};
}

void aabbs(const CertifiedFrustum& frustum, const AabbSoa& b, std::uint64_t* visible, std::uint64_t* inside) {
  const CertifiedFrustum::Data& f = frustum.data();
  if (f.empty) return clear(bitset_words(b.count), visible, inside);
  if (!certified_batch_uses_fma())
    return one_by_one(b.count, visible, inside, [&](std::size_t i) {
      return box_fma(frustum, Aabb{glm::vec3(b.min_x[i], b.min_y[i], b.min_z[i]), glm::vec3(b.max_x[i], b.max_y[i], b.max_z[i])});
    });
  // The full words of `s` (the boxes, or the padded tail): planes prepared once per array set.
  auto run = [&](const AabbSoa& s, std::size_t full, std::uint64_t* vis, std::uint64_t* ins) {
    CertPlane planes[6];
    for (int i = 0; i < f.active_count; ++i) {
      const CertifiedPlane& p = f.fast_box[static_cast<std::size_t>(i)];
      // Hoisted per plane: the p-vertex reads max where n' >= 0 (certified_pn_vertex's choice).
      planes[i] = CertPlane{p.nx, p.ny, p.nz, p.d_out, p.d_in, p.norm,
                            p.nx >= 0.0f ? s.max_x : s.min_x, p.ny >= 0.0f ? s.max_y : s.min_y,
                            p.nz >= 0.0f ? s.max_z : s.min_z, p.nx >= 0.0f ? s.min_x : s.max_x,
                            p.ny >= 0.0f ? s.min_y : s.max_y, p.nz >= 0.0f ? s.min_z : s.max_z};
    }
    const bool covered = put_covering_pair_first(planes, f.active_count);
    const certified_batch_detail::Arrays arrays{{s.min_x, s.min_y, s.min_z}, {s.max_x, s.max_y, s.max_z}};
    auto box = [&](std::size_t i) {
      return Aabb{glm::vec3(s.min_x[i], s.min_y[i], s.min_z[i]), glm::vec3(s.max_x[i], s.max_y[i], s.max_z[i])};
    };
    run_full_words(
        full, vis, ins,
        [&](std::size_t w0, std::size_t w1, std::uint64_t* v, std::uint64_t* n, std::uint8_t* fl) {
          HWY_DYNAMIC_DISPATCH(CertAabbKernel)(planes, f.active_count, covered, arrays, f.t_box, f.m_safe, w0, w1,
                                               s.count / 64, v, n, fl);
        },
        [&](std::size_t i) { return magnitude_bits(box(i)) > abs_bits(f.m_safe); },
        [&](std::size_t i) { return certified_pn_vertex(frustum, box(i)); });
  };
  const std::size_t full = b.count / 64, rest = b.count - full * 64;
  run(b, full, visible, inside);
  if (rest == 0) return;
  Padded pad{};
  const AabbSoa tail = padded_tail(b, full, rest, pad);
  std::uint64_t vis = 0, ins = 0;
  run(tail, 1, &vis, inside ? &ins : nullptr);
  const std::uint64_t keep = (std::uint64_t{1} << rest) - 1;
  visible[full] = vis & keep;
  if (inside) inside[full] = ins & keep;
}

void spheres(const CertifiedFrustum& frustum, const SphereSoa& s, std::uint64_t* visible, std::uint64_t* inside) {
  const CertifiedFrustum::Data& f = frustum.data();
  if (f.empty) return clear(bitset_words(s.count), visible, inside);
  if (!certified_batch_uses_fma())
    return one_by_one(s.count, visible, inside, [&](std::size_t i) {
      return sphere_fma(frustum, Sphere{glm::vec3(s.x[i], s.y[i], s.z[i]), s.radius[i]});
    });
  CertPlane planes[6];
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_sphere[static_cast<std::size_t>(i)];
    planes[i] = CertPlane{p.nx, p.ny, p.nz, p.d_out, p.d_in, p.norm, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  }
  auto run = [&](const SphereSoa& q, std::size_t full, std::uint64_t* vis, std::uint64_t* ins) {
    run_full_words(
        full, vis, ins,
        [&](std::size_t w0, std::size_t w1, std::uint64_t* v, std::uint64_t* n, std::uint8_t* fl) {
          HWY_DYNAMIC_DISPATCH(CertSphereKernel)(planes, f.active_count, q.x, q.y, q.z, q.radius, f.t_sphere, f.m_safe,
                                                 w0, w1, v, n, fl);
        },
        [&](std::size_t i) {
          const float m = std::max(std::abs(q.x[i]), std::max(std::abs(q.y[i]), std::abs(q.z[i]))) + q.radius[i];
          return abs_bits(m) > abs_bits(f.m_safe);
        },
        [&](std::size_t i) { return certified_sphere(frustum, Sphere{glm::vec3(q.x[i], q.y[i], q.z[i]), q.radius[i]}); });
  };
  const std::size_t full = s.count / 64, rest = s.count - full * 64;
  run(s, full, visible, inside);
  if (rest == 0) return;
  Padded pad{};
  const SphereSoa tail = padded_tail(s, full, rest, pad);
  std::uint64_t vis = 0, ins = 0;
  run(tail, 1, &vis, inside ? &ins : nullptr);
  const std::uint64_t keep = (std::uint64_t{1} << rest) - 1;
  visible[full] = vis & keep;
  if (inside) inside[full] = ins & keep;
}

}  // namespace

void certified_cull_aabbs_bitset(const CertifiedFrustum& f, const AabbSoa& b, std::uint64_t* visible,
                                 std::uint64_t* inside) {
  aabbs(f, b, visible, inside);
}

void certified_cull_spheres_bitset(const CertifiedFrustum& f, const SphereSoa& s, std::uint64_t* visible,
                                   std::uint64_t* inside) {
  spheres(f, s, visible, inside);
}

void certified_meets_aabbs_bitset(const CertifiedFrustum& frustum, const AabbSoa& b, const glm::vec3& seed,
                                  const std::uint64_t* todo, std::uint64_t* meets) {
  const CertifiedFrustum::Data& f = frustum.data();
  const std::size_t words = bitset_words(b.count);
  if (f.empty || f.active_count == 0) return clear(words, meets, nullptr);
  CertPlane planes[6];
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_box[static_cast<std::size_t>(i)];
    planes[i] = CertPlane{p.nx, p.ny, p.nz, p.d_out, p.d_in, p.norm, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  }
  const float g[3] = {seed.x, seed.y, seed.z};
  auto run = [&](const AabbSoa& s, std::size_t w0, std::size_t w1, const std::uint64_t* in, std::uint64_t* out) {
    const certified_batch_detail::Arrays arrays{{s.min_x, s.min_y, s.min_z}, {s.max_x, s.max_y, s.max_z}};
    HWY_DYNAMIC_DISPATCH(CertAabbMeetKernel)(planes, f.active_count, arrays, g, f.t_box, f.m_safe, w0, w1, in, out);
  };
  const std::size_t full = b.count / 64, rest = b.count - full * 64;
  run(b, 0, full, todo, meets);
  if (rest == 0) return;
  Padded pad{};
  const AabbSoa tail = padded_tail(b, full, rest, pad);
  const std::uint64_t in = todo[full] & ((std::uint64_t{1} << rest) - 1);
  run(tail, 0, 1, &in, meets + full);
}

void certified_meets_spheres_bitset(const CertifiedFrustum& frustum, const SphereSoa& s, const glm::vec3& seed,
                                    const std::uint64_t* todo, std::uint64_t* meets) {
  const CertifiedFrustum::Data& f = frustum.data();
  const std::size_t words = bitset_words(s.count);
  if (f.empty || f.active_count == 0) return clear(words, meets, nullptr);
  CertPlane box[6], ball[6];
  const float g[3] = {seed.x, seed.y, seed.z};
  float inv_norm2[6];  // 1 / |n'|^2 (an estimate: only where the projections go)
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_box[static_cast<std::size_t>(i)];
    const CertifiedPlane& q = f.fast_sphere[static_cast<std::size_t>(i)];
    box[i] = CertPlane{p.nx, p.ny, p.nz, p.d_out, p.d_in, p.norm, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
    ball[i] = CertPlane{q.nx, q.ny, q.nz, q.d_out, q.d_in, q.norm, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
    inv_norm2[i] = p.norm > 0.0f ? 1.0f / (p.norm * p.norm) : 0.0f;
  }
  auto run = [&](const SphereSoa& q, std::size_t w0, std::size_t w1, const std::uint64_t* in, std::uint64_t* out) {
    HWY_DYNAMIC_DISPATCH(CertSphereMeetKernel)(box, ball, f.active_count, g, inv_norm2, q.x, q.y, q.z, q.radius, f.t_box,
                                               f.t_sphere, f.m_safe, w0, w1, in, out);
  };
  const std::size_t full = s.count / 64, rest = s.count - full * 64;
  run(s, 0, full, todo, meets);
  if (rest == 0) return;
  Padded pad{};
  const SphereSoa tail = padded_tail(s, full, rest, pad);
  const std::uint64_t in = todo[full] & ((std::uint64_t{1} << rest) - 1);
  run(tail, 0, 1, &in, meets + full);
}

bool certified_batch_uses_fma() { return HWY_DYNAMIC_DISPATCH(UsesFmaImpl)(); }

}  // namespace cullproof
#endif  // HWY_ONCE

// Per-target helpers shared by the SIMD batch kernels (src/simd/batch_soa.cpp,
// src/simd/batch_certified.cpp, src/simd/batch_combinations.cpp). Highway's "-inl.h"
// idiom: the guard toggles with HWY_TARGET_TOGGLE so that foreach_target.h compiles the helpers
// once per SIMD target.
#if defined(CULLPROOF_BATCH_UTIL_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CULLPROOF_BATCH_UTIL_INL_H_
#undef CULLPROOF_BATCH_UTIL_INL_H_
#else
#define CULLPROOF_BATCH_UTIL_INL_H_
#endif

#include <hwy/highway.h>

#include <cstdint>
#include <cstring>

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {

/// The lanes of mask `m` as bits, lane 0 in bit 0 (at most 64 lanes).
template <class D, class M>
HWY_INLINE std::uint64_t mask_bits(D d, M m) {
  std::uint8_t buf[16] = {};
  hwy::HWY_NAMESPACE::StoreMaskBits(d, m, buf);
  std::uint64_t bits;
  std::memcpy(&bits, buf, sizeof(bits));
  const std::size_t n = hwy::HWY_NAMESPACE::Lanes(d);
  return n >= 64 ? bits : (bits & ((std::uint64_t{1} << n) - 1));
}

/// |x| of a float vector as bits (sign cleared): for non-negative floats the unsigned order of
/// the bits is the order of the values, and a NaN sorts above infinity, so a maximum over bits is
/// exact and NaN-proof.
template <class DU, class V>
HWY_INLINE hwy::HWY_NAMESPACE::Vec<DU> abs_bits(DU du, V v) {
  return hwy::HWY_NAMESPACE::And(hwy::HWY_NAMESPACE::BitCast(du, v), hwy::HWY_NAMESPACE::Set(du, 0x7fffffffu));
}

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard

// Built-in batch methods' array form (not installed): AoS volumes, as the method interface hands
// them over, transposed into SoA chunks for the SIMD bitset kernels, verdicts expanded from the
// visible / inside bits.
#pragma once

#include "cullproof/simd/cull_batch.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace cullproof::detail {

inline constexpr std::size_t kSoaChunk = 256;  // a multiple of 64: whole bitset words

// Branch-free (the bits of a mixed scene are unpredictable): outside 0, intersecting 1, inside 2.
inline Visibility bit_verdict(const std::uint64_t* visible, const std::uint64_t* inside, std::size_t j) noexcept {
  const unsigned v = unsigned(visible[j >> 6] >> (j & 63)) & 1u, i = unsigned(inside[j >> 6] >> (j & 63)) & v;
  return Visibility(v + i);
}

/// What a pass of an array form proves of a chunk of volumes: bit i of `outside`, `inside` or
/// `meets` where volume i is proved outside, inside or intersecting; a volume with none of them
/// is left to the next pass.
struct PassProofs {
  static constexpr std::size_t kCapacity = kSoaChunk;
  std::uint64_t outside[kCapacity / 64], inside[kCapacity / 64], meets[kCapacity / 64];
};

/// The k lowest bits set (all 64 for k >= 64): a bitset word's first k items.
constexpr std::uint64_t low_bits(std::size_t k) noexcept { return k >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << k) - 1; }

/// Bits [0, n) of the bitset `bits` set, the rest of its words clear.
inline void first_bits(std::size_t n, std::uint64_t* bits) noexcept {
  for (std::size_t w = 0; w < bitset_words(n); ++w) bits[w] = low_bits(n - w * 64);
}

/// boxes[0..m) transposed into `a` (m <= kSoaChunk): the SoA view of the chunk.
inline AabbSoa aabb_soa(const Aabb* boxes, std::size_t m, float (&a)[6][kSoaChunk]) noexcept {
  for (std::size_t j = 0; j < m; ++j) {
    const Aabb& b = boxes[j];
    a[0][j] = b.min.x, a[1][j] = b.min.y, a[2][j] = b.min.z;
    a[3][j] = b.max.x, a[4][j] = b.max.y, a[5][j] = b.max.z;
  }
  return AabbSoa{a[0], a[1], a[2], a[3], a[4], a[5], m};
}

/// spheres[0..m) transposed into `a` (m <= kSoaChunk): the SoA view of the chunk.
inline SphereSoa sphere_soa(const Sphere* spheres, std::size_t m, float (&a)[4][kSoaChunk]) noexcept {
  for (std::size_t j = 0; j < m; ++j) {
    const Sphere& s = spheres[j];
    a[0][j] = s.center.x, a[1][j] = s.center.y, a[2][j] = s.center.z, a[3][j] = s.radius;
  }
  return SphereSoa{a[0], a[1], a[2], a[3], m};
}

/// run(const AabbSoa&, std::uint64_t* visible, std::uint64_t* inside) over chunks of `boxes`.
template <class Run>
void aabb_batch(const Aabb* boxes, std::size_t n, Visibility* out, Run&& run) {
  alignas(64) float a[6][kSoaChunk];
  std::uint64_t vis[kSoaChunk / 64], ins[kSoaChunk / 64];
  for (std::size_t i0 = 0; i0 < n; i0 += kSoaChunk) {
    const std::size_t m = std::min(kSoaChunk, n - i0);
    run(aabb_soa(boxes + i0, m, a), vis, ins);
    for (std::size_t j = 0; j < m; ++j) out[i0 + j] = bit_verdict(vis, ins, j);
  }
}

/// run(const SphereSoa&, std::uint64_t* visible, std::uint64_t* inside) over chunks of `spheres`.
template <class Run>
void sphere_batch(const Sphere* spheres, std::size_t n, Visibility* out, Run&& run) {
  alignas(64) float a[4][kSoaChunk];
  std::uint64_t vis[kSoaChunk / 64], ins[kSoaChunk / 64];
  for (std::size_t i0 = 0; i0 < n; i0 += kSoaChunk) {
    const std::size_t m = std::min(kSoaChunk, n - i0);
    run(sphere_soa(spheres + i0, m, a), vis, ins);
    for (std::size_t j = 0; j < m; ++j) out[i0 + j] = bit_verdict(vis, ins, j);
  }
}

/// One volume through an array form, batch(const V*, std::size_t, Visibility*): 64 copies (a full
/// bitset word), so that the vector code, not the scalar tail, is what the harness checks.
template <class V, class Batch>
Visibility as_word(const V& v, Batch&& batch) {
  V copies[64];
  std::fill(copies, copies + 64, v);
  Visibility out[64];
  batch(static_cast<const V*>(copies), std::size_t(64), out);
  return out[0];
}

template <class Run>
Visibility aabb_as_word(const Aabb& b, Run&& run) {
  return as_word(b, [&](const Aabb* c, std::size_t n, Visibility* v) { aabb_batch(c, n, v, run); });
}

template <class Run>
Visibility sphere_as_word(const Sphere& s, Run&& run) {
  return as_word(s, [&](const Sphere* c, std::size_t n, Visibility* v) { sphere_batch(c, n, v, run); });
}

}  // namespace cullproof::detail

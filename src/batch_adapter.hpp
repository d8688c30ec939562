// Built-in batch methods' array form (not installed): AoS volumes, as the method interface hands
// them over, transposed into SoA chunks for the SIMD bitset kernels, verdicts expanded from the
// visible / inside bits.
#pragma once

#include "cullproof/cull_batch.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace cullproof::detail {

inline constexpr std::size_t kSoaChunk = 256;  // a multiple of 64: whole bitset words

inline Visibility bit_verdict(const std::uint64_t* visible, const std::uint64_t* inside, std::size_t j) noexcept {
  const std::uint64_t bit = std::uint64_t(1) << (j & 63);
  if ((visible[j >> 6] & bit) == 0) return Visibility::outside;
  return (inside[j >> 6] & bit) ? Visibility::inside : Visibility::intersecting;
}

/// run(const AabbSoa&, std::uint64_t* visible, std::uint64_t* inside) over chunks of `boxes`.
template <class Run>
void aabb_batch(const Aabb* boxes, std::size_t n, Visibility* out, Run&& run) {
  alignas(64) float a[6][kSoaChunk];
  std::uint64_t vis[kSoaChunk / 64], ins[kSoaChunk / 64];
  for (std::size_t i0 = 0; i0 < n; i0 += kSoaChunk) {
    const std::size_t m = std::min(kSoaChunk, n - i0);
    for (std::size_t j = 0; j < m; ++j) {
      const Aabb& b = boxes[i0 + j];
      a[0][j] = b.min.x, a[1][j] = b.min.y, a[2][j] = b.min.z;
      a[3][j] = b.max.x, a[4][j] = b.max.y, a[5][j] = b.max.z;
    }
    run(AabbSoa{a[0], a[1], a[2], a[3], a[4], a[5], m}, vis, ins);
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
    for (std::size_t j = 0; j < m; ++j) {
      const Sphere& s = spheres[i0 + j];
      a[0][j] = s.center.x, a[1][j] = s.center.y, a[2][j] = s.center.z, a[3][j] = s.radius;
    }
    run(SphereSoa{a[0], a[1], a[2], a[3], m}, vis, ins);
    for (std::size_t j = 0; j < m; ++j) out[i0 + j] = bit_verdict(vis, ins, j);
  }
}

/// One volume through a batch kernel: 64 copies (a full bitset word), so that the vector code,
/// not the scalar tail, is what the harness checks.
template <class Run>
Visibility aabb_as_word(const Aabb& b, Run&& run) {
  Aabb copies[64];
  std::fill(copies, copies + 64, b);
  Visibility v[64];
  aabb_batch(copies, 64, v, run);
  return v[0];
}

template <class Run>
Visibility sphere_as_word(const Sphere& s, Run&& run) {
  Sphere copies[64];
  std::fill(copies, copies + 64, s);
  Visibility v[64];
  sphere_batch(copies, 64, v, run);
  return v[0];
}

}  // namespace cullproof::detail

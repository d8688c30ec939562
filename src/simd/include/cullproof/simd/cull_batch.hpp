// cullproof SIMD batch culling (library cullproof::simd, Highway with runtime dispatch).
//
// Structure-of-arrays input; output as a bitset (bit i of word i/64, LSB first) or as an index
// list. The verdicts are bit-for-bit those of the scalar tests on every input: AABBs as
// pn_vertex_index, which is pn_vertex (Assarsson & Möller 2000 §3.1) wherever the float plane
// values are finite, spheres as sphere_plane_test_wide, which is sphere_plane_test (Lighthouse3D)
// there — same operations in the same order, no FMA (-ffp-contract=off, no MulAdd in a value); a
// volume whose plane value overflows float goes through the scalar test, which takes that value
// in double (plane_value).
#pragma once

#include "cullproof/core/cull.hpp"

#include <cstddef>
#include <cstdint>

namespace cullproof {

/// N boxes as six float arrays. Box i is {min_x[i].., max_x[i]..}. Any alignment is accepted;
/// 64-byte aligned arrays are faster (no SIMD load straddles two cache lines; a std::vector of a
/// few MB starts 16 bytes off).
/// Values must be finite (as docs/semantics.md requires).
struct AabbSoa {
  const float* min_x = nullptr;
  const float* min_y = nullptr;
  const float* min_z = nullptr;
  const float* max_x = nullptr;
  const float* max_y = nullptr;
  const float* max_z = nullptr;
  std::size_t count = 0;
};

/// N spheres as four float arrays.
struct SphereSoa {
  const float* x = nullptr;
  const float* y = nullptr;
  const float* z = nullptr;
  const float* radius = nullptr;
  std::size_t count = 0;
};

/// Number of 64-bit words of a bitset over n items.
constexpr std::size_t bitset_words(std::size_t n) noexcept { return (n + 63) / 64; }

/// visible bit i set iff pn_vertex_index(frustum, box i) != outside. `visible` holds
/// bitset_words(count) words; bits past count are zero.
void cull_aabbs_bitset(const Frustum& frustum, const AabbSoa& boxes, std::uint64_t* visible);
/// As cull_aabbs_bitset, and inside bit i set iff pn_vertex_index(frustum, box i) == inside.
void classify_aabbs_bitset(const Frustum& frustum, const AabbSoa& boxes, std::uint64_t* visible,
                           std::uint64_t* inside);
/// Writes the indices of the visible boxes (ascending) to `out` (room for count) and returns
/// how many there are.
std::size_t cull_aabbs_indices(const Frustum& frustum, const AabbSoa& boxes, std::uint32_t* out);

/// visible bit i set iff sphere_plane_test_wide(normalized_frustum, sphere i) != outside.
/// The frustum must be normalised (Frustum::normalized()).
void cull_spheres_bitset(const Frustum& normalized_frustum, const SphereSoa& spheres,
                         std::uint64_t* visible);
/// As cull_spheres_bitset, and inside bit i set iff sphere_plane_test_wide(...) == inside.
void classify_spheres_bitset(const Frustum& normalized_frustum, const SphereSoa& spheres,
                             std::uint64_t* visible, std::uint64_t* inside);
/// Indices of the visible spheres; returns the count.
std::size_t cull_spheres_indices(const Frustum& normalized_frustum, const SphereSoa& spheres,
                                 std::uint32_t* out);

/// Scalar reference: the loop `pn_vertex(frustum, box i) != outside` over the SoA, same output
/// as cull_aabbs_bitset (the baseline of the >= 5x target).
void cull_aabbs_bitset_scalar(const Frustum& frustum, const AabbSoa& boxes, std::uint64_t* visible);

/// Name of the SIMD target the runtime dispatch selects on this machine (e.g. "AVX3", "AVX2").
const char* batch_simd_target();

}  // namespace cullproof

// Certified-exact culling of arrays (cullproof/exact_certified_batch.hpp): the SIMD certified
// batch first (src/certified/batch_certified.cpp: outside and inside proved with float margins,
// Highway runtime dispatch); for AABBs it leaves undecided, a second SIMD pass that proves them
// intersecting by a witness point (the frame's interior point clamped to the box, or the box's
// centre) and a vertex outside some plane; then the cascade (src/certified/exact_certified.cpp)
// for every volume still undecided. Every stage is certified, so the verdicts are the exact truth.
#include "cullproof/exact_certified_batch.hpp"

#include "batch_adapter.hpp"
#include "cullproof/certified_batch.hpp"

#include <algorithm>
#include <cstdint>

namespace cullproof {

namespace {

constexpr std::size_t kChunk = detail::kSoaChunk;

// A chunk's verdicts: outside and inside where the certified batch proved them, intersecting
// where it or `proved` (may be null) did, the cascade (rest(j)) for the others.
template <class Rest>
void settle(const std::uint64_t* vis, const std::uint64_t* ins, const std::uint64_t* proved, std::size_t m,
            Visibility* verdicts, Rest&& rest) {
  for (std::size_t j = 0; j < m; ++j) verdicts[j] = detail::bit_verdict(vis, ins, j);
  for (std::size_t w = 0; w * 64 < m; ++w)
    for (std::uint64_t r = vis[w] & ~ins[w] & ~(proved ? proved[w] : 0); r != 0; r &= r - 1) {
      const std::size_t j = w * 64 + std::size_t(__builtin_ctzll(r));
      if (j < m) verdicts[j] = rest(j);
    }
}

}  // namespace

void exact_certified_aabbs(const ExactCertifiedFrustum& f, const AabbSoa& boxes, Visibility* verdicts) {
  std::uint64_t vis[kChunk / 64], ins[kChunk / 64], todo[kChunk / 64], meets[kChunk / 64];
  // The seed of the witness points: the frame's interior point, rounded to float (any point is
  // sound; the clamped point is certified, not the seed).
  const glm::vec3 seed = f.has_interior ? glm::vec3(float(f.interior[0]), float(f.interior[1]), float(f.interior[2]))
                                        : glm::vec3(0.0f);
  for (std::size_t i0 = 0; i0 < boxes.count; i0 += kChunk) {
    const std::size_t m = std::min(kChunk, boxes.count - i0);
    const AabbSoa part{boxes.min_x + i0, boxes.min_y + i0, boxes.min_z + i0,
                       boxes.max_x + i0, boxes.max_y + i0, boxes.max_z + i0, m};
    certified_cull_aabbs_bitset(f.certified, part, vis, ins);
    const std::size_t words = bitset_words(m);
    for (std::size_t w = 0; w < words; ++w) todo[w] = vis[w] & ~ins[w];
    certified_meets_aabbs_bitset(f.certified, part, seed, todo, meets);
    settle(vis, ins, meets, m, verdicts + i0, [&](std::size_t j) {
      return exact_certified_aabb(f, Aabb{{part.min_x[j], part.min_y[j], part.min_z[j]}, {part.max_x[j], part.max_y[j], part.max_z[j]}});
    });
  }
}

void exact_certified_spheres(const ExactCertifiedFrustum& f, const SphereSoa& spheres, Visibility* verdicts) {
  std::uint64_t vis[kChunk / 64], ins[kChunk / 64], todo[kChunk / 64], meets[kChunk / 64];
  for (std::size_t i0 = 0; i0 < spheres.count; i0 += kChunk) {
    const std::size_t m = std::min(kChunk, spheres.count - i0);
    const SphereSoa part{spheres.x + i0, spheres.y + i0, spheres.z + i0, spheres.radius + i0, m};
    certified_cull_spheres_bitset(f.certified, part, vis, ins);
    const std::size_t words = bitset_words(m);
    for (std::size_t w = 0; w < words; ++w) todo[w] = vis[w] & ~ins[w];
    certified_meets_spheres_bitset(f.certified, part, todo, meets);
    settle(vis, ins, meets, m, verdicts + i0, [&](std::size_t j) {
      return exact_certified_sphere(f, Sphere{{part.x[j], part.y[j], part.z[j]}, part.radius[j]});
    });
  }
}

void exact_certified_aabbs(const ExactCertifiedFrustum& f, const Aabb* boxes, std::size_t n, Visibility* verdicts) {
  alignas(64) float a[6][kChunk];
  for (std::size_t i0 = 0; i0 < n; i0 += kChunk)
    exact_certified_aabbs(f, detail::aabb_soa(boxes + i0, std::min(kChunk, n - i0), a), verdicts + i0);
}

void exact_certified_spheres(const ExactCertifiedFrustum& f, const Sphere* spheres, std::size_t n, Visibility* verdicts) {
  alignas(64) float a[4][kChunk];
  for (std::size_t i0 = 0; i0 < n; i0 += kChunk)
    exact_certified_spheres(f, detail::sphere_soa(spheres + i0, std::min(kChunk, n - i0), a), verdicts + i0);
}

}  // namespace cullproof

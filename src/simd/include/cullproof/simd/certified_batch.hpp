// Certified conservative SIMD batch culling: structure-of-arrays AABBs and spheres,
// Highway runtime dispatch (library cullproof::simd). The certified fast path of
// certified_pn_vertex / certified_sphere, evaluated with fused multiply-adds (the certified bound
// allows it; the same verdicts on every machine): the verdicts are those of the scalar functions except
// within the rounding margin, where either may say `intersecting`; both are certified. Volumes
// large enough to risk overflow are handed to the scalar functions.
#pragma once

#include "cullproof/core/certified.hpp"
#include "cullproof/simd/cull_batch.hpp"

#include <cstdint>

namespace cullproof {

/// visible bit i clear iff box i is certainly outside; `inside` (may be null) bit i set iff it is
/// certainly inside. Each array holds bitset_words(count) words; bits past count are zero.
/// Boxes must be valid (min <= max).
void certified_cull_aabbs_bitset(const CertifiedFrustum& f, const AabbSoa& boxes, std::uint64_t* visible,
                                 std::uint64_t* inside = nullptr);
/// The same for spheres (radius >= 0).
void certified_cull_spheres_bitset(const CertifiedFrustum& f, const SphereSoa& spheres, std::uint64_t* visible,
                                   std::uint64_t* inside = nullptr);

/// Of the boxes whose bit is set in `todo` (bitset_words(count) words), sets bit i of `meets`
/// where box i is certainly intersecting: a float point of it (`seed` clamped to the box, or its
/// centre) is certified strictly inside every plane and a vertex strictly outside one, by the
/// fast path's point tests; every other bit is zero. For boxes the plane test left undecided
/// (visible and not inside): a set bit is a proof, a clear one decides nothing. Any seed is
/// sound; one inside the frustum decides the most.
void certified_meets_aabbs_bitset(const CertifiedFrustum& f, const AabbSoa& boxes, const glm::vec3& seed,
                                  const std::uint64_t* todo, std::uint64_t* meets);

/// Of the spheres whose bit is set in `todo`, sets bit i of `meets` where sphere i is certainly
/// intersecting: a float point of it (its centre, or a step from the centre towards `seed`,
/// certified inside the ball) is certified strictly inside every plane by the point test, and
/// some point of it strictly outside one by the sphere test's bound; every other bit is zero. As
/// for boxes, a set bit is a proof and a clear one decides nothing; any seed is sound.
void certified_meets_spheres_bitset(const CertifiedFrustum& f, const SphereSoa& spheres, const glm::vec3& seed,
                                    const std::uint64_t* todo, std::uint64_t* meets);

/// Whether the dispatched SIMD target has fused multiply-adds. Without them the batches run
/// the same operations volume by volume with std::fma (same verdicts, slower).
bool certified_batch_uses_fma();

}  // namespace cullproof

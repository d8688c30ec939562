// Certified conservative SIMD batch culling (issue 7): structure-of-arrays AABBs and spheres,
// Highway runtime dispatch (library cullproof::simd). Verdicts are bit-for-bit those of
// certified_pn_vertex / certified_sphere on every input (same operations in the same order, no
// FMA); volumes large enough to risk overflow are handed to the scalar functions.
#pragma once

#include "cullproof/certified.hpp"
#include "cullproof/cull_batch.hpp"

#include <cstdint>

namespace cullproof {

/// visible bit i set iff certified_pn_vertex(f, box i) != outside; `inside` (may be null) bit i
/// set iff it is inside. Each array holds bitset_words(count) words; bits past count are zero.
void certified_cull_aabbs_bitset(const CertifiedFrustum& f, const AabbSoa& boxes, std::uint64_t* visible,
                                 std::uint64_t* inside = nullptr);
/// visible bit i set iff certified_sphere(f, sphere i) != outside; `inside` likewise.
void certified_cull_spheres_bitset(const CertifiedFrustum& f, const SphereSoa& spheres, std::uint64_t* visible,
                                   std::uint64_t* inside = nullptr);

}  // namespace cullproof

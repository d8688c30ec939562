// Certified-exact culling of arrays (library cullproof::simd): the SIMD certified batch
// (cullproof/simd/certified_batch.hpp) decides what lies clearly outside or clearly inside, with its
// float margins, several volumes per instruction; SIMD passes prove what they can of the rest
// (witness points; for boxes, the planes and the frame's combinations in float; for balls, the
// cascade's own stage 1 and stage 2 proofs in double, a ball per lane); every other
// volume goes through the scalar cascade of cullproof/simd/exact_certified.hpp. The verdicts are those
// of the scalar functions: the exact truth.
#pragma once

#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"

#include <cstddef>

namespace cullproof {

/// verdicts[i] for box i of the structure of arrays (valid boxes).
void exact_certified_aabbs(const ExactCertifiedFrustum& f, const AabbSoa& boxes, Visibility* verdicts);
/// verdicts[i] for sphere i (radius >= 0).
void exact_certified_spheres(const ExactCertifiedFrustum& f, const SphereSoa& spheres, Visibility* verdicts);
/// The same for arrays of structures (transposed in chunks of 256).
void exact_certified_aabbs(const ExactCertifiedFrustum& f, const Aabb* boxes, std::size_t n, Visibility* verdicts);
void exact_certified_spheres(const ExactCertifiedFrustum& f, const Sphere* spheres, std::size_t n,
                             Visibility* verdicts);

}  // namespace cullproof

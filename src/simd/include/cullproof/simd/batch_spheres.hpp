// The sphere array form's double pass (batch_spheres.cpp; not installed).
#pragma once

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"

#include <cstddef>
#include <cstdint>

namespace cullproof {

/// The double pass over the balls of `balls` (at most detail::PassProofs::kCapacity) whose bit is set in `todo`:
/// the scalar cascade's stage 1 and its proofs of stage 2 (anchors, witness points, Farkas
/// multipliers from the projections onto the planes of J), several balls per instruction, the
/// balls sorted by J first so that a vector's balls share their planes. The arrays of `balls` are
/// read in whole vectors: readable up to balls.count rounded up to kBallReadable.
inline constexpr std::size_t kBallReadable = 16;
void exact_ball_pass(const ExactCertifiedFrustum& f, const SphereSoa& balls, const std::uint64_t* todo,
                     detail::PassProofs& r);

}  // namespace cullproof

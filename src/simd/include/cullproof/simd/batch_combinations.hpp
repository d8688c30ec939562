// The AABB array form's float pass (batch_combinations.cpp; not installed).
#pragma once

#include "cullproof/simd/batch_adapter.hpp"
#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>

namespace cullproof {

/// What the first float pass gives for a chunk of boxes: J[i] bit j set where plane j is not
/// proved to hold box i; bit i of `outside`, `inside` or `meets` where box i is proved outside,
/// inside or intersecting, of `open` where none is, and for an open box, of `meet_ok` where it
/// meets the frustum if every combination within J is proved positive on it.
struct FloatFirstResult {
  static constexpr std::size_t kCapacity = 256;
  std::uint32_t J[kCapacity];
  std::uint64_t outside[kCapacity / 64], inside[kCapacity / 64], meets[kCapacity / 64], open[kCapacity / 64],
      meet_ok[kCapacity / 64];
};

/// The first float pass (f.float_planes > 0) over at most kCapacity boxes: the planes, and for
/// boxes they leave, the witness points (`seed` clamped to the box, and its centre), except for
/// boxes whose bit is set in `tried` (may be null): their witness points failed before. The
/// arrays of `part` are read in whole vectors: readable up to part.count rounded up to
/// kReadable (what lies past part.count decides nothing).
inline constexpr std::size_t kReadable = 16;
void exact_float_first(const ExactCertifiedFrustum& f, const AabbSoa& part, const glm::vec3& seed,
                       FloatFirstResult& r, const std::uint64_t* tried = nullptr);

/// What the float pass on the open boxes gives: the `count` boxes the first pass left open, the
/// p-th being box order[p] (sorted by J); bit p of `outside` where a combination proves it
/// outside, of `meets` where `meet_ok` has it and every combination within J is proved positive.
struct FloatOpenResult {
  std::size_t count = 0;
  std::uint32_t order[FloatFirstResult::kCapacity];
  std::uint64_t outside[FloatFirstResult::kCapacity / 64], meets[FloatFirstResult::kCapacity / 64];
};

/// The float pass on the boxes the first pass left open (`r`, as it gave them for `boxes`), on the
/// combinations within their J. The open boxes are sorted by J first and copied side by side, so
/// that a vector's boxes mostly share J.
void exact_float_open(const ExactCertifiedFrustum& f, const AabbSoa& boxes, const FloatFirstResult& r,
                      FloatOpenResult& o);

/// The scalar cascade's stage 1 (exact_certified.cpp, exact_certified_aabb: the planes in double
/// with the threshold T = t_box m) on the boxes of `boxes` (at most detail::PassProofs::kCapacity)
/// whose bit is set in `todo`, a box per lane, and what it decides alone (a box none of them
/// proves is left to the scalar cascade): a plane proves the box outside; no plane is
/// left (J empty): inside; a plane crossed and the p-vertex shared by J proved inside every plane
/// of J: intersecting. Boxes with a coordinate that is not finite are left to the cascade.
void exact_box_planes(const ExactCertifiedFrustum& f, const AabbSoa& boxes, const std::uint64_t* todo,
                      detail::PassProofs& r);

}  // namespace cullproof

// Naive 8-corner per-plane counting test for AABBs.
//
// Source: Lighthouse3D "View Frustum Culling Tutorial", section "Geometric Approach - Testing
// Boxes", FrustumG::boxInFrustum.
// Claim: conservative. A box is rejected only when all eight corners are on the wrong side of
// one plane (then the whole box is: a half-space is convex). A box outside the frustum but
// not outside any single plane is reported intersecting (the text's "orange box").
// Touching: a corner with distance exactly 0 counts as `in` (the text tests `< 0` for out), so
// a box touching a plane from outside has an `in` corner and is intersecting; a box touching
// from inside has no `out` corner and is inside. Both agree with docs/semantics.md.
// Corner k: bit 0 selects max.x, bit 1 max.y, bit 2 max.z. The early exit of the inner loop
// (stop once both counts are non-zero) is kept as published.
#include "cullproof/core/cull.hpp"

namespace cullproof {

namespace {
glm::vec3 corner(const Aabb& b, int k) noexcept {
  return glm::vec3((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                   (k & 4) ? b.max.z : b.min.z);
}
}  // namespace

Visibility aabb_eight_corner(const Frustum& frustum, const Aabb& box) noexcept {
  Visibility result = Visibility::inside;
  for (int i = 0; i < kPlaneCount; ++i) {
    int out = 0, in = 0;
    for (int k = 0; k < 8 && (in == 0 || out == 0); ++k) {
      if (frustum[i].eval(corner(box, k)) < 0.0f)
        ++out;
      else
        ++in;
    }
    if (in == 0) return Visibility::outside;
    if (out != 0) result = Visibility::intersecting;
  }
  return result;
}

}  // namespace cullproof

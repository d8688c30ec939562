// Point plane test.
//
// Source: Lighthouse3D "View Frustum Culling Tutorial", section "Geometric Approach - Testing
// Points and Spheres", FrustumG::pointInFrustum.
// Claim: exact (a point is inside iff dot(n, p) + d >= 0 for all six planes; the only float
// error is the rounding of the plane evaluation).
// Touching: `distance < 0` rejects, so a point on a plane is inside (docs/semantics.md: closed sets).
// The text and docs/semantics.md agree; no correction needed.
#include "cullproof/core/cull.hpp"

namespace cullproof {

Visibility point_plane_test(const Frustum& frustum, const Point& p) noexcept {
  for (int i = 0; i < kPlaneCount; ++i)
    if (frustum[i].eval(p) < 0.0f) return Visibility::outside;
  return Visibility::inside;
}

}  // namespace cullproof

// Sphere plane test on normalised planes.
//
// Source: Lighthouse3D "View Frustum Culling Tutorial", section "Geometric Approach - Testing
// Points and Spheres", FrustumG::sphereInFrustum; A&M 2000 §5 mention the
// same test.
// Claim: conservative. Outside is only returned when the sphere is outside one plane, inside
// when it is inside every plane; near an edge or corner of the frustum a sphere outside all of
// it but not outside any single plane is reported intersecting (a false intersect).
// Touching: `distance < -radius` rejects, so a sphere touching a plane from outside
// (distance == -radius) is intersecting; `distance < radius` makes one touching from inside
// (distance == radius) inside. Both agree with docs/semantics.md.
// Addition to the text: a degenerate plane (n == 0, the far plane of an infinite projection)
// cannot be normalised; it is skipped when d >= 0 (all space) and rejects when d < 0 (nothing).
// The text would divide by a zero length.
// sphere_plane_test_wide (own, the scalar form of the SIMD batch) takes a value that overflows
// float again in double (plane_value): a centre near FLT_MAX makes n.c + d +inf, -inf or NaN.
#include "cullproof/core/cull.hpp"

namespace cullproof {

Visibility sphere_plane_test(const Frustum& f, const Sphere& s) noexcept {
  Visibility result = Visibility::inside;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& p = f[i];
    if (p.is_degenerate()) {
      if (p.d < 0.0f) return Visibility::outside;
      continue;
    }
    const float distance = p.eval(s.center);
    if (distance < -s.radius) return Visibility::outside;
    if (distance < s.radius) result = Visibility::intersecting;
  }
  return result;
}

Visibility sphere_plane_test_wide(const Frustum& f, const Sphere& s) noexcept {
  Visibility result = Visibility::inside;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& p = f[i];
    if (p.is_degenerate()) {
      if (p.d < 0.0f) return Visibility::outside;
      continue;
    }
    const double distance = plane_value(p, s.center);
    if (distance < -double(s.radius)) return Visibility::outside;
    if (distance < double(s.radius)) result = Visibility::intersecting;
  }
  return result;
}

}  // namespace cullproof

// Pre-test stages: the box's bounding sphere, the frustum's bounding sphere and the frustum's
// AABB, each returning a sure verdict or "unknown" so that stages compose in front of a main
// test.
//
// Source: Lighthouse3D "View Frustum Culling Tutorial", section "Some Notes and Possible
// Optimizations": "Spheres as Bounding Volumes for Boxes" (cases A, B, C), "Spheres
// everywhere", "Axis-Aligned Boxes everywhere". (The tutorial's heading "Further Optimization" is the
// coherence section, not this one.)
// Claims (as stages in front of pn_vertex): conservative.
//  - box_sphere_stage: the sphere contains the box (radius from the float centre to the
//    farthest corner, computed in float and enlarged by a derived relative bound), so sphere
//    outside => box outside and
//    sphere inside => box inside; sphere intersecting falls through ("case C", "test the box
//    itself"). A touching sphere is intersecting (sphere_plane_test), so it falls through.
//  - frustum_sphere_stage: outside when the two spheres are disjoint, `dist > r1 + r2`
//    (strict: touching spheres fall through). The text's sphere-sphere test.
//  - frustum_aabb_stage: the text's code with strict `>`/`<` for OUTSIDE; its INSIDE (object
//    box within the frustum's box) and INTERSECT both mean "further testing is required", so
//    they fall through. Unbounded frusta (infinite far plane) have no bounds: fall through.
#include "cullproof/core/cull.hpp"

#include <cmath>
#include <limits>

namespace cullproof {

namespace {

// The box's bounding sphere in float, radius rounded up: each of the subtractions, squares,
// sums and the square root has relative error <= 2^-24, together < 8 * 2^-24 = 2^-21, so the
// factor (1 + 2^-20) (itself rounded down by at most 2^-24) makes the radius at least the exact
// distance from the float centre to the farthest corner (barring underflow of tiny extents,
// which the 1e-30 absolute term covers).
Sphere box_sphere(const Aabb& b) noexcept {
  const glm::vec3 c = b.center();
  const glm::vec3 e = glm::max(b.max - c, c - b.min);
  const float r = std::sqrt((e.x * e.x + e.y * e.y) + e.z * e.z);
  return Sphere{c, r * (1.0f + 0x1p-20f) + 1e-30f};
}

}  // namespace

StageResult box_sphere_stage(const Frustum& normalized_frustum, const Aabb& box) noexcept {
  const Visibility v = sphere_plane_test(normalized_frustum, box_sphere(box));
  if (v == Visibility::intersecting) return std::nullopt;
  return v;
}

FrustumBounds frustum_bounds(const Frustum& f) {
  FrustumBounds out;
  if (!is_bounded(f)) return out;
  const auto c = frustum_corners(f);
  glm::dvec3 centre(0.0), lo(std::numeric_limits<double>::infinity()), hi(-lo);
  for (const auto& p : c) {
    centre += p;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  centre /= 8.0;
  out.bounded = true;
  out.sphere_center = glm::vec3(centre);
  double r = 0.0;
  for (const auto& p : c) r = std::max(r, glm::length(p - glm::dvec3(out.sphere_center)));
  out.sphere_radius = float_at_least(r);
  for (int k = 0; k < 3; ++k) {
    out.box.min[k] = float_at_most(lo[k]);
    out.box.max[k] = float_at_least(hi[k]);
  }
  return out;
}

StageResult frustum_sphere_stage(const FrustumBounds& fb, const Aabb& box) noexcept {
  if (!fb.bounded) return std::nullopt;
  const Sphere s = box_sphere(box);
  const double dist = glm::length(glm::dvec3(s.center) - glm::dvec3(fb.sphere_center));
  if (dist > double(s.radius) + double(fb.sphere_radius)) return Visibility::outside;
  return std::nullopt;
}

StageResult frustum_aabb_stage(const FrustumBounds& fb, const Aabb& ob) noexcept {
  if (!fb.bounded) return std::nullopt;
  const Aabb& b = fb.box;
  if (b.min.x > ob.max.x || b.max.x < ob.min.x || b.min.y > ob.max.y || b.max.y < ob.min.y ||
      b.min.z > ob.max.z || b.max.z < ob.min.z)
    return Visibility::outside;
  return std::nullopt;
}

}  // namespace cullproof

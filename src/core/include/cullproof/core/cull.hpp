// cullproof fast cullers, stateless part: point, sphere, AABB and OBB tests against a frustum,
// the radar approach, the perspective-transform baseline and the composable pre-test stages.
//
// Every function follows docs/semantics.md: a point x is inside plane (n, d) when
// dot(n, x) + d >= 0, the frustum is the intersection of six closed half-spaces in the order
// left, right, bottom, top, near, far, and a volume touching the frustum from outside is
// `intersecting`, never `outside`. Each algorithm lives in its own file in src/cull/, whose
// header names the source text, the section, the claim, and how touching volumes are treated.
// Texts that use another sign (Assarsson & Möller: outside when n.x + d > 0) are translated.
//
// Stateful (frame-coherent) cullers are in cull_coherence.hpp, hierarchies in cull_bvh.hpp,
// SIMD batches in cull_batch.hpp (library cullproof::simd).
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <optional>

namespace cullproof {

// ---------------------------------------------------------------------------------------------
// Points (src/core/cull/point_plane.cpp)

/// Lighthouse3D pointInFrustum: outside as soon as one plane gives dot(n, p) + d < 0, else
/// inside. Never `intersecting`. A point on a plane is inside. Planes need not be normalised.
Visibility point_plane_test(const Frustum& frustum, const Point& p) noexcept;

// ---------------------------------------------------------------------------------------------
// Spheres (src/core/cull/sphere_plane.cpp)

/// Lighthouse3D sphereInFrustum: per plane, distance < -r is outside, distance < r intersecting.
/// `frustum` must have unit normals (Frustum::normalized()); degenerate planes (n == 0) are "all
/// space" when d >= 0 (skipped) and "nothing" when d < 0 (outside). Conservative: a sphere near a
/// frustum edge may be reported intersecting although it is outside.
Visibility sphere_plane_test(const Frustum& normalized_frustum, const Sphere& s) noexcept;
/// sphere_plane_test with each plane value taken by plane_value: the same verdicts wherever the
/// float values are finite, the value in double where it overflows. (src/core/cull/sphere_plane.cpp)
Visibility sphere_plane_test_wide(const Frustum& normalized_frustum, const Sphere& s) noexcept;

// ---------------------------------------------------------------------------------------------
// The radar approach (src/core/cull/radar.cpp; Lighthouse3D "Radar Approach", after Puig Placeres,
// Game Programming Gems 5). Works in the camera frame: z along the view direction.

/// Camera frame and the precomputed factors of the radar tests.
struct RadarCamera {
  glm::vec3 eye{0.0f};
  glm::vec3 x_axis{1.0f, 0.0f, 0.0f};   ///< camera right, unit
  glm::vec3 y_axis{0.0f, 1.0f, 0.0f};   ///< camera up, unit
  glm::vec3 z_axis{0.0f, 0.0f, -1.0f};  ///< view direction, unit (pc.z = dot(p - eye, z_axis))
  float near_dist = 0.1f;
  float far_dist = 100.0f;              ///< may be +infinity
  float tang = 0.0f;                    ///< tan of half the vertical fov (as published: see radar.cpp)
  float ratio = 1.0f;                   ///< width / height
  float sphere_factor_x = 1.0f;         ///< 1 / cos(half horizontal fov)
  float sphere_factor_y = 1.0f;         ///< 1 / cos(half vertical fov)
};

/// Corrected setCamInternals + setCamDef: tang = tan(fov/2), sphere factors of the half angles.
/// Throws ValidationError for the cameras frustum_from_camera refuses.
RadarCamera radar_camera(const PerspectiveCamera& cam);
/// As published in "Radar Approach - Implementation II": tang = tan(fov) (the full angle, not
/// halved), sphereFactorY = 1/cos(fov), sphereFactorX = 1/cos(atan(tang * ratio)).
RadarCamera radar_camera_as_published(const PerspectiveCamera& cam);
/// Camera parameters of a symmetric perspective frustum, derived from its planes (in double):
/// apex, axes, tan of the half fovs, near and far (far may be infinite). std::nullopt when the
/// frustum is not a symmetric perspective one (within relative tolerance 1e-5), or when its
/// camera does not fit in float (an apex or a near or far distance beyond FLT_MAX).
/// `as_published` applies the Implementation II factors to the derived fov.
std::optional<RadarCamera> radar_camera_from_frustum(const Frustum& frustum, bool as_published = false);

/// Radar point test: z outside [near, far], then |y| > z*tang, then |x| > z*tang*ratio is
/// outside; else inside (a point on the boundary is inside). Exact in exact arithmetic.
Visibility radar_point(const RadarCamera& cam, const Point& p) noexcept;
/// Radar sphere test with the sphere factors (Implementation II). A touching sphere is
/// intersecting. Conservative (per-plane, like sphere_plane_test) with the corrected camera.
Visibility radar_sphere(const RadarCamera& cam, const Sphere& s) noexcept;
/// radar_sphere with the same operations, taken again in double when one of its float values
/// overflows (a coordinate, a dot product or a bound that is not finite, far excepted when it is
/// infinite): the verdicts of radar_sphere wherever nothing overflows. (src/core/cull/radar.cpp)
Visibility radar_sphere_wide(const RadarCamera& cam, const Sphere& s) noexcept;

// ---------------------------------------------------------------------------------------------
// AABB tests

/// Lighthouse3D "Testing Boxes": per plane, count the 8 corners with distance < 0 (out) and
/// >= 0 (in); no corner in: outside; both: intersecting. (src/core/cull/eight_corner.cpp)
Visibility aabb_eight_corner(const Frustum& frustum, const Aabb& box) noexcept;

/// Assarsson & Möller 2000 §3.1 fig. 4, per-box sign selection with branches: n-vertex outside
/// (value < 0): outside; p-vertex outside: intersecting. (src/core/cull/pn_vertex.cpp)
Visibility pn_vertex(const Frustum& frustum, const Aabb& box) noexcept;

/// The min/max index trick of the blog post "View frustum culling (AABB vs Frustum)", made
/// three-way: box[] = {min, max}, p index = (n > 0), n index = 1 - p index. The verdicts of
/// pn_vertex wherever the float plane values are finite; a value that overflows float is taken
/// again in double (plane_value). (src/core/cull/pn_vertex_index.cpp)
Visibility pn_vertex_index(const Frustum& frustum, const Aabb& box) noexcept;

/// dot(n, x) + d as Plane::eval computes it in float; where that overflows (finite input, a
/// value that is not finite: an infinite product or partial sum, or inf - inf), again in double,
/// where every product of two floats is exact and no sum of four of them overflows (each is
/// below 2^256). A float overflow says nothing about the sign of the value (n_x x_x = +inf and
/// n_y x_y = -inf make NaN), so a test that must not err beyond rounding takes it in double.
inline double plane_value(const Plane& p, const glm::vec3& x) noexcept {
  const float v = p.eval(x);
  if (std::isfinite(v)) return v;
  return ((double(p.n.x) * x.x + double(p.n.y) * x.y) + double(p.n.z) * x.z) + double(p.d);
}
/// The p-vertex post as published: only the p-vertex, `dp < -d` rejects; returns outside or
/// intersecting, never inside (the post's test is two-way). (src/core/cull/pn_vertex_index.cpp)
Visibility p_vertex_post(const Frustum& frustum, const Aabb& box) noexcept;

/// Per-frame sign bitfields (A&M §3.1, after Haines & Wallace): bit k of p_bits[i] set when
/// component k of plane i's normal is > 0, i.e. the p-vertex takes max on that axis.
struct PnLut {
  Frustum frustum;
  std::array<std::uint8_t, 6> p_bits{};
};
/// Computes the sign bitfields once per frame.
PnLut make_pn_lut(const Frustum& frustum) noexcept;
/// n/p-vertex test with the precomputed LUT; the n-vertex is the inverted bitfield. Same
/// verdicts as pn_vertex. (src/core/cull/pn_vertex_lut.cpp)
Visibility pn_vertex_lut(const PnLut& lut, const Aabb& box) noexcept;

// ---------------------------------------------------------------------------------------------
// OBB (src/core/cull/obb_pn_vertex.cpp)

/// A&M §3.1 / Lighthouse3D "Testing Boxes II": project the plane normal on the box axes,
/// take the signs to build the p- and n-vertex c +- sum h_i u_i, test them like pn_vertex.
Visibility obb_pn_vertex(const Frustum& frustum, const Obb& box) noexcept;

// ---------------------------------------------------------------------------------------------
// Perspective-transform baseline (DirectModel; A&M §2) (src/core/cull/perspective_transform.cpp)

/// As published: the 8 corners times the clip matrix, divided by w, bounded by an AABB in NDC,
/// compared with the NDC cube ([-1,1]^3 or depth [0,1]). Wrong when a corner has w <= 0
/// (behind the eye plane): the division mirrors or blows up the coordinates; a visible box from
/// behind the eye to beyond the far plane is rejected.
Visibility perspective_transform_as_published(const glm::mat4& clip_from_world,
                                              DepthConvention depth, const Aabb& box) noexcept;
/// Corrected: as published while every corner has w > 0; otherwise homogeneous outcodes
/// (all corners outside one clip half-space -x<=w, x<=w, ...: outside; else intersecting).
Visibility perspective_transform(const glm::mat4& clip_from_world, DepthConvention depth,
                                 const Aabb& box) noexcept;
/// A clip matrix whose Gribb–Hartmann planes (OpenGL depth) are positive multiples of the
/// frustum's planes, found by least squares in double; std::nullopt when the six planes are not
/// the image of a clip cube (relative residual > 1e-6 or a non-positive scale).
std::optional<glm::mat4> clip_matrix_from_frustum(const Frustum& frustum);

// ---------------------------------------------------------------------------------------------
// Pre-test stages (Lighthouse3D "Some Notes and Possible Optimizations") (src/core/cull/pretests.cpp)
//
// A stage returns outside or inside when it is sure, std::nullopt ("unknown") otherwise; the
// caller falls through to the next stage or the main test:
//   if (auto v = box_sphere_stage(fn, box)) return *v; return pn_vertex(f, box);

/// A stage's answer: a sure verdict, or std::nullopt to fall through.
using StageResult = std::optional<Visibility>;

/// The box's bounding sphere (centre, radius |half extent| rounded up) against the normalised
/// planes: outside or inside are sure; intersecting falls through ("case C").
StageResult box_sphere_stage(const Frustum& normalized_frustum, const Aabb& box) noexcept;

/// Bounding sphere and AABB of a bounded frustum (from its corners, in double, rounded outward).
struct FrustumBounds {
  bool bounded = false;  ///< false: an unbounded frustum; the stages below always fall through
  glm::vec3 sphere_center{0.0f};
  float sphere_radius = 0.0f;
  Aabb box;
};
/// Computes the bounds once per frame.
FrustumBounds frustum_bounds(const Frustum& frustum);
/// "Spheres everywhere": box's bounding sphere disjoint from the frustum's sphere: outside.
StageResult frustum_sphere_stage(const FrustumBounds& bounds, const Aabb& box) noexcept;
/// "Axis-Aligned Boxes everywhere": box disjoint from the frustum's AABB (strict compares, so a
/// touching box falls through): outside. The text's INSIDE (box in the frustum's AABB) is not a
/// frustum verdict, so it falls through too.
StageResult frustum_aabb_stage(const FrustumBounds& bounds, const Aabb& box) noexcept;

}  // namespace cullproof

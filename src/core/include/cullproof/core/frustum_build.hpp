// Frustum construction: from a clip matrix (Gribb–Hartmann), from gluPerspective/gluLookAt
// parameters (Lighthouse3D's geometric approach), from Hoff's off-axis camera, stereo pairs,
// orthographic projections and per-object (local-space) matrices; corners and symmetry.
//
// Sources:
//  - G. Gribb, K. Hartmann, "Fast Extraction of Viewing Frustum Planes from the
//    World-View-Projection Matrix", 2001 (row sums as fixed in docs/semantics.md "Frusta from matrices").
//  - Lighthouse3D "View Frustum Culling Tutorial", sections "Geometric Approach - Extracting the
//    Planes" and "Clip Space Approach".
//  - K. Hoff, "A 'Fast' Method for Culling of OBBs Against a Perspective Viewing Frustum", 1996:
//    camera axes, off-axis centre of projection, window on the camera XY plane.
//  - The blog post "View frustum culling (AABB vs Frustum)": planes in object-local space from a per-object
//    modelview-projection matrix.
#pragma once

#include "cullproof/core/geometry.hpp"

#include <array>
#include <optional>

namespace cullproof {

/// Clip-space depth range of a projection matrix.
enum class DepthRange {
  negative_one_to_one,  ///< OpenGL: -w <= z <= w
  zero_to_one,          ///< Direct3D, Vulkan, Metal: 0 <= z <= w
};

/// How a clip matrix maps depth: the range, and whether near maps to the top of it (reversed-Z).
struct DepthConvention {
  DepthRange range = DepthRange::negative_one_to_one;
  bool reversed_z = false;
};

/// Row i (0-based) of a GLM column-major matrix, as (a, b, c, d) of the clip coordinate it gives.
glm::vec4 matrix_row(const glm::mat4& m, int i) noexcept;

/// Gribb–Hartmann extraction in float from clip = m * x. With r1..r4 the rows: left r4+r1,
/// right r4-r1, bottom r4+r2, top r4-r2; depth per `depth` (docs/semantics.md "Frusta from matrices"): near r4+r3
/// or r3, far r4-r3; reversed-Z swaps the near and far roles. An infinite far plane comes out as
/// n == 0, d > 0 ("contains all space"), never NaN. Planes are not normalised.
/// Every plane is finite for every finite matrix: a plane whose two rows reach past FLT_MAX
/// (gribb_hartmann_halves) is extracted as fl(r4/2 +- rk/2), half the plane, the same half-space
/// (halving is exact for normal entries; a subnormal one rounds by at most 2^-150). Otherwise
/// fl(r4 +- rk), one rounding per coefficient.
/// Passing P*V gives world-space planes; passing P*V*M gives planes in M's local space.
Frustum frustum_from_matrix(const glm::mat4& clip_from_space, DepthConvention depth = {});
/// Whether frustum_from_matrix halves the rows a and b before adding or subtracting them: some
/// coefficient has |a_i| + |b_i| > FLT_MAX, where the float sum or difference may overflow.
bool gribb_hartmann_halves(const glm::vec4& a, const glm::vec4& b) noexcept;

/// Planes in an object's local space: frustum_from_matrix(view_proj * model). Test boxes given in
/// the object's own coordinates against these (the blog post "View frustum culling (AABB vs Frustum)").
Frustum local_frustum(const glm::mat4& view_proj, const glm::mat4& model, DepthConvention depth = {});

/// gluPerspective + gluLookAt parameters (Lighthouse3D). `far_dist` may be +infinity.
struct PerspectiveCamera {
  float fovy_degrees = 60.0f;  ///< vertical field of view
  float aspect = 1.0f;         ///< width / height ("ratio")
  float near_dist = 0.1f;
  float far_dist = 100.0f;
  glm::vec3 eye{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
};

/// Lighthouse3D geometric approach, normal-and-point variant ("the more efficient alternative"):
/// near (normal d, point nc), far (normal -d, point fc), side planes through the eye. Computed in
/// double and rounded to float; the side normals are unit, so planes agree with
/// frustum_from_matrix(view_projection(cam)).normalized() to within float rounding of the inputs
/// (tests/test_frustum_build.cpp states the tolerance). Throws ValidationError for a camera with
/// fov outside (0, 180), aspect <= 0, near <= 0, far <= near, eye == target or up parallel to the
/// view direction.
Frustum frustum_from_camera(const PerspectiveCamera& cam);
/// glm::perspective (or infinitePerspective when far is infinite) times glm::lookAt, for the
/// given depth convention (reversed-Z swaps near and far in the matrix).
glm::mat4 view_projection(const PerspectiveCamera& cam, DepthConvention depth = {});
/// The projection alone of view_projection: glm::perspective (infinitePerspective, or its [0, 1]
/// limit, when `far_dist` is infinite) for the depth convention, reversed-Z swapping near and far.
glm::mat4 perspective_projection(float fovy_degrees, float aspect, float near_dist, float far_dist,
                                 DepthConvention depth = {});

/// Hoff's camera (Hoff 1996): camera axes in world coordinates, an origin, a centre of
/// projection (COP) in camera coordinates that may be off-axis, a viewplane window on the camera
/// XY plane (z = 0), near and far planes parallel to it. The camera looks along -z (towards -vpn):
/// cop.z > near_z > far_z. `far_z` may be -infinity.
struct HoffCamera {
  glm::vec3 origin{0.0f};
  glm::vec3 horizon{1.0f, 0.0f, 0.0f};  ///< camera x axis in world coordinates (unit)
  glm::vec3 view_up{0.0f, 1.0f, 0.0f};  ///< camera y axis (unit)
  glm::vec3 vpn{0.0f, 0.0f, 1.0f};      ///< viewplane normal, camera z axis (unit), points back
  glm::vec3 cop{0.0f, 0.0f, 1.0f};      ///< centre of projection, camera coordinates
  float window_left = -0.5f, window_right = 0.5f, window_bottom = -0.5f, window_top = 0.5f;
  float near_z = 0.5f;   ///< camera-space z of the near plane
  float far_z = -100.0f; ///< camera-space z of the far plane
};

/// The frustum of a HoffCamera, planes through the COP and the window edges, in world space.
/// Throws ValidationError naming the field for an inconsistent camera.
Frustum frustum_from_hoff_camera(const HoffCamera& cam);
/// The COP of a HoffCamera in world coordinates.
glm::vec3 hoff_cop_world(const HoffCamera& cam) noexcept;

/// A stereo pair with parallel view axes and off-axis (asymmetric) frusta converging at
/// `convergence` (the standard "off-axis" stereo set-up).
struct StereoRig {
  PerspectiveCamera center;          ///< the cyclopean camera
  float eye_separation = 0.065f;     ///< distance between the eyes, world units
  float convergence = 2.0f;          ///< distance of the zero-parallax plane
};
/// {left eye, right eye} view-projection matrices (glm::frustum with shifted window).
std::array<glm::mat4, 2> stereo_view_projections(const StereoRig& rig, DepthConvention depth = {});

/// The frustum of a case: six planes, or a clip matrix with its depth convention.
struct CaseFrustum {
  /// The planes as given, or (for a matrix case) extracted from the float matrix in float by
  /// frustum_from_matrix: what a float culler sees.
  Frustum planes;
  /// Set when the case gives the frustum as a matrix; the truth is then end-to-end (exact
  /// extraction from these float entries).
  std::optional<glm::mat4> matrix;
  DepthConvention depth;
};

/// A case frustum made from planes.
CaseFrustum frustum_spec(const Frustum& planes);
/// A case frustum made from a clip matrix (planes extracted in float by frustum_from_matrix).
CaseFrustum frustum_spec(const glm::mat4& matrix, DepthConvention depth);

/// An off-axis perspective projection (glm::frustum) for the given depth convention.
glm::mat4 off_axis_projection(float left, float right, float bottom, float top, float near_dist,
                              float far_dist, DepthConvention depth = {});
/// An orthographic projection (glm::ortho) for the given depth convention.
glm::mat4 orthographic_projection(float left, float right, float bottom, float top,
                                  float near_dist, float far_dist, DepthConvention depth = {});

/// The point where three planes n.x + d = 0 meet (each plane as (n.x, n.y, n.z, d)), or nullopt
/// when they do not meet in one point or the point is not finite. Cramer's rule in double:
/// det = n_a . (n_b x n_c), x = -(d_a (n_b x n_c) + d_b (n_c x n_a) + d_c (n_a x n_b)) / det.
///
/// Cut-off, derived: det is computed with 2 roundings in each component of the cross product and
/// 3 in the dot product, so its absolute error is at most gamma_5 S (Higham, "Accuracy and
/// Stability of Numerical Algorithms", 2002, §3.1: gamma_n = n u / (1 - n u)), where S is the sum
/// of the magnitudes of its six terms |n_a,i n_b,j n_c,k|. A determinant within that bound of 0
/// has no certain sign and the point no accuracy: the planes count as not meeting. The test is
/// |det| > kMeetCutoff S, computed, with kMeetCutoff = 16 u (u = 2^-53): it covers gamma_5 with
/// the unit doubled (any IEEE rounding mode: the oracle calls it rounding upwards) and the
/// roundings of S itself. Exactly parallel normals give det = 0 and S > 0 or S = 0: refused.
std::optional<glm::dvec3> planes_meet(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) noexcept;
/// The same for float planes (converted exactly).
std::optional<glm::dvec3> planes_meet(const Plane& a, const Plane& b, const Plane& c) noexcept;
/// planes_meet's cut-off on |det| / S.
inline constexpr double kMeetCutoff = 16 * 0x1p-53;

/// The 8 corners of a bounded frustum, computed in double by intersecting plane triples.
/// Index bits: bit 0 right (else left), bit 1 top (else bottom), bit 2 far (else near).
/// Throws std::domain_error when the frustum is unbounded (a degenerate plane, or three planes
/// that do not meet in a point).
std::array<glm::dvec3, 8> frustum_corners(const Frustum& f);
/// Whether the frustum is bounded (all six planes non-degenerate and every corner triple meets).
bool is_bounded(const Frustum& f) noexcept;
/// The centre of a bounded frustum: the mean of its eight corners (Assarsson & Möller, fn. 5).
glm::dvec3 frustum_center(const Frustum& f);

/// Whether a bounded frustum is symmetric about its view axis (what the octant test needs,
/// Assarsson & Möller 3.3): near and far faces are parallel rectangles centred on one line
/// perpendicular to them, with parallel edges. `rel_tol` is relative to the frustum's size.
bool is_symmetric(const Frustum& f, double rel_tol = 1e-5);

}  // namespace cullproof

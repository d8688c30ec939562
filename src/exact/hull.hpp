// Internal: a frustum as a convex polyhedron (vertices, extreme rays, edges) and OBB helpers
// shared by Hoff's test, the separating-axis test and the reverse test. Float, as a float
// culler holds them.
#pragma once

#include "cullproof/exact.hpp"
#include "cullproof/geometry.hpp"

#include <array>
#include <optional>
#include <utility>
#include <vector>

namespace cullproof::exact_detail {

/// The frustum's vertices and, when the far plane is "all space", the rays of its lateral edges.
struct FrustumHull {
  bool empty = false;                      ///< a plane with n == 0, d < 0: nothing is inside
  std::vector<glm::vec3> vertices;         ///< 8 corners (bounded) or the 4 near corners
  std::vector<glm::vec3> rays;             ///< lateral edge directions (unbounded; largest component in [0.5, 1), not unit), else empty
  std::vector<std::pair<int, int>> edges;  ///< vertex index pairs (bounded edges)
  std::vector<std::pair<int, int>> ray_edges;  ///< (vertex index, ray index)
};

/// Vertices/rays of a frustum with frustum topology (left/right x bottom/top x near/far). The
/// far plane may be "all space". nullopt when another plane is degenerate, triples do not meet,
/// or the six planes do not have frustum topology (a computed corner lies outside another
/// plane by more than rounding: e.g. nearly parallel side planes that cross before the far
/// plane, so the polytope's vertices are not the eight corner triples).
/// Whether the eight corner triples of `f` (double) are the vertices of the polytope: each
/// satisfies every plane to within 1e-6 of the magnitudes involved.
bool has_frustum_topology(const Frustum& f, const std::vector<glm::dvec3>& corners);
std::optional<FrustumHull> frustum_hull(const Frustum& f);

/// The eight corners of an OBB, index bits: bit k set = +h_k along u_k.
std::array<glm::vec3, 8> obb_corners(const Obb& b) noexcept;

/// Half-length of the OBB's projection on `axis` (sum h_i |u_i . axis|).
inline float obb_radius(const Obb& b, const glm::vec3& axis) noexcept {
  return b.half.x * std::abs(glm::dot(b.axes[0], axis)) + b.half.y * std::abs(glm::dot(b.axes[1], axis)) +
         b.half.z * std::abs(glm::dot(b.axes[2], axis));
}

/// Whether all eight OBB corners are inside every plane (float evaluation, closed).
bool all_corners_inside(const Frustum& f, const std::array<glm::vec3, 8>& corners) noexcept;

}  // namespace cullproof::exact_detail

namespace cullproof::exact_detail {

/// Does the closed segment [a, b] meet the closed face of the OBB on axis k, side s (+1/-1)?
/// Float: the segment is cut with the face plane, the cut point compared with the face's
/// half-extents (closed). A segment lying in the face plane is clipped against the rectangle.
bool segment_hits_obb_face(const glm::vec3& a, const glm::vec3& b, const Obb& box, int k, float s) noexcept;

/// Is p inside the OBB (|(p - c) . u_k| <= h_k for each axis; axes taken as orthonormal)?
bool point_in_obb(const glm::vec3& p, const Obb& box) noexcept;

/// Does the closed segment [a, b] meet frustum face `face` (the part of plane `face` that
/// satisfies the other five planes)? Float.
bool segment_hits_frustum_face(const glm::vec3& a, const glm::vec3& b, const Frustum& f, int face) noexcept;

/// Hoff's first two stages: 6-bit outcodes of the eight corners, built plane by
/// plane in the order near, left, right, bottom, top, far with a trivial reject as soon as the AND
/// of the codes is non-zero; then a trivial accept if any code is zero (`inside` when all are).
/// Sets *stage when it decides; nullopt when neither stage decides.
std::optional<Visibility> hoff_trivial_stages(const Frustum& f, const std::array<glm::vec3, 8>& corners,
                                              HoffStage* stage) noexcept;

/// Whether the segment a + t (b - a), t in [0, 1], given in coordinates where the face is the
/// rectangle |x_j| <= h_j, |x_l| <= h_l of its plane, has a point in that rectangle (Liang–Barsky
/// clipping). Used for a segment lying in a face's plane.
bool clip_segment_to_rect(float a_j, float d_j, float h_j, float a_l, float d_l, float h_l) noexcept;

/// Outcode of a point: bit i set when the point is outside plane i (eval < 0).
inline unsigned outcode(const Frustum& f, const glm::vec3& p) noexcept {
  unsigned c = 0;
  for (int i = 0; i < kPlaneCount; ++i)
    if (f[i].eval(p) < 0.0f) c |= 1u << i;
  return c;
}

}  // namespace cullproof::exact_detail

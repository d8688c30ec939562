// Hoff's OBB test as published, its completed variant, and exact float tests by separating
// axes. See src/exact/*.cpp for the sources, sections and what each adds.
#pragma once

#include "cullproof/core/geometry.hpp"

#include <array>
#include <optional>
#include <string_view>

namespace cullproof {

/// Where Hoff's procedure ended for one box.
enum class HoffStage : std::uint8_t {
  trivial_reject,  ///< all eight corners outside one plane
  trivial_accept,  ///< a corner inside all six planes
  edge_face,       ///< a frustum edge hits an OBB face
  containment,     ///< the frustum's origin lies in the OBB
  box_edge_face,   ///< (hoff-exact only) an OBB edge hits a frustum face
  final_reject,    ///< nothing found: rejected
};
/// "trivial-reject", "trivial-accept", "edge-face", "containment", "box-edge-face", "final-reject".
std::string_view to_string(HoffStage s) noexcept;

/// A bounded frustum as a polyhedron: its eight corners (frustum_corners order: bit 0 right,
/// bit 1 top, bit 2 far) in float, as a float culler holds them.
struct FrustumPolyhedron {
  std::array<glm::vec3, 8> corners;
};
/// Corners of a bounded frustum rounded to float; nullopt when unbounded.
std::optional<FrustumPolyhedron> frustum_polyhedron(const Frustum& f);

/// The pyramid apex of a perspective frustum (Hoff's centre of projection): the point where the
/// four side planes meet, least squares in double. nullopt when the side planes do not meet in a
/// point (orthographic) or the frustum is degenerate.
std::optional<glm::vec3> frustum_apex(const Frustum& f);

/// Hoff 1996, exactly as published: outcodes, trivial reject per plane in the
/// order near, left, right, bottom, top, far, trivial accept on the first corner inside all
/// planes, 12 frustum edges x 6 OBB faces, then the frustum origin `origin` inside the OBB, else
/// reject. Needs a bounded frustum (nullopt otherwise). Three-way: `inside` when all eight
/// corners are inside every plane, else `intersecting` on any accept. `stage` (optional) receives
/// where the procedure ended.
std::optional<Visibility> hoff96(const Frustum& f, const Obb& b, const glm::vec3& origin,
                                 HoffStage* stage = nullptr);
/// Hoff's structure completed so that it is exact (see src/core/exact/hoff_exact.cpp for what was
/// added and the corpus cases that prove each addition is needed).
std::optional<Visibility> hoff_exact(const Frustum& f, const Obb& b, HoffStage* stage = nullptr);

/// Separating-axis test in float for an OBB against a frustum: axes are the face normals of both
/// and the cross products of box edge directions with frustum edge directions (parallel pairs
/// skipped). Handles an infinite far plane (the frustum's lateral edges become rays),
/// orthographic and off-axis frusta, and degenerate boxes. Two-way answer: true if separated.
/// nullopt when the planes do not form a frustum (not six planes meeting in frustum topology).
std::optional<bool> sat_separated(const Frustum& f, const Obb& b);
/// Three-way SAT: outside when separated; inside when all eight corners are inside all planes.
std::optional<Visibility> sat_classify(const Frustum& f, const Obb& b);

/// The "reverse" test asked for in the p-vertex post's comments: the n/p-vertex test, and when it
/// says intersecting, the frustum's corners against the box's own six face planes (outside when
/// all corners lie outside one face plane). Bounded frusta use corners; an unbounded frustum
/// skips the reverse stage.
Visibility pn_vertex_reverse(const Frustum& f, const Obb& b);

}  // namespace cullproof

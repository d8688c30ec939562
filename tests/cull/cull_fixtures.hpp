// Hand-made frusta and helpers shared by the tests of the fast culler family.
#pragma once

#include "cullproof/core/cull.hpp"

#include <glm/ext/matrix_clip_space.hpp>

namespace cullproof::test {

/// Symmetric perspective frustum with exact coefficients: apex at the origin, looking down -z,
/// 90 degree fov both ways (|x| <= -z, |y| <= -z), near z = -1, far z = -10.
inline Frustum sym90() {
  Frustum f;
  f[kLeft] = Plane{{1, 0, -1}, 0};
  f[kRight] = Plane{{-1, 0, -1}, 0};
  f[kBottom] = Plane{{0, 1, -1}, 0};
  f[kTop] = Plane{{0, -1, -1}, 0};
  f[kNear] = Plane{{0, 0, -1}, -1};
  f[kFar] = Plane{{0, 0, 1}, 10};
  return f;
}

/// sym90 with an infinite far plane (n == 0, d > 0).
inline Frustum sym90_infinite() {
  Frustum f = sym90();
  f[kFar] = Plane{{0, 0, 0}, 1};
  return f;
}

/// Orthographic box -1 <= x, y <= 1, -10 <= z <= -1.
inline Frustum ortho() {
  Frustum f;
  f[kLeft] = Plane{{1, 0, 0}, 1};
  f[kRight] = Plane{{-1, 0, 0}, 1};
  f[kBottom] = Plane{{0, 1, 0}, 1};
  f[kTop] = Plane{{0, -1, 0}, 1};
  f[kNear] = Plane{{0, 0, -1}, -1};
  f[kFar] = Plane{{0, 0, 1}, 10};
  return f;
}

/// Off-axis (asymmetric) perspective: window x in [-0.2, 1], y in [-0.5, 0.5] at near 1, far 10.
inline glm::mat4 off_axis_matrix() { return glm::frustum(-0.2f, 1.0f, -0.5f, 0.5f, 1.0f, 10.0f); }
inline Frustum off_axis() { return frustum_from_matrix(off_axis_matrix()); }

/// The clip matrix of sym90 (OpenGL depth): glm::frustum(-1, 1, -1, 1, 1, 10).
inline glm::mat4 sym90_matrix() { return glm::frustum(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 10.0f); }

inline Aabb box(glm::vec3 lo, glm::vec3 hi) { return Aabb{lo, hi}; }

// Canonical boxes against sym90 (and ortho: the same boxes, checked per frustum in tests).
inline Aabb inside_box() { return box({-0.5f, -0.5f, -4}, {0.5f, 0.5f, -3}); }
inline Aabb outside_box() { return box({20, -0.5f, -4}, {21, 0.5f, -3}); }
inline Aabb straddle_right_box() { return box({2.5f, -0.5f, -4}, {3.5f, 0.5f, -3}); }   // crosses x = -z = 3..4
inline Aabb touch_near_outside_box() { return box({-0.25f, -0.25f, -1}, {0.25f, 0.25f, 0}); }  // max z... shares z = -1
inline Aabb touch_near_inside_box() { return box({-0.5f, -0.5f, -3}, {0.5f, 0.5f, -1}); }
inline Aabb behind_box() { return box({-0.5f, -0.5f, 1}, {0.5f, 0.5f, 2}); }
inline Aabb far_beyond_box() { return box({-0.5f, -0.5f, -30}, {0.5f, 0.5f, -20}); }

}  // namespace cullproof::test

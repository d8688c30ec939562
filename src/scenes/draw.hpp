// Internal to src/scenes: random numbers, cameras and placed objects of the scene families.
#pragma once

#include "cullproof/core/splitmix.hpp"
#include "cullproof/scenes/scenes.hpp"

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace cullproof::scenes::detail {

/// A run's random numbers: one splitmix64 stream per (seed, family, index).
struct Rng {
  SplitMix64 s;
  double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * s.uniform(); }
  /// log-uniform in [lo, hi], lo > 0
  double log_uniform(double lo, double hi) noexcept { return lo * std::pow(hi / lo, s.uniform()); }
  int pick(int n) noexcept { return s.range(0, n - 1); }
  bool chance(double p) noexcept { return s.uniform() < p; }
  glm::dvec3 in_box(double half) noexcept { return {uniform(-half, half), uniform(-half, half), uniform(-half, half)}; }
  glm::dvec3 direction() noexcept;
  /// A rotation, uniform over all rotations (Shoemake's quaternion).
  glm::dmat3 rotation() noexcept;
};

/// A camera as the families move it.
struct Camera {
  enum class Kind { perspective, off_axis, orthographic };
  Kind kind = Kind::perspective;
  glm::dvec3 eye{0.0};
  glm::dmat3 axes{1.0};  ///< columns right, up, back
  double fovy = 60.0, aspect = 1.5;  ///< perspective
  double left = -1, right = 1, bottom = -1, top = 1;  ///< off-axis: the window at the near plane; orthographic: extents
  double near_d = 0.1, far_d = 100.0;  ///< far may be infinite for `perspective`
  DepthConvention depth;
};

/// The world's scale: cameras stand and objects lie within [-kWorld, kWorld]^3 (before a far
/// family's offset).
inline constexpr double kWorld = 100.0;

/// A random camera in the world about `origin`, of a random kind.
Camera random_camera(Rng& r, const glm::dvec3& origin);
/// Another projection of a random kind for the same pose.
void random_projection(Rng& r, Camera& c);
/// The view a system gets: float pose, view and projection matrices, their product and the planes
/// extracted from it.
CullView view_of(const Camera& c);
/// A point in view space (x right, y up, z back; the camera looks along -z) to the world.
glm::dvec3 to_world(const Camera& c, const glm::dvec3& p) noexcept;
/// The frames of a camera path: frame 0 at `start`, then one event per frame (a cut goes to
/// another random place about `origin`); `cameras` gets each frame's camera.
std::vector<RunFrame> camera_path(Rng& r, Camera start, std::size_t frames, const glm::dvec3& origin,
                                  std::vector<Camera>& cameras);

/// An object as the families place and move it: a local volume about the origin and the
/// transform translation * rotation * scale; `rotated` false keeps a box axis-aligned.
struct Placed {
  Volume local;
  glm::dvec3 position{0.0};
  glm::dmat3 rotation{1.0};
  glm::dvec3 scale{1.0};
  bool rotated = false;
};
/// The object with `id`: its world volume (computed in double, rounded to float once per value),
/// its local volume and float transform.
SceneObject realise(const Placed& p, std::uint32_t id);
/// Bit for bit the same volume (a moved object whose world did not change is not reported).
bool same_volume(const Volume& a, const Volume& b) noexcept;

}  // namespace cullproof::scenes::detail

// Camera paths: a camera moving past fixed volumes, frame by frame (cullproof/gen/generators.hpp).
#include "blocks.hpp"

#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cmath>

namespace cullproof::gen {

using namespace detail;

namespace {

// The camera of frame k of a path from `base`: motions are applied k times from the base pose
// (not accumulated frame to frame), so frame k does not depend on rounding in earlier frames.
Camera moved(const Camera& base, const std::string& motion, int k, const glm::dvec3& step, const glm::dvec3& axis,
             double angle, double zoom) {
  Camera c = base;
  const glm::dvec3 dir = glm::normalize(glm::dvec3(base.dir));
  const glm::dvec3 right = glm::normalize(glm::cross(dir, glm::dvec3(base.up)));
  const glm::dvec3 up = glm::cross(right, dir);
  auto turn = [&](const glm::dvec3& about) {
    const glm::dquat q = glm::angleAxis(angle * k, about);
    c.dir = glm::vec3(q * dir);
    c.up = glm::vec3(q * up);
  };
  if (motion == "translation" || motion == "general") c.eye = glm::vec3(glm::dvec3(base.eye) + step * double(k));
  if (motion == "rotation-x") turn(right);
  if (motion == "rotation-y") turn(up);
  if (motion == "rotation-z") turn(dir);
  if (motion == "general") turn(glm::normalize(axis));
  if (motion == "zoom") {
    const float s = float(std::pow(zoom, k));
    c.l *= s, c.r *= s, c.b *= s, c.t *= s;
  }
  return c;
}

}  // namespace

CameraPath detail::make_camera_path() {
  static const char* const kMotions[] = {"still", "translation", "rotation-x", "rotation-y",
                                         "rotation-z", "general", "zoom"};
  CameraPath path;
  path.motion = kMotions[pick(7)];
  const Camera base = generic_camera();
  const Placement first = placement_for(base);
  // Per frame: a step of 0.1% to 10% of the scene, a turn of 0.001 to 0.2 radians, a zoom of
  // 0.5% to 10%, so that over the path the objects placed about the frusta cross their faces.
  const glm::dvec3 step = unit_vector() * (first.size * log_in(-3, -1));
  const glm::dvec3 axis = unit_vector();
  const double angle = (coin(50) ? 1 : -1) * log_in(-3, -0.7);
  const double zoom = coin(50) ? 1.0 + log_in(-2.3, -1) : 1.0 / (1.0 + log_in(-2.3, -1));
  std::vector<Placement> places;
  for (int k = 0; k < int(kPathFrames); ++k) {
    const Camera c = moved(base, path.motion, k, step, axis, angle, zoom);
    path.frames.push_back(realize(c));
    places.push_back(placement_for(c));
    path.scene_size.push_back(places.back().size);
  }
  // Objects about the first, middle and last frames' frusta: near their faces and corners, or
  // anywhere around them.
  static constexpr Distribution kAround[] = {Distribution::near_boundary, Distribution::corner, Distribution::uniform};
  for (std::size_t i = 0; i < kPathObjects; ++i) {
    const Placement& p = places[std::size_t(std::array<int, 3>{0, int(kPathFrames) / 2, int(kPathFrames) - 1}[pick(3)])];
    path.objects.push_back(generic_volume(kAround[pick(3)], p));
  }
  return path;
}

rc::Gen<CameraPath> camera_path() { return rc::gen::resize(100, rc::gen::exec(detail::make_camera_path)); }

PathIndex path_index(std::uint64_t index) noexcept {
  PathIndex p;
  p.path = index / (kPathFrames * kPathObjects);
  p.frame = std::size_t(index / kPathObjects % kPathFrames);
  p.object = std::size_t(index % kPathObjects);
  return p;
}

std::uint64_t path_case_index(const PathIndex& p) noexcept {
  return (p.path * kPathFrames + p.frame) * kPathObjects + p.object;
}

GenCase path_case(const CameraPath& p, std::size_t frame, std::size_t object) {
  GenCase g;
  g.frustum = p.frames.at(frame);
  g.scene_size = p.scene_size.at(frame);
  g.volume = p.objects.at(object);
  return g;
}


}  // namespace cullproof::gen

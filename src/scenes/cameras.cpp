// The cameras of the scene families and their paths: every projection cullproof knows
// (perspective, off-axis, orthographic; reversed-Z; infinite far; both depth ranges) and the
// events between frames that break what a system keeps from frame to frame (a cut, a switched
// projection, a zoom) beside those that keep it (a step, a turn, a roll, the other eye).
#include "draw.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <limits>

namespace cullproof::scenes::detail {

glm::dvec3 Rng::direction() noexcept {
  // Uniform on the sphere: z uniform in [-1, 1], the angle about z uniform.
  const double z = uniform(-1.0, 1.0), a = uniform(0.0, 2.0 * M_PI), r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(a), r * std::sin(a), z};
}

glm::dmat3 Rng::rotation() noexcept {
  // Shoemake, "Uniform random rotations", Graphics Gems III, 1992.
  const double u1 = s.uniform(), u2 = 2.0 * M_PI * s.uniform(), u3 = 2.0 * M_PI * s.uniform();
  const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
  const double x = a * std::sin(u2), y = a * std::cos(u2), z = b * std::sin(u3), w = b * std::cos(u3);
  return glm::dmat3(1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y),   //
                    2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x),   //
                    2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y));
}

namespace {

// Rotates the camera's axes by `angle` radians about its own axis `k` (0 right, 1 up, 2 back).
void turn(Camera& c, int k, double angle) {
  const glm::dvec3 about = c.axes[k];
  const double cs = std::cos(angle), sn = std::sin(angle);
  for (int i = 0; i < 3; ++i) {
    const glm::dvec3 v = c.axes[i];
    // Rodrigues' formula
    c.axes[i] = v * cs + glm::cross(about, v) * sn + about * glm::dot(about, v) * (1.0 - cs);
  }
}

// Right-handed orthonormal axes with `back` given.
glm::dmat3 axes_from_back(const glm::dvec3& back, const glm::dvec3& up_hint) {
  glm::dvec3 right = glm::cross(up_hint, back);
  if (glm::length(right) < 1e-6) right = glm::cross(glm::dvec3(1, 0, 0), back);
  right = glm::normalize(right);
  return glm::dmat3(right, glm::cross(back, right), back);
}

}  // namespace

void random_projection(Rng& r, Camera& c) {
  const int kind = r.pick(4);
  c.kind = kind <= 1 ? Camera::Kind::perspective : kind == 2 ? Camera::Kind::off_axis : Camera::Kind::orthographic;
  c.depth.range = r.chance(0.5) ? DepthRange::zero_to_one : DepthRange::negative_one_to_one;
  c.depth.reversed_z = r.chance(0.3);
  c.near_d = r.log_uniform(0.02, 2.0);
  c.far_d = c.near_d * r.log_uniform(20.0, 5000.0);
  c.fovy = r.uniform(20.0, 120.0);
  c.aspect = r.log_uniform(0.5, 2.5);
  if (c.kind == Camera::Kind::perspective && r.chance(0.3)) c.far_d = std::numeric_limits<double>::infinity();
  if (c.kind == Camera::Kind::off_axis) {
    const double h = c.near_d * r.uniform(0.2, 1.5), w = h * c.aspect, sx = r.uniform(-0.8, 0.8), sy = r.uniform(-0.8, 0.8);
    c.left = (-1.0 + sx) * w, c.right = (1.0 + sx) * w, c.bottom = (-1.0 + sy) * h, c.top = (1.0 + sy) * h;
  }
  if (c.kind == Camera::Kind::orthographic) {
    const double h = r.log_uniform(2.0, 60.0), w = h * c.aspect, sx = r.uniform(-0.3, 0.3);
    c.left = (-1.0 + sx) * w, c.right = (1.0 + sx) * w, c.bottom = -h, c.top = h;
    c.far_d = std::min(c.far_d, 4.0 * kWorld);
  }
}

Camera random_camera(Rng& r, const glm::dvec3& origin) {
  Camera c;
  c.eye = origin + r.in_box(kWorld);
  c.axes = axes_from_back(r.direction(), glm::dvec3(0, 1, 0));
  turn(c, 2, r.uniform(-0.3, 0.3));  // a little roll
  random_projection(r, c);
  return c;
}

glm::dvec3 to_world(const Camera& c, const glm::dvec3& p) noexcept { return c.eye + c.axes * p; }

CullView view_of(const Camera& c) {
  CullView v;
  v.eye = glm::vec3(c.eye);
  v.axes = glm::mat3(c.axes);
  // The view matrix from the float pose: rows right, up, back; translation -axes^T eye.
  glm::mat4 view(1.0f);
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) view[k][i] = v.axes[i][k];
    view[3][i] = -glm::dot(v.axes[i], v.eye);
  }
  v.view = view;
  const float n = float(c.near_d), f = float(c.far_d);
  switch (c.kind) {
    case Camera::Kind::perspective:
      v.projection = perspective_projection(float(c.fovy), float(c.aspect), n, f, c.depth);
      break;
    case Camera::Kind::off_axis:
      v.projection = off_axis_projection(float(c.left), float(c.right), float(c.bottom), float(c.top), n, f, c.depth);
      break;
    case Camera::Kind::orthographic:
      v.projection = orthographic_projection(float(c.left), float(c.right), float(c.bottom), float(c.top), n, f, c.depth);
      break;
  }
  v.perspective = c.kind != Camera::Kind::orthographic;
  v.frustum = frustum_spec(v.projection * v.view, c.depth);
  return v;
}

std::vector<RunFrame> camera_path(Rng& r, Camera c, std::size_t frames, const glm::dvec3& origin,
                                  std::vector<Camera>& cameras) {
  std::vector<RunFrame> out;
  cameras.clear();
  static const char* const kEvents[] = {"still", "translate", "translate", "translate", "turn", "turn",
                                        "roll", "zoom", "cut", "projection", "eye"};
  constexpr int kEventCount = int(sizeof(kEvents) / sizeof(kEvents[0]));
  for (std::size_t k = 0; k < frames; ++k) {
    std::string event = "first";
    if (k > 0) {
      event = kEvents[r.pick(kEventCount)];
      if (event == "translate") c.eye += r.direction() * r.log_uniform(0.05, 0.1 * kWorld);
      if (event == "turn") turn(c, r.pick(2), r.uniform(-0.4, 0.4));
      if (event == "roll") turn(c, 2, r.uniform(-0.8, 0.8));
      if (event == "zoom") {
        const double z = r.log_uniform(0.6, 1.6);
        c.fovy = std::clamp(c.fovy * z, 2.0, 160.0);
        c.left *= z, c.right *= z, c.bottom *= z, c.top *= z;
      }
      if (event == "cut") {  // another place and direction, the same projection
        const Camera next = random_camera(r, origin);
        c.eye = next.eye;
        c.axes = next.axes;
      }
      if (event == "projection") random_projection(r, c);
      if (event == "eye") c.eye += c.axes[0] * r.uniform(0.03, 0.1);  // the other eye of a stereo pair
    }
    cameras.push_back(c);
    RunFrame f;
    f.view = view_of(c);
    f.camera = event;
    out.push_back(std::move(f));
  }
  return out;
}

}  // namespace cullproof::scenes::detail

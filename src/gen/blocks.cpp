// The building blocks the families draw with (blocks.hpp).
#include "blocks.hpp"

#include "cullproof/core/splitmix.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace cullproof::gen::detail {


namespace {

thread_local FastDraw* t_fast = nullptr;
thread_local Replay* t_replay = nullptr;

// RapidCheck's draw of [lo, hi] whose value, until shrunk, is `root`.
rc::Gen<std::int64_t> rooted(std::int64_t lo, std::int64_t root) {
  return [lo, root](const rc::Random&, int) {
    return rc::shrinkable::shrinkRecur(root, [lo](std::int64_t x) { return rc::shrink::towards(x, lo); });
  };
}

}  // namespace

FastDraw::FastDraw(std::uint64_t key, std::vector<std::int64_t>* log) : key_(key), log_(log), outer_(t_fast) {
  t_fast = this;
}
FastDraw::~FastDraw() { t_fast = outer_; }

Replay::Replay(const std::vector<std::int64_t>& values) : values_(values), outer_(t_replay) { t_replay = this; }
Replay::~Replay() { t_replay = outer_; }

std::int64_t integer(std::int64_t lo, std::int64_t hi) {
  if (FastDraw* f = t_fast) {
    const std::uint64_t r = splitmix64(f->key_ + 0x9E3779B97F4A7C15ull * ++f->count_);
    const std::uint64_t span = std::uint64_t(hi) - std::uint64_t(lo) + 1;  // 0: the whole of int64
    const std::uint64_t k = span == 0 ? r : std::uint64_t((static_cast<unsigned __int128>(r) * span) >> 64);
    const std::int64_t x = std::int64_t(std::uint64_t(lo) + k);
    if (f->log_) f->log_->push_back(x);
    return x;
  }
  if (Replay* r = t_replay) {
    const std::size_t at = r->next_++;
    const std::int64_t root = at < r->values_.size() ? std::clamp(r->values_[at], lo, hi) : lo;
    return *rooted(lo, root);
  }
  return *rc::gen::inRange<std::int64_t>(lo, hi + 1);
}

constexpr std::int64_t kSteps = std::int64_t(1) << 30;

double unit() { return double(integer(0, kSteps)) / double(kSteps); }
double in(double lo, double hi) { return lo + (hi - lo) * unit(); }
double log_in(double lo_exp10, double hi_exp10) { return std::pow(10.0, in(lo_exp10, hi_exp10)); }
bool coin(int percent_true) { return integer(0, 99) < percent_true; }
int pick(int n) { return int(integer(0, n - 1)); }

glm::dvec3 unit_vector() {
  const double z = in(-1.0, 1.0), a = in(0.0, 2.0 * M_PI), s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(a), s * std::sin(a), z};
}

// A rotation from three uniforms (Shoemake), as a float matrix: orthonormal only up to rounding.
glm::mat3 rotation() {
  const double u1 = unit(), u2 = in(0, 2 * M_PI), u3 = in(0, 2 * M_PI);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  const glm::quat q(float(a * std::sin(u2)), float(a * std::cos(u2)), float(b * std::sin(u3)), float(b * std::cos(u3)));
  return glm::mat3_cast(glm::normalize(q));
}

glm::mat4 reverse_depth(const glm::mat4& proj, DepthRange range) {
  glm::mat4 r(1.0f);
  r[2][2] = -1.0f;
  if (range == DepthRange::zero_to_one) r[3][2] = 1.0f;
  return r * proj;
}


glm::mat4 projection(const Camera& c, bool finite_only) {
  glm::mat4 p;
  const bool inf = c.infinite && !finite_only && !c.ortho;
  const float f = (c.infinite && finite_only) ? c.n * 1000.0f : c.f;
  if (c.ortho) {
    p = c.depth.range == DepthRange::negative_one_to_one ? glm::orthoRH_NO(c.l, c.r, c.b, c.t, c.n, f)
                                                         : glm::orthoRH_ZO(c.l, c.r, c.b, c.t, c.n, f);
  } else if (!inf) {
    p = c.depth.range == DepthRange::negative_one_to_one ? glm::frustumRH_NO(c.l, c.r, c.b, c.t, c.n, f)
                                                         : glm::frustumRH_ZO(c.l, c.r, c.b, c.t, c.n, f);
  } else {
    // The limit of frustumRH_* as far -> infinity: r3 = (0, 0, -1, -2n) or (0, 0, -1, -n).
    p = glm::mat4(0.0f);
    p[0][0] = 2.0f * c.n / (c.r - c.l);
    p[1][1] = 2.0f * c.n / (c.t - c.b);
    p[2][0] = (c.r + c.l) / (c.r - c.l);
    p[2][1] = (c.t + c.b) / (c.t - c.b);
    p[2][2] = -1.0f;
    p[2][3] = -1.0f;
    p[3][2] = c.depth.range == DepthRange::negative_one_to_one ? -2.0f * c.n : -c.n;
  }
  return c.depth.reversed_z ? reverse_depth(p, c.depth.range) : p;
}

glm::mat4 view_matrix(const Camera& c) { return glm::lookAtRH(c.eye, c.eye + c.dir, c.up); }


Placement placement_of(const Frustum& f) {
  Placement p;
  if (!is_bounded(f)) return p;
  p.corner = frustum_corners(f);
  for (const auto& c : p.corner) p.center += c / 8.0;
  for (const auto& a : p.corner)
    for (const auto& b : p.corner) p.size = std::max(p.size, glm::length(a - b));
  p.ok = std::isfinite(p.size) && p.size > 0.0;
  return p;
}

CaseFrustum realize(const Camera& c) {
  const glm::mat4 vp = projection(c, false) * view_matrix(c);
  CaseFrustum f = frustum_spec(vp, c.depth);
  if (!c.as_matrix) {
    f.matrix.reset();
    if (c.normalize) f.planes = f.planes.normalized();
  }
  return f;
}

Placement placement_for(const Camera& c) {
  Camera finite = c;
  finite.depth = {};
  const Frustum f = frustum_from_matrix(projection(finite, true) * view_matrix(c));
  Placement p = placement_of(f);
  if (!p.ok) {  // numerically degenerate: place around the view axis
    p.center = glm::dvec3(c.eye) + glm::dvec3(c.dir) * double(c.n) * 2.0;
    p.size = std::max(1e-3, double(c.n) * 4.0);
    for (int i = 0; i < 8; ++i)
      p.corner[static_cast<std::size_t>(i)] =
          p.center + p.size * 0.5 * glm::dvec3((i & 1) ? 1 : -1, (i & 2) ? 1 : -1, (i & 4) ? 1 : -1);
    p.ok = true;
  }
  return p;
}

// The generic camera: anywhere, looking anywhere.
Camera generic_camera() {
  Camera c;
  for (int i = 0; i < 3; ++i) c.eye[i] = coin(20) ? 0.0f : float((coin(50) ? 1 : -1) * log_in(-2, 3));
  c.dir = glm::vec3(unit_vector());
  glm::vec3 up = glm::vec3(unit_vector());
  if (glm::length(glm::cross(up, c.dir)) < 0.2f) {
    // Too close to the view direction: use the axis least aligned with it.
    const glm::vec3 a = glm::abs(c.dir);
    up = a.x <= a.y && a.x <= a.z ? glm::vec3(1, 0, 0) : a.y <= a.z ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  }
  c.up = up;
  c.n = float(log_in(-2, 0.7));
  c.f = c.n * float(log_in(1, 3));
  const int kind = pick(10);  // 0-5 symmetric, 6-7 off-axis, 8-9 orthographic
  const float aspect = float(in(0.4, 2.5));
  if (kind < 8) {
    const float fovy = float(in(15, 120));
    const float t = c.n * std::tan(glm::radians(fovy) / 2.0f);
    c.t = t;
    c.b = -t;
    c.r = t * aspect;
    c.l = -c.r;
    if (kind >= 6) {  // off-axis: shift the window (stereo, CAVE walls, Hoff's off-axis COP)
      const float sx = float(in(-0.9, 0.9)) * c.r, sy = float(in(-0.5, 0.5)) * c.t;
      c.l += sx;
      c.r += sx;
      c.b += sy;
      c.t += sy;
    }
    c.infinite = coin(15);
  } else {
    c.ortho = true;
    const float h = float(log_in(-1, 2));
    c.t = h;
    c.b = -h;
    c.r = h * aspect;
    c.l = -c.r;
  }
  c.depth.range = coin(50) ? DepthRange::negative_one_to_one : DepthRange::zero_to_one;
  c.depth.reversed_z = coin(25);
  c.as_matrix = coin(40);
  c.normalize = coin(30);
  return c;
}

// Volumes ------------------------------------------------------------------------------------


Shape any_shape() {
  const int k = pick(20);
  return k < 2 ? Shape::point : k < 6 ? Shape::sphere : k < 13 ? Shape::aabb : Shape::obb;
}

// A volume of the given shape centred at c with typical half-size s (each axis 0.1..1 of s).
Volume volume_at(Shape shape, const glm::dvec3& c, double s) {
  const glm::vec3 cf(c);
  switch (shape) {
    case Shape::point: return Point(cf);
    case Shape::sphere: return Sphere{cf, float(s * in(0.1, 1.0))};
    case Shape::aabb: {
      const glm::dvec3 h(s * in(0.1, 1), s * in(0.1, 1), s * in(0.1, 1));
      return Aabb{glm::vec3(c - h), glm::vec3(c + h)};
    }
    case Shape::obb: break;
  }
  return Obb{cf, rotation(), glm::vec3(float(s * in(0.1, 1)), float(s * in(0.1, 1)), float(s * in(0.1, 1)))};
}

// Corners of face k of a placement frustum (docs/semantics.md plane order), and its outward normal.
const int kFaceCorners[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};

glm::dvec3 point_on_face(const Placement& p, int face) {
  const double u = unit(), v = unit();
  const auto& k = kFaceCorners[face];
  const glm::dvec3 a = glm::mix(p.corner[k[0]], p.corner[k[1]], u), b = glm::mix(p.corner[k[3]], p.corner[k[2]], u);
  return glm::mix(a, b, v);
}

glm::dvec3 outward(const Placement& p, int face) {
  const auto& k = kFaceCorners[face];
  glm::dvec3 n = glm::cross(p.corner[k[1]] - p.corner[k[0]], p.corner[k[3]] - p.corner[k[0]]);
  if (glm::length(n) == 0.0) return glm::normalize(glm::mix(p.corner[k[0]], p.corner[k[2]], 0.5) - p.center);
  n = glm::normalize(n);
  const glm::dvec3 face_c = (p.corner[k[0]] + p.corner[k[2]]) * 0.5;
  return glm::dot(n, face_c - p.center) < 0 ? -n : n;
}

double rel_size(double lo_exp, double hi_exp) { return log_in(lo_exp, hi_exp); }

Volume near_boundary(const Placement& p, Shape shape, double s) {
  const int face = pick(6);
  const glm::dvec3 x = point_on_face(p, face) + outward(p, face) * (s * in(-2.5, 2.5));
  return volume_at(shape, x, s);
}

Volume near_corner(const Placement& p, Shape shape, double s) {
  glm::dvec3 x, out;
  if (coin(60)) {  // an edge: two corners differing in one index bit
    const int i = pick(8), bit = 1 << pick(3);
    const int j = i ^ bit;
    x = glm::mix(p.corner[i], p.corner[j], unit());
    out = glm::normalize((p.corner[i] + p.corner[j]) * 0.5 - p.center);
  } else {
    const int i = pick(8);
    x = p.corner[i];
    out = glm::normalize(p.corner[i] - p.center);
  }
  return volume_at(shape, x + out * (s * in(0.2, 2.0)), s);
}

GenCase make(const Camera& cam, const Placement& p, Volume v) {
  GenCase g;
  g.frustum = realize(cam);
  g.volume = std::move(v);
  g.scene_size = p.size;
  return g;
}

// The largest coordinate magnitude of a volume, its extent included (double: no overflow).
double volume_magnitude(const Volume& v) {
  double m = 0.0;
  auto vec = [&](const glm::vec3& x, double extra) {
    for (int i = 0; i < 3; ++i) m = std::max(m, double(std::abs(x[i])) + extra);
  };
  std::visit(
      [&](const auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) {
          vec(x, 0.0);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          vec(x.center, x.radius);
        } else if constexpr (std::is_same_v<T, Aabb>) {
          vec(x.min, 0.0);
          vec(x.max, 0.0);
        } else {
          double e = 0.0;
          for (int a = 0; a < 3; ++a) e += double(x.half[a]) * glm::length(glm::dvec3(x.axes[a]));
          vec(x.center, e);
        }
      },
      v);
  return m;
}

}  // namespace cullproof::gen::detail

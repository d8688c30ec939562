// Case generators (see cullproof/generators.hpp).
#include "cullproof/generators.hpp"

#include "cullproof/certified.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include <array>
#include <functional>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace cullproof::gen {

// ---------------------------------------------------------------------------------------------
// Names

namespace {

struct Info {
  Distribution d;
  const char* name;
  const char* text;
};

constexpr Info kInfo[] = {
    {Distribution::uniform, "uniform", "volumes of all sizes anywhere around the frustum"},
    {Distribution::near_boundary, "near-boundary", "within a few box sizes of a frustum face"},
    {Distribution::corner, "corner", "near frustum edges and corners, where n/p tests err (Assarsson & Moller fig. 2)"},
    {Distribution::enclosing, "enclosing", "volumes about as large as the frustum, often containing it"},
    {Distribution::tiny_huge, "tiny-huge", "sizes from 1e-7 to 10 times the frustum"},
    {Distribution::degenerate, "degenerate", "flat, segment and point boxes, zero-radius spheres, points"},
    {Distribution::touch, "touch", "exactly touching a plane at a face, an edge or a vertex (exact values)"},
    {Distribution::ulp, "ulp", "touching, then moved 1 ulp in or out"},
    {Distribution::far_offset, "far-offset", "camera and small volumes at world coordinates 1e5 to 1e7"},
    {Distribution::tiny_near, "tiny-near", "near 1e-4..1e-2, far 1e3..1e7, end-to-end from the float32 matrix"},
    {Distribution::reversed_infinite, "reversed-infinite", "reversed-Z and infinite far, both depth ranges"},
    {Distribution::extreme_fov, "extreme-fov", "fov 0.01..179.9 degrees, aspect 1e-3..1e3"},
    {Distribution::ill_conditioned, "ill-conditioned", "planes scaled by huge/tiny factors, skewed OBB axes"},
    {Distribution::rod, "rod", "long thin boxes crossing the frustum with no corner inside"},
    {Distribution::contact, "contact",
     "float-exact contact: flat boxes in a face, boxes, points and spheres touching faces, edges and corners"},
    {Distribution::camera_path, "camera-path",
     "a camera moving past fixed volumes (still, translating, turning, zooming), frame by frame"},
    {Distribution::huge, "huge",
     "coordinates, extents, radii, plane coefficients and matrix entries up to FLT_MAX, where float sums overflow"},
    {Distribution::subnormal, "subnormal",
     "subnormal sizes, distances to a face, plane coefficients and matrix entries, where products underflow"},
};

}  // namespace

std::string_view to_string(Distribution d) noexcept {
  for (const Info& i : kInfo)
    if (i.d == d) return i.name;
  return "invalid";
}

std::string_view describe(Distribution d) noexcept {
  for (const Info& i : kInfo)
    if (i.d == d) return i.text;
  return "";
}

std::vector<Distribution> generic_distributions() {
  return {Distribution::uniform,    Distribution::near_boundary, Distribution::corner,
          Distribution::enclosing,  Distribution::tiny_huge,     Distribution::degenerate,
          Distribution::contact,    Distribution::camera_path};
}

std::vector<Distribution> hard_distributions() {
  return {Distribution::touch, Distribution::ulp, Distribution::far_offset, Distribution::tiny_near,
          Distribution::reversed_infinite, Distribution::degenerate, Distribution::extreme_fov,
          Distribution::ill_conditioned, Distribution::rod, Distribution::corner, Distribution::huge,
          Distribution::subnormal};
}

std::vector<Distribution> no_overflow_distributions() {
  std::vector<Distribution> out;
  for (const Info& i : kInfo)
    if (i.d != Distribution::huge) out.push_back(i.d);
  return out;
}

std::vector<Distribution> parse_distributions(std::string_view name) {
  if (name == "all") {
    std::vector<Distribution> all;
    for (const Info& i : kInfo) all.push_back(i.d);
    return all;
  }
  if (name == "all-hard") return hard_distributions();
  if (name == "all-generic") return generic_distributions();
  for (const Info& i : kInfo)
    if (name == i.name) return {i.d};
  std::string known = "all, all-generic, all-hard";
  for (const Info& i : kInfo) known += std::string(", ") + i.name;
  throw std::invalid_argument("unknown distribution '" + std::string(name) + "' (known: " + known + ")");
}

// ---------------------------------------------------------------------------------------------
// Building blocks

namespace {

constexpr std::int64_t kSteps = std::int64_t(1) << 30;

// A double in [0, 1], shrinking towards 0.
rc::Gen<double> unit() {
  return rc::gen::map(rc::gen::inRange<std::int64_t>(0, kSteps + 1),
                      [](std::int64_t k) { return double(k) / double(kSteps); });
}
double in(double lo, double hi) { return lo + (hi - lo) * *unit(); }
double log_in(double lo_exp10, double hi_exp10) { return std::pow(10.0, in(lo_exp10, hi_exp10)); }
bool coin(int percent_true) { return *rc::gen::inRange(0, 100) < percent_true; }
int pick(int n) { return *rc::gen::inRange(0, n); }

glm::dvec3 unit_vector() {
  const double z = in(-1.0, 1.0), a = in(0.0, 2.0 * M_PI), s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {s * std::cos(a), s * std::sin(a), z};
}

// A rotation from three uniforms (Shoemake), as a float matrix: orthonormal only up to rounding.
glm::mat3 rotation() {
  const double u1 = *unit(), u2 = in(0, 2 * M_PI), u3 = in(0, 2 * M_PI);
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

// What a camera generator decides; the matrix and the planes follow from it.
struct Camera {
  glm::vec3 eye{0.0f};
  glm::vec3 dir{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  bool ortho = false;
  float l = -1, r = 1, b = -1, t = 1;  // window at the near plane (ortho: the box)
  float n = 1, f = 100;
  bool infinite = false;
  DepthConvention depth;
  bool as_matrix = false;
  bool normalize = false;
};

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

// The frustum's bounded part used to place volumes (an infinite far plane is brought in to
// 1000 near distances); corners in double.
struct Placement {
  std::array<glm::dvec3, 8> corner{};
  glm::dvec3 center{0.0};
  double size = 1.0;  // diameter
  bool ok = false;
};

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

enum class Shape { point, sphere, aabb, obb };

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
  const double u = *unit(), v = *unit();
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
    x = glm::mix(p.corner[i], p.corner[j], *unit());
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

// A volume of generic distribution d around placement p (its draws follow the camera's).
Volume generic_volume(Distribution d, const Placement& p) {
  const Shape shape = d == Distribution::degenerate ? Shape::aabb : any_shape();
  switch (d) {
    case Distribution::uniform: {
      const glm::dvec3 x = p.center + p.size * 0.75 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1));
      return volume_at(shape, x, p.size * rel_size(-3, -0.5));
    }
    case Distribution::near_boundary: return near_boundary(p, shape, p.size * rel_size(-3, -1));
    case Distribution::corner: return near_corner(p, shape, p.size * rel_size(-3, -1));
    case Distribution::enclosing: {
      const glm::dvec3 x = p.center + p.size * 0.2 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1));
      return volume_at(shape == Shape::point ? Shape::aabb : shape, x, p.size * in(0.5, 1.5));
    }
    case Distribution::tiny_huge: {
      const double s = p.size * rel_size(-7, 1);
      return coin(50) ? near_boundary(p, shape, s)
                      : volume_at(shape, p.center + p.size * 0.6 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1)), s);
    }
    case Distribution::degenerate: {
      const double s = p.size * rel_size(-3, -1);
      Volume v = coin(50) ? near_boundary(p, Shape::aabb, s) : near_corner(p, Shape::aabb, s);
      const int kind = pick(6);
      if (kind == 0) return Point(std::get<Aabb>(v).center());
      if (kind == 1) return Sphere{std::get<Aabb>(v).center(), 0.0f};
      Aabb b = std::get<Aabb>(v);
      const int keep = kind == 2 ? 0 : kind == 3 ? 1 : 2;  // 2: point box, 3: segment, 4-5: flat
      for (int a = 0, kept = 0; a < 3; ++a) {
        const bool flat = kept >= keep;
        if (!flat) {
          ++kept;
          continue;
        }
        b.min[a] = b.max[a] = b.center()[a];
      }
      if (coin(50)) return to_obb(b);
      return b;
    }
    default: break;
  }
  return volume_at(shape, p.center, p.size * 0.1);
}

GenCase generic_case(Distribution d) {
  const Camera cam = generic_camera();
  const Placement p = placement_for(cam);
  return make(cam, p, generic_volume(d, p));
}

// Exact touching --------------------------------------------------------------------------------
//
// View space frustum with integer planes: glm::frustum(-n, n, -n, n, n, f) in [-1,1], so
// |x| <= -z, |y| <= -z, z in [-f, -n]; f/n in {2, 3, 5, 9} keeps every matrix entry dyadic. The
// world transform is an axis permutation with signs and an integer translation: exact.
struct ExactFrame {
  glm::mat3 rot{1.0f};  // world = rot * view + shift
  glm::vec3 shift{0.0f};
  float n = 1, f = 3;
};

ExactFrame exact_frame() {
  ExactFrame e;
  static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const int* perm = kPerm[pick(6)];
  glm::mat3 r(0.0f);
  for (int i = 0; i < 3; ++i) r[i][perm[i]] = coin(50) ? 1.0f : -1.0f;
  e.rot = r;
  e.shift = glm::vec3(float(*rc::gen::inRange(-64, 65)), float(*rc::gen::inRange(-64, 65)), float(*rc::gen::inRange(-64, 65)));
  static const float kN[3] = {0.5f, 1.0f, 2.0f}, kRatio[4] = {2, 3, 5, 9};
  e.n = kN[pick(3)];
  e.f = e.n * kRatio[pick(4)];
  return e;
}

// The view matrix of a frame: the inverse of (world = rot * view + shift), [rot^T | -rot^T shift].
glm::mat4 view_of(const ExactFrame& e) {
  glm::mat4 v(glm::transpose(e.rot));
  v[3] = glm::vec4(-(glm::transpose(e.rot) * e.shift), 1.0f);
  return v;
}

CaseFrustum exact_frustum(const ExactFrame& e, bool as_matrix) {
  const glm::mat4 p = glm::frustumRH_NO(-e.n, e.n, -e.n, e.n, e.n, e.f);
  CaseFrustum f = frustum_spec(p * view_of(e), {});
  if (!as_matrix) f.matrix.reset();
  return f;
}

glm::vec3 to_world(const ExactFrame& e, glm::vec3 v) { return e.rot * v + e.shift; }

Aabb world_box(const ExactFrame& e, glm::vec3 lo, glm::vec3 hi) {
  const glm::vec3 a = to_world(e, lo), b = to_world(e, hi);
  return Aabb{glm::min(a, b), glm::max(a, b)};
}

// A dyadic value in [lo, hi] with at most 4 fractional bits.
float dyadic(float lo, float hi) {
  const int steps = int((hi - lo) * 16.0f);
  return lo + float(*rc::gen::inRange(0, steps + 1)) / 16.0f;
}

// `frustum`: how the case's frustum is made from its frame (unset: the touch family's, planes or
// an OpenGL matrix).
GenCase touch_case(bool nudge, const std::function<CaseFrustum(const ExactFrame&)>& frustum = nullptr) {
  const ExactFrame e = exact_frame();
  const float n = e.n, f = e.f;
  const float h = dyadic(0.0625f, 0.5f) * n;
  glm::vec3 lo, hi;
  float* moved = nullptr;
  int kind = pick(7);
  switch (kind) {
    case 0:  // face on the near plane, from outside (intersecting)
      lo = {-h, -h, -n};
      hi = {h, h, -n + h};
      moved = &lo.z;
      break;
    case 1:  // face on the near plane, from inside (inside)
      lo = {-h, -h, -n - h};
      hi = {h, h, -n};
      moved = &hi.z;
      break;
    case 2:  // face on the far plane, from outside
      lo = {-h, -h, -f - h};
      hi = {h, h, -f};
      moved = &hi.z;
      break;
    case 3: {  // an edge on the right plane x = -z, from outside
      const float a = dyadic(n, f);
      lo = {a, -h, -a};
      hi = {a + h, h, -a + h};
      moved = &lo.x;
      break;
    }
    case 4: {  // a vertex on the lateral edge x = y = -z, from outside
      const float a = dyadic(n, f);
      lo = {a, a, -a};
      hi = {a + h, a + h, -a + h};
      moved = &lo.y;
      break;
    }
    case 5:  // a frustum corner (n, n, -n) touching a box corner from outside
      lo = {n, n, -n};
      hi = {n + h, n + h, -n + h};
      moved = &lo.x;
      break;
    default: {  // a box inside touching the left plane x = z along an edge
      // Left plane x - z >= 0; the box's min x equals its max z: touching from inside.
      const float a = dyadic(n, f - h);
      lo = {-a, -h, -a - h};
      hi = {-a + h, h, -a};
      moved = &hi.z;
      break;
    }
  }
  if (nudge) *moved = std::nextafter(*moved, coin(50) ? std::numeric_limits<float>::infinity()
                                                     : -std::numeric_limits<float>::infinity());
  GenCase g;
  g.frustum = frustum ? frustum(e) : exact_frustum(e, coin(30));
  g.scene_size = 2.0 * f * std::sqrt(3.0);
  const Aabb box = world_box(e, lo, hi);
  const int shape = pick(10);
  if (shape < 5) {
    g.volume = box;
  } else if (shape < 8) {
    g.volume = to_obb(box);
  } else if (shape == 8) {  // the touching corner or face centre as a point (on the plane: inside)
    g.volume = Point(to_world(e, kind == 4 || kind == 5 ? lo : glm::vec3(0.0f, 0.0f, kind == 2 ? -f : -n)));
  } else {  // a sphere touching the near or far plane
    const float r = h;
    const float z = kind == 2 ? -f - r : -n + r;
    g.volume = Sphere{to_world(e, {0.0f, 0.0f, nudge ? std::nextafter(z, 0.0f) : z}), r};
  }
  return g;
}

// Float-exact contact ------------------------------------------------------------------------------
//
// Every value a plane test computes is a float (see float_exact): dyadic coordinates of a few
// bits on frusta whose planes have small dyadic coefficients, moved to the world by an axis
// permutation with signs and an integer shift. Two frustum kinds:
//  - orthographic boxes |x| <= w, |y| <= w, z in [-f, -n] (w, f - n powers of two), given as
//    unit planes (so that spheres are exact too) or as a matrix in any depth convention;
//  - the integer perspective frustum of the touch family, as planes or as a matrix in any depth
//    convention, with a finite or an infinite far plane.
// Volumes meet the frustum's boundary: flat boxes lying in a face (inside), boxes touching a face,
// an edge or a vertex from outside (intersecting) or from inside (inside), points on faces, edges
// and corners, spheres tangent to a face from either side, OBBs with permuted axes.

DepthConvention any_depth() {
  DepthConvention d;
  d.range = coin(50) ? DepthRange::negative_one_to_one : DepthRange::zero_to_one;
  d.reversed_z = coin(30);
  return d;
}

// A view-space plane (inside: n.x + d >= 0) in the world of e: exact for a unit axis normal.
Plane world_plane(const ExactFrame& e, glm::vec3 n, float d) {
  const glm::vec3 nw = e.rot * n;
  return Plane{nw, d - glm::dot(nw, e.shift)};
}

Obb permuted_obb(const ExactFrame& e, const Aabb& view_box) {
  // The box itself, described with a permuted, sign-flipped frame: axes are columns of a signed
  // permutation, half-extents permuted to match. Corners and projections stay exact.
  static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const int* perm = kPerm[pick(6)];
  const Aabb w = world_box(e, view_box.min, view_box.max);
  const glm::vec3 c = (w.min + w.max) * 0.5f, h = (w.max - w.min) * 0.5f;
  Obb o;
  o.center = c;
  for (int i = 0; i < 3; ++i) {
    glm::vec3 axis(0.0f);
    axis[perm[i]] = coin(50) ? 1.0f : -1.0f;
    o.axes[i] = axis;
    o.half[i] = h[perm[i]];
  }
  return o;
}

GenCase contact_ortho() {
  const ExactFrame e = exact_frame();
  const float w = std::ldexp(1.0f, *rc::gen::inRange(-1, 3));  // 0.5 .. 4
  const float n = e.n, f = n + std::ldexp(1.0f, *rc::gen::inRange(0, 5));
  const int shape = pick(10);  // 0-3 box, 4-5 OBB, 6-7 point, 8-9 sphere
  // Face coordinates per view axis: the inside is [lo, hi].
  const glm::vec3 lo(-w, -w, -f), hi(w, w, -n);
  const float s = dyadic(0.0625f, 0.5f) * std::min(w, f - n);  // volume size, below the frustum's
  glm::vec3 a, b, contact;
  // Contact: choose how many axes (1 face, 2 edge, 3 vertex) sit on the boundary, on which side.
  const int axes_on = 1 + pick(3);
  const bool from_outside = coin(50);
  const bool flat = shape < 4 && axes_on == 1 && coin(30);  // a flat box lying in the face
  int first = pick(3);
  for (int k = 0; k < 3; ++k) {
    const int ax = (first + k) % 3;
    if (k < axes_on) {
      const bool high = coin(50);
      const float face = high ? hi[ax] : lo[ax];
      const bool out_is_up = high;  // outside lies above hi, below lo
      contact[ax] = face;
      if (flat) {
        a[ax] = b[ax] = face;
      } else if (from_outside == out_is_up) {
        a[ax] = face, b[ax] = face + s;
      } else {
        a[ax] = face - s, b[ax] = face;
      }
    } else {  // well within the face's extent along this axis
      const float span = hi[ax] - lo[ax];
      const float c = lo[ax] + span * 0.5f + dyadic(-0.25f, 0.25f) * span;
      const float half = std::min(s, span * 0.125f);
      a[ax] = c - half, b[ax] = c + half;
      contact[ax] = c;
    }
  }
  GenCase g;
  g.scene_size = 2.0 * std::sqrt(2.0 * w * w + (f - n) * (f - n) / 4.0);
  const bool planes_form = shape >= 8 || coin(50);
  if (planes_form) {
    Frustum fr;
    fr.planes[kLeft] = world_plane(e, {1, 0, 0}, w);
    fr.planes[kRight] = world_plane(e, {-1, 0, 0}, w);
    fr.planes[kBottom] = world_plane(e, {0, 1, 0}, w);
    fr.planes[kTop] = world_plane(e, {0, -1, 0}, w);
    fr.planes[kNear] = world_plane(e, {0, 0, -1}, -n);
    fr.planes[kFar] = world_plane(e, {0, 0, 1}, f);
    g.frustum = frustum_spec(fr);
  } else {
    const DepthConvention depth = any_depth();
    glm::mat4 p = depth.range == DepthRange::negative_one_to_one ? glm::orthoRH_NO(-w, w, -w, w, n, f)
                                                                  : glm::orthoRH_ZO(-w, w, -w, w, n, f);
    if (depth.reversed_z) p = reverse_depth(p, depth.range);
    g.frustum = frustum_spec(p * view_of(e), depth);
  }
  const Aabb box{glm::min(a, b), glm::max(a, b)};
  if (shape < 4) {
    g.volume = world_box(e, box.min, box.max);
  } else if (shape < 6) {
    g.volume = permuted_obb(e, box);
  } else if (shape < 8) {
    // The contact point: on a face, an edge or at a frustum corner (inside).
    g.volume = Point(to_world(e, contact));
  } else {
    // A sphere tangent to the first contact face, from outside or inside.
    const int ax = first;
    const bool high = a[ax] == hi[ax] || b[ax] == hi[ax];
    const float face = high ? hi[ax] : lo[ax];
    const float r = s * 0.5f;
    glm::vec3 c;
    for (int k = 0; k < 3; ++k) c[k] = (lo[k] + hi[k]) * 0.5f;
    c[ax] = face + ((from_outside == high) ? r : -r);
    g.volume = Sphere{to_world(e, c), r};
  }
  return g;
}

GenCase contact_perspective() {
  // The touch family's contacts on its integer frustum, in any depth convention, with a finite or
  // an infinite far plane, as planes or as the matrix. A sphere (the lateral planes' normals are
  // not unit) becomes its bounding box, which keeps the contact with a near or far face.
  const DepthConvention depth = any_depth();
  const bool infinite = coin(25), as_matrix = coin(50);
  GenCase g = touch_case(false, [&](const ExactFrame& e) {
    glm::mat4 p;
    if (infinite) {
      p = glm::mat4(0.0f);
      p[0][0] = p[1][1] = 1.0f;  // 2n / (r - l) with r - l = 2n
      p[2][2] = -1.0f;
      p[2][3] = -1.0f;
      p[3][2] = depth.range == DepthRange::negative_one_to_one ? -2.0f * e.n : -e.n;
    } else {
      p = depth.range == DepthRange::negative_one_to_one ? glm::frustumRH_NO(-e.n, e.n, -e.n, e.n, e.n, e.f)
                                                         : glm::frustumRH_ZO(-e.n, e.n, -e.n, e.n, e.n, e.f);
    }
    if (depth.reversed_z) p = reverse_depth(p, depth.range);
    CaseFrustum f = frustum_spec(p * view_of(e), depth);
    if (!as_matrix) f.matrix.reset();
    return f;
  });
  if (const Sphere* sp = std::get_if<Sphere>(&g.volume)) g.volume = Aabb{sp->center - sp->radius, sp->center + sp->radius};
  return g;
}

GenCase contact_case() { return coin(50) ? contact_ortho() : contact_perspective(); }

// Hard families on the generic camera ------------------------------------------------------------

GenCase hard_case(Distribution d) {
  Camera cam = generic_camera();
  switch (d) {
    case Distribution::far_offset: {
      for (int i = 0; i < 3; ++i) cam.eye[i] = float((coin(50) ? 1 : -1) * log_in(5, 7));
      cam.n = float(log_in(-1, 0));
      cam.f = float(log_in(2, 3));
      if (cam.ortho) cam.ortho = false, cam.l = -cam.n, cam.r = cam.n, cam.b = -cam.n, cam.t = cam.n;
      const Placement p = placement_for(cam);
      return make(cam, p, coin(50) ? near_boundary(p, any_shape(), log_in(-2, 1)) : near_corner(p, any_shape(), log_in(-2, 1)));
    }
    case Distribution::tiny_near: {
      cam.ortho = false;
      cam.infinite = false;
      cam.n = float(log_in(-4, -2));
      cam.f = float(log_in(3, 7));
      const float t = cam.n * std::tan(glm::radians(float(in(20, 110))) / 2.0f), a = float(in(0.5, 2.2));
      cam.t = t, cam.b = -t, cam.r = t * a, cam.l = -t * a;
      cam.as_matrix = true;
      // Place near the planes close to the eye: a slice at depth between near and 1000 near.
      Camera slice = cam;
      slice.f = cam.n * float(log_in(0.3, 3));
      slice.depth = {};
      const Placement p = placement_for(slice);
      const Placement whole = placement_for(cam);
      GenCase g = make(cam, p, coin(60) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                                        : near_corner(p, any_shape(), p.size * rel_size(-3, -1)));
      g.scene_size = whole.size;
      return g;
    }
    case Distribution::reversed_infinite: {
      if (cam.ortho) cam.ortho = false, cam.l = -cam.n, cam.r = cam.n, cam.b = -cam.n, cam.t = cam.n;
      cam.infinite = true;
      cam.depth.reversed_z = coin(70);
      cam.as_matrix = coin(60);
      const Placement p = placement_for(cam);
      return make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                                   : volume_at(any_shape(), p.center + p.size * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1)),
                                               p.size * rel_size(-3, 0)));
    }
    case Distribution::extreme_fov: {
      cam.ortho = false;
      const float fovy = float(coin(50) ? log_in(-2, 1) : in(120, 179.9));
      const float aspect = float(log_in(-3, 3));
      const float t = cam.n * std::tan(glm::radians(fovy) / 2.0f);
      cam.t = t, cam.b = -t, cam.r = t * aspect, cam.l = -t * aspect;
      const Placement p = placement_for(cam);
      return make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-4, -1))
                                   : near_corner(p, any_shape(), p.size * rel_size(-4, -1)));
    }
    case Distribution::ill_conditioned: {
      cam.as_matrix = false;
      cam.normalize = false;
      const Placement p = placement_for(cam);
      GenCase g = make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                                        : near_corner(p, any_shape(), p.size * rel_size(-3, -1)));
      for (Plane& pl : g.frustum.planes.planes) {
        // Powers of two keep the half-space exactly; other factors round every coefficient.
        const double k = coin(50) ? std::ldexp(1.0, *rc::gen::inRange(-60, 61)) : log_in(-18, 18);
        pl.n = glm::vec3(glm::dvec3(pl.n) * k);
        pl.d = float(double(pl.d) * k);
      }
      if (Obb* o = std::get_if<Obb>(&g.volume)) {
        for (int a = 0; a < 3; ++a)  // visibly non-orthonormal axes
          o->axes[a] = glm::vec3(glm::dvec3(o->axes[a]) + unit_vector() * log_in(-4, -2));
      }
      return g;
    }
    case Distribution::rod: {
      // A bounded frustum, so that both ends of a rod longer than the frustum lie outside it;
      // the rod passes through a point inside (slid along its own axis).
      cam.infinite = false;
      const Placement p = placement_for(cam);
      const glm::dvec3 through = glm::mix(p.center, p.corner[pick(8)], in(0, 0.6));
      const double len = p.size * in(1.5, 4), thick = p.size * log_in(-4, -2);
      Obb o;
      if (coin(30)) {
        const int a = pick(3);
        glm::dvec3 axis(0.0);
        axis[a] = 1.0;
        o.center = glm::vec3(through + axis * (len * in(-0.3, 0.3)));
        o.half = glm::vec3(float(thick));
        o.half[a] = float(len);
        return make(cam, p, Aabb{o.center - o.half, o.center + o.half});
      }
      o.axes = rotation();
      o.center = glm::vec3(through + glm::dvec3(o.axes[0]) * (len * in(-0.3, 0.3)));
      o.half = glm::vec3(float(len), float(thick), float(thick * in(0.2, 1)));
      return make(cam, p, o);
    }
    default: break;
  }
  return generic_case(d);
}

// The whole float range ------------------------------------------------------------------------
//
// Generic scenes carried to the ends of the float range by exact scalings, and volumes and
// planes as large as a float gets:
//  - huge: coordinates, extents, radii, plane coefficients and matrix entries up to FLT_MAX,
//    where max - min, min + max, n.x + d, an OBB's corners and the Gribb-Hartmann row sums
//    overflow;
//  - subnormal: scenes whose sizes, distances to a face, plane coefficients or matrix entries
//    are subnormal, where the products of a plane test underflow.
// A scaling by 2^k is exact while the values stay normal floats; into the subnormal range they
// round, monotonically (a box stays a box, a radius stays >= 0), and the case is what the rounded
// floats describe. Every case is valid (finite floats): a scaling that would overflow is taken
// one power of two smaller.

constexpr float kFltMax = std::numeric_limits<float>::max();

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

// Whether every value of the case is finite (the extracted planes of a matrix case included).
bool finite_case(const GenCase& g) {
  if (g.frustum.matrix)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite((*g.frustum.matrix)[c][r])) return false;
  return is_valid(g.frustum.planes) && is_valid(g.volume);
}

float times2(float x, int k) { return std::ldexp(x, k); }
glm::vec3 times2(const glm::vec3& x, int k) { return {times2(x.x, k), times2(x.y, k), times2(x.z, k)}; }

// The case in a world scaled by 2^k (x -> 2^k x): planes (n, 2^k d); a matrix's translation
// column times 2^k (its clip coordinates are 2^k times the old ones: the same frustum); the
// volume's coordinates, radius and half-extents times 2^k.
GenCase scale_world(GenCase g, int k) {
  if (g.frustum.matrix) {
    glm::mat4 m = *g.frustum.matrix;
    for (int r = 0; r < 4; ++r) m[3][r] = times2(m[3][r], k);
    g.frustum = frustum_spec(m, g.frustum.depth);
  } else {
    for (Plane& p : g.frustum.planes.planes) p.d = times2(p.d, k);
  }
  std::visit(
      [&](auto& x) {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, Point>) {
          x = times2(x, k);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          x.center = times2(x.center, k), x.radius = times2(x.radius, k);
        } else if constexpr (std::is_same_v<T, Aabb>) {
          x.min = times2(x.min, k), x.max = times2(x.max, k);
        } else {
          x.center = times2(x.center, k), x.half = times2(x.half, k);
        }
      },
      g.volume);
  g.scene_size = std::ldexp(g.scene_size, k);
  return g;
}

Placement scale_placement(Placement p, int k) {
  for (auto& c : p.corner) c = glm::ldexp(c, glm::ivec3(k));
  p.center = glm::ldexp(p.center, glm::ivec3(k));
  p.size = std::ldexp(p.size, k);
  return p;
}

// Scales the world so that `length` (a magnitude of the case) becomes about 2^target, a power
// of two smaller where that would overflow. Returns the power applied.
int scale_to(GenCase& g, double length, int target) {
  int k = target - std::ilogb(std::max(length, 0x1p-1000));
  for (;; --k) {
    GenCase s = scale_world(g, k);
    if (finite_case(s)) {
      g = std::move(s);
      return k;
    }
  }
}

// Plane p times 2^j so that its largest coefficient has exponent `target` (the same half-space;
// exact unless it goes subnormal). A normal that would round to zero is kept a power of two
// larger, so that the plane stays what it was (a plane, not all space or nothing).
void scale_plane_to(Plane& p, int target) {
  const float big = std::max({std::abs(p.n.x), std::abs(p.n.y), std::abs(p.n.z), std::abs(p.d)});
  if (big == 0.0f) return;
  for (int j = target - std::ilogb(big);; ++j) {
    const Plane q{times2(p.n, j), times2(p.d, j)};
    if (p.is_degenerate() || !q.is_degenerate()) {
      p = q;
      return;
    }
  }
}

// Plane p times 2^j so that its largest normal component has exponent `target`, or less where
// d would overflow (the same half-space, exact while nothing goes subnormal).
void scale_normal_to(Plane& p, int target) {
  if (p.is_degenerate()) return;
  const float n = std::max({std::abs(p.n.x), std::abs(p.n.y), std::abs(p.n.z)});
  int j = target - std::ilogb(n);
  if (p.d != 0.0f) j = std::min(j, 127 - std::ilogb(p.d));
  p = Plane{times2(p.n, j), times2(p.d, j)};
}

// A matrix case's entries times 2^j so that the largest has exponent `target` (clip coordinates
// scaled by 2^j: the same frustum); the planes are extracted again.
void scale_matrix_to(GenCase& g, int target) {
  glm::mat4 m = *g.frustum.matrix;
  float big = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) big = std::max(big, std::abs(m[c][r]));
  if (big == 0.0f) return;
  const int j = target - std::ilogb(big);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m[c][r] = times2(m[c][r], j);
  g.frustum = frustum_spec(m, g.frustum.depth);
}

float clamp_float(double x) { return float(std::clamp(x, -double(kFltMax), double(kFltMax))); }

// A volume as large as a float gets, about placement p: an AABB whose sides reach towards
// +-FLT_MAX on some axes (containing the frustum, straddling its faces, or beyond one), a sphere
// of radius up to FLT_MAX, an OBB whose half-extents come near FLT_MAX, or a point far out.
Volume huge_volume(const Placement& p) {
  const glm::dvec3 at = p.center + p.size * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1));
  auto far_out = [] { return double(kFltMax) * in(0.25, 1.0); };
  const int kind = pick(20);
  if (kind < 10) {
    Aabb b;
    for (int a = 0; a < 3; ++a) {
      double lo = at[a] - p.size * in(0, 1), hi = at[a] + p.size * in(0, 1);
      const double side = coin(50) ? 1.0 : -1.0;
      switch (pick(5)) {
        case 0: lo = -far_out(), hi = far_out(); break;  // across the whole range on this axis
        case 1: hi = far_out(); break;                   // from about the frustum up
        case 2: lo = -far_out(); break;                  // from about the frustum down
        case 3:                                          // far out on one side: min + max overflows
          lo = side * double(kFltMax) * in(0.5, 0.9), hi = side * double(kFltMax) * in(0.9, 1.0);
          break;
        default: break;  // about the frustum
      }
      b.min[a] = clamp_float(lo), b.max[a] = clamp_float(hi);
      if (b.min[a] > b.max[a]) std::swap(b.min[a], b.max[a]);
    }
    return b;
  }
  if (kind < 14) {
    glm::dvec3 c = at;
    if (coin(30))
      for (int a = 0; a < 3; ++a) c[a] = (coin(50) ? 1 : -1) * far_out();
    return Sphere{glm::vec3(clamp_float(c.x), clamp_float(c.y), clamp_float(c.z)), float(double(kFltMax) * log_in(-3, 0))};
  }
  if (kind < 18) {
    Obb o;
    o.center = glm::vec3(clamp_float(at.x), clamp_float(at.y), clamp_float(at.z));
    o.axes = rotation();
    for (int a = 0; a < 3; ++a) o.half[a] = coin(25) ? clamp_float(p.size * in(0.01, 1)) : float(double(kFltMax) * in(0.05, 1.0));
    return o;
  }
  return Point(clamp_float(coin(50) ? at.x : (coin(50) ? 1 : -1) * far_out()),
               clamp_float(coin(50) ? at.y : (coin(50) ? 1 : -1) * far_out()),
               clamp_float(coin(50) ? at.z : (coin(50) ? 1 : -1) * far_out()));
}

// A generic volume about the frustum: the families that straddle faces, corners and the frustum.
Volume around(const Placement& p) {
  static constexpr Distribution kAround[] = {Distribution::uniform, Distribution::near_boundary, Distribution::corner,
                                             Distribution::enclosing, Distribution::tiny_huge};
  return generic_volume(kAround[pick(5)], p);
}

GenCase huge_case() {
  Camera cam = generic_camera();
  const int kind = pick(100);
  if (kind >= 60 && kind < 80) cam.as_matrix = false;
  if (kind >= 80) {
    cam.as_matrix = true;
    // Half the time a camera far from the origin, so that the matrix's translation column (whose
    // rows are about the same size) is what reaches FLT_MAX.
    if (coin(50)) cam.eye = glm::vec3(unit_vector() * log_in(3, 6));
  }
  const Placement p = placement_for(cam);
  GenCase g = make(cam, p, around(p));
  if (kind < 35) {
    // The scene carried to the top of the range: its largest coordinate at 2^118 .. 2^127; three
    // times in four the planes (or the matrix) scaled up to FLT_MAX as well, so that n.x overflows.
    double length = volume_magnitude(g.volume);
    for (const auto& c : p.corner) length = std::max({length, std::abs(c.x), std::abs(c.y), std::abs(c.z)});
    scale_to(g, length, *rc::gen::inRange(118, 128));
    if (coin(75)) {
      if (g.frustum.matrix) scale_matrix_to(g, *rc::gen::inRange(120, 128));
      else
        for (Plane& pl : g.frustum.planes.planes) scale_plane_to(pl, *rc::gen::inRange(110, 128));
    }
  } else if (kind < 60) {
    // A volume as large as a float gets about a frustum at any scale.
    const int k = scale_to(g, p.size, *rc::gen::inRange(-2, 120));
    g.volume = huge_volume(scale_placement(p, k));
  } else if (kind < 80) {
    // Planes with coefficients up to FLT_MAX, ordinary volumes: n.x overflows. A power of two
    // keeps the half-space exactly; another factor rounds every coefficient.
    for (Plane& pl : g.frustum.planes.planes) {
      if (coin(50)) {
        scale_normal_to(pl, *rc::gen::inRange(116, 128));
        continue;
      }
      const double big = std::max({std::abs(pl.n.x), std::abs(pl.n.y), std::abs(pl.n.z), std::abs(pl.d)});
      if (big == 0.0) continue;
      const double factor = double(kFltMax) * log_in(-2, 0) / big;
      Plane q{glm::vec3(glm::dvec3(pl.n) * factor), float(double(pl.d) * factor)};
      if (!q.is_degenerate() || pl.is_degenerate()) pl = q;
    }
  } else {
    // A clip matrix whose entries reach FLT_MAX (every depth convention, reversed-Z, infinite far):
    // the Gribb-Hartmann row sums overflow float.
    scale_to(g, p.size, *rc::gen::inRange(0, 100));
    if (coin(50)) {
      scale_matrix_to(g, 127);
    } else {
      // The largest entry at 0.8 .. 1 FLT_MAX: a factor that is not a power of two rounds every
      // entry (a frustum a rounding away), and brings more pairs of entries past FLT_MAX.
      glm::mat4 m = *g.frustum.matrix;
      double big = 0.0;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) big = std::max(big, double(std::abs(m[c][r])));
      if (big > 0.0) {
        const double factor = double(kFltMax) * in(0.8, 1.0) / big;
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r) m[c][r] = clamp_float(double(m[c][r]) * factor);
        g.frustum = frustum_spec(m, g.frustum.depth);
      }
    }
  }
  return g;
}

GenCase subnormal_case() {
  Camera cam = generic_camera();
  const int kind = pick(100);
  if (kind < 50 && coin(50)) cam.eye = glm::vec3(0.0f);  // coordinates near 0 are subnormal too
  if (kind >= 50 && kind < 75) cam.as_matrix = false;
  const Placement p = placement_for(cam);
  if (kind < 50) {
    // The scene carried to the bottom of the range: its size at 2^-140 .. 2^-112, where extents
    // and distances to the faces are subnormal.
    GenCase g = make(cam, p, around(p));
    scale_to(g, p.size, *rc::gen::inRange(-140, -111));
    return g;
  }
  if (kind < 75) {
    // Planes with subnormal coefficients (largest at 2^-146 .. 2^-127), ordinary volumes: a
    // product n_i x_i underflows wherever it is below 2^-126, which with these coefficients is
    // at every coordinate below 2 in magnitude, and at larger ones for the smaller coefficients.
    GenCase g = make(cam, p, around(p));
    for (Plane& pl : g.frustum.planes.planes) scale_plane_to(pl, *rc::gen::inRange(-146, -126));
    return g;
  }
  // A tiny frustum (size 2^-120 .. 2^-100) and volumes 1e-7 .. 1e-4 of it near its faces and
  // corners: subnormal extents at subnormal distances.
  const double s = p.size * rel_size(-7, -4);
  GenCase g = make(cam, p, coin(50) ? near_boundary(p, any_shape(), s) : near_corner(p, any_shape(), s));
  scale_to(g, p.size, *rc::gen::inRange(-120, -99));
  return g;
}

}  // namespace

namespace {

// Exact frusta with integer corners --------------------------------------------------------------
//
// Truncated pyramids whose eight corners are integer points: perspective (the far window the
// larger), off-axis and sheared (near and far windows centred off the axis, each by its own
// integer offset) and orthographic (the same window at both depths), moved to the world by an
// exact frame (ExactFrame: signed axis permutation; its integer shift half the time). Each plane
// passes through three corners, so its coefficients are small integers, computed exactly, and
// points built from the corners with dyadic weights lie exactly on the planes. The families
// below (exact_touching, exact_containment, exact_degenerate) are aimed at methods that claim to
// be exact: a volume that touches the boundary exactly, or misses it by one or two ulps, and
// frusta and volumes that are not what a camera makes (sheared pyramids, non-orthonormal OBB
// axes, planes that hold everywhere or nowhere).

struct IntegerFrustum {
  Frustum planes;
  std::array<glm::vec3, 8> corner;  // index bits: 0 right, 1 top, 2 far (as frustum_corners)
};

int between(int lo, int hi) { return *rc::gen::inRange(lo, hi + 1); }  // lo .. hi inclusive

// x moved by k ulps (k may be negative).
float ulps(float x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<float>::infinity());
  for (; k < 0; ++k) x = std::nextafter(x, -std::numeric_limits<float>::infinity());
  return x;
}
// Mostly 0, sometimes +-1 or +-2 ulps.
int small_nudge() { return *rc::gen::element(0, 0, 0, 1, -1, 2, -2); }

// The plane through integer points p, q, r, oriented so that the corners' centroid (sum8 is 8
// times it) is inside. In double: every value is an integer far below 2^24, so the float plane
// is exact.
Plane plane_through(glm::dvec3 p, glm::dvec3 q, glm::dvec3 r, glm::dvec3 sum8) {
  const glm::dvec3 n = glm::cross(q - p, r - p);
  const double d = -glm::dot(n, p);
  const bool inward = glm::dot(n, sum8) + 8.0 * d >= 0.0;
  return inward ? Plane{glm::vec3(n), float(d)} : Plane{glm::vec3(-n), float(-d)};
}

IntegerFrustum integer_frustum() {
  const int zn = between(1, 4), zf = zn + between(1, 12);
  const int a = between(1, 4), b = between(1, 4);
  const bool ortho = coin(25);
  const int A = ortho ? a : a + between(0, 8), B = ortho ? b : b + between(1, 8);
  const int ox = between(-3, 3), oy = between(-3, 3);
  const int fx = ortho ? ox : between(-3, 3), fy = ortho ? oy : between(-3, 3);
  ExactFrame e = exact_frame();
  // Unshifted half the time: corners with a zero coordinate, which a nudge of an ulp or two takes
  // to a subnormal (the window's centre offset cancelling its half-width).
  if (coin(50)) e.shift = glm::vec3(0.0f);
  IntegerFrustum out;
  glm::dvec3 sum(0.0);
  for (int i = 0; i < 8; ++i) {
    const bool right = i & 1, top = i & 2, far = i & 4;
    const int hx = far ? A : a, hy = far ? B : b, cx = far ? fx : ox, cy = far ? fy : oy;
    const glm::vec3 view(float(cx + (right ? hx : -hx)), float(cy + (top ? hy : -hy)), float(far ? -zf : -zn));
    out.corner[std::size_t(i)] = to_world(e, view);
    sum += glm::dvec3(out.corner[std::size_t(i)]);
  }
  auto through = [&](int i, int j, int k) {
    return plane_through(glm::dvec3(out.corner[std::size_t(i)]), glm::dvec3(out.corner[std::size_t(j)]),
                         glm::dvec3(out.corner[std::size_t(k)]), sum);
  };
  out.planes[kLeft] = through(0, 2, 4);
  out.planes[kRight] = through(1, 3, 5);
  out.planes[kBottom] = through(0, 1, 4);
  out.planes[kTop] = through(2, 3, 6);
  out.planes[kNear] = through(0, 1, 2);
  out.planes[kFar] = through(4, 5, 6);
  // Unnormalised planes, some scaled by a power of two (the same half-space, still exact).
  for (Plane& p : out.planes.planes) {
    const float s = *rc::gen::element(1.0f, 1.0f, 0.5f, 2.0f, 0.0625f, 1024.0f);
    p.n *= s;
    p.d *= s;
  }
  return out;
}

// A point exactly on the boundary: a corner, a point of an edge (weights k/8) or a point of a
// face (bilinear weights k/4 on its four coplanar corners): affine combinations of integer
// corners with dyadic weights, exact in float.
glm::vec3 boundary_point(const IntegerFrustum& f) {
  const auto& c = f.corner;
  const int kind = pick(3);
  if (kind == 0) return c[std::size_t(pick(8))];
  if (kind == 1) {  // edges join corners differing in one index bit
    const int i = pick(8), j = i ^ (1 << pick(3));
    const glm::vec3 p = c[std::size_t(i)], q = c[std::size_t(j)];
    return p + (q - p) * (float(between(0, 8)) / 8.0f);
  }
  const int axis = pick(3), value = pick(2);  // the face: one index bit fixed
  std::array<glm::vec3, 4> q;
  for (int i = 0, k = 0; i < 8; ++i)
    if (((i >> axis) & 1) == value) q[std::size_t(k++)] = c[std::size_t(i)];
  const float u = float(between(0, 4)) / 4.0f, v = float(between(0, 4)) / 4.0f;
  const glm::vec3 e0 = q[0] + (q[1] - q[0]) * u, e1 = q[2] + (q[3] - q[2]) * u;
  return e0 + (e1 - e0) * v;
}

// A rotation by whole-degree Euler angles, each a multiple of 90 degrees half the time: a float
// matrix whose axes are then a rounding away from the coordinate axes (cos 90 degrees is not 0 in
// float), so that a box's faces are nearly parallel to the frustum's.
glm::mat3 degree_rotation() {
  glm::vec3 angles;
  for (int i = 0; i < 3; ++i) angles[i] = float(coin(50) ? 90 * pick(4) : pick(360));
  return glm::mat3_cast(glm::quat(glm::radians(angles)));
}

float small_extent() { return *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 2.0f, 3.0f, 40.0f); }

// A volume with a vertex (box), an extreme point (sphere) or its only point at p, extending in
// random directions, then nudged by up to two ulps per coordinate.
Volume volume_touching(glm::vec3 p) {
  const int kind = pick(4);
  if (kind == 0) {  // an AABB with a corner at p
    Aabb b{p, p};
    for (int k = 0; k < 3; ++k) {
      const float length = small_extent();
      if (coin(50)) b.max[k] = p[k] + length;
      else b.min[k] = p[k] - length;
      b.min[k] = ulps(b.min[k], small_nudge());
      b.max[k] = ulps(b.max[k], small_nudge());
      if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
    }
    return b;
  }
  if (kind == 1) {  // an OBB with a vertex at p
    Obb o;
    if (coin(50)) {
      // Small integer axes: not orthonormal, possibly parallel; the volume is the parallelepiped
      // as given.
      for (int i = 0; i < 3; ++i) {
        glm::vec3 u(float(between(-2, 2)), float(between(-2, 2)), float(between(-2, 2)));
        if (u == glm::vec3(0.0f)) u[i] = 1.0f;
        o.axes[i] = u;
      }
    } else {
      o.axes = coin(50) ? degree_rotation() : rotation();
    }
    glm::vec3 c = p;
    for (int i = 0; i < 3; ++i) {
      o.half[i] = *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 2.0f);
      c += (coin(50) ? 1.0f : -1.0f) * o.half[i] * o.axes[i];
    }
    for (int k = 0; k < 3; ++k) c[k] = ulps(c[k], small_nudge());
    o.center = c;
    return o;
  }
  if (kind == 2) {  // a sphere touching p from one axis direction
    Sphere s;
    s.radius = *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 3.0f);
    glm::vec3 c = p;
    c[pick(3)] += (coin(50) ? 1.0f : -1.0f) * s.radius;
    for (int k = 0; k < 3; ++k) c[k] = ulps(c[k], small_nudge());
    s.center = c;
    s.radius = ulps(s.radius, s.radius > 0.0f ? small_nudge() : std::max(0, small_nudge()));
    return s;
  }
  Point q = p;
  for (int k = 0; k < 3; ++k) q[k] = ulps(q[k], small_nudge());
  return q;
}

// The case's scene size: the diameter of the corners' bounding box.
double corner_span(const IntegerFrustum& f) {
  glm::dvec3 lo(f.corner[0]), hi(f.corner[0]);
  for (const auto& c : f.corner) lo = glm::min(lo, glm::dvec3(c)), hi = glm::max(hi, glm::dvec3(c));
  return glm::length(hi - lo);
}

GenCase integer_case(const IntegerFrustum& f, Volume v) {
  GenCase g;
  g.frustum = frustum_spec(f.planes);
  g.volume = std::move(v);
  g.scene_size = corner_span(f);
  return g;
}

GenCase exact_touching_case() {
  const IntegerFrustum f = integer_frustum();
  return integer_case(f, volume_touching(boundary_point(f)));
}

GenCase exact_containment_case() {
  const IntegerFrustum f = integer_frustum();
  glm::vec3 lo = f.corner[0], hi = f.corner[0], sum(0.0f);
  for (const auto& q : f.corner) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
    sum += q;
  }
  const glm::vec3 centre = sum / 8.0f;  // dyadic, exact
  switch (pick(5)) {
    case 0: {  // the frustum's bounding box, grown or shrunk by a few units or ulps
      const float grow = *rc::gen::element(0.0f, 0.0f, 1.0f, -0.5f, 10.0f);
      Aabb b{lo - grow, hi + grow};
      for (int k = 0; k < 3; ++k) {
        b.min[k] = ulps(b.min[k], small_nudge());
        b.max[k] = ulps(b.max[k], small_nudge());
        if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      }
      return integer_case(f, b);
    }
    case 1: {  // a small box about the centroid
      const float h = *rc::gen::element(0.0f, 0.125f, 0.25f, 0.5f, 1.0f);
      return integer_case(f, Aabb{centre - h, centre + h});
    }
    case 2:  // a ball about the centroid, from a point to one containing the frustum
      return integer_case(f, Sphere{centre, *rc::gen::element(0.0f, 0.25f, 1.0f, 4.0f, 100.0f)});
    case 3: {  // a rotated box about the centroid
      const float h = *rc::gen::element(0.25f, 1.0f, 4.0f, 30.0f);
      return integer_case(f, Obb{centre, coin(50) ? degree_rotation() : rotation(), glm::vec3(h, h * 0.5f, h * 2.0f)});
    }
    default: {  // a corner of the frustum itself, as a point box
      const glm::vec3 q = f.corner[std::size_t(pick(8))];
      return integer_case(f, Aabb{q, q});
    }
  }
}

GenCase exact_degenerate_case() {
  IntegerFrustum f = integer_frustum();
  switch (pick(10)) {  // six in ten keep the planes as built
    case 0: f.planes[kFar] = Plane{glm::vec3(0.0f), 1.0f}; break;         // infinite far: holds everywhere
    case 1: f.planes[pick(6)] = Plane{glm::vec3(0.0f), -1.0f}; break;     // holds nowhere: empty frustum
    case 2: {                                                             // flipped: often empty or unbounded
      Plane& p = f.planes[pick(6)];
      p = Plane{-p.n, -p.d};
      break;
    }
    case 3: f.planes[pick(6)] = Plane{glm::vec3(0.0f), 0.0f}; break;      // 0 >= 0: holds everywhere
    default: break;
  }
  // The corners stay those of the integer frustum: boundary points of the planes kept.
  const glm::vec3 p = boundary_point(f);
  switch (pick(4)) {
    case 0: {  // a flat box: one zero extent
      Aabb b{p, p};
      const int flat = pick(3);
      for (int k = 0; k < 3; ++k) {
        if (k == flat) continue;
        b.min[k] = p[k] - small_extent();
        b.max[k] = p[k] + small_extent();
      }
      b.min[flat] = b.max[flat] = ulps(p[flat], small_nudge());
      return integer_case(f, b);
    }
    case 1: {  // a segment box
      Aabb b{p, p};
      const int k = pick(3);
      b.min[k] = p[k] - small_extent();
      b.max[k] = ulps(p[k], small_nudge());
      if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      return integer_case(f, b);
    }
    case 2: {  // a zero-radius ball
      glm::vec3 q = p;
      for (int k = 0; k < 3; ++k) q[k] = ulps(q[k], small_nudge());
      return integer_case(f, Sphere{q, 0.0f});
    }
    default: return integer_case(f, volume_touching(p));
  }
}

}  // namespace

// Camera paths ---------------------------------------------------------------------------------

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

rc::Gen<CameraPath> camera_path() {
  return rc::gen::resize(100, rc::gen::exec([] {
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
  }));
}

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

rc::Gen<GenCase> case_of(Distribution d) {
  // Fixed size: the building blocks draw from their whole ranges whatever size RapidCheck is at
  // (its inRange narrows with size, which at size 0 would pin every draw to its lower bound).
  return rc::gen::resize(100, rc::gen::exec([d] {
    switch (d) {
      case Distribution::touch: return touch_case(false);
      case Distribution::contact: return contact_case();
      case Distribution::ulp: return touch_case(true);
      case Distribution::far_offset:
      case Distribution::tiny_near:
      case Distribution::reversed_infinite:
      case Distribution::extreme_fov:
      case Distribution::ill_conditioned:
      case Distribution::rod: return hard_case(d);
      case Distribution::huge: return huge_case();
      case Distribution::subnormal: return subnormal_case();
      case Distribution::camera_path: {
        const CameraPath p = *camera_path();
        return path_case(p, std::size_t(pick(int(kPathFrames))), std::size_t(pick(int(kPathObjects))));
      }
      default: return generic_case(d);
    }
  }));
}

rc::Gen<CaseFrustum> any_frustum() {
  return rc::gen::resize(100, rc::gen::exec([] { return realize(generic_camera()); }));
}

rc::Gen<GenCase> exact_touching() { return rc::gen::resize(100, rc::gen::exec(exact_touching_case)); }
rc::Gen<GenCase> exact_containment() { return rc::gen::resize(100, rc::gen::exec(exact_containment_case)); }
rc::Gen<GenCase> exact_degenerate() { return rc::gen::resize(100, rc::gen::exec(exact_degenerate_case)); }

rc::Gen<GenCase> any_case() {
  // Every distribution and every exact family equally likely; a case shrinks towards cases of
  // the first source (uniform). Fixed size, as case_of: the source is drawn from the whole range.
  const std::vector<Distribution> all = parse_distributions("all");
  const int sources = int(all.size()) + 3;
  return rc::gen::resize(100, rc::gen::mapcat(rc::gen::inRange(0, sources), [all](int k) {
    if (k < int(all.size())) return case_of(all[std::size_t(k)]);
    if (k == int(all.size())) return exact_touching();
    if (k == int(all.size()) + 1) return exact_containment();
    return exact_degenerate();
  }));
}

namespace {

// One independent stream per (seed, distribution, index): splitmix64 of the three.
std::uint64_t draw_key(std::uint64_t seed, Distribution d, std::uint64_t index) {
  auto mix = [](std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
  };
  return mix(mix(mix(seed) ^ std::uint64_t(d)) ^ index);
}

}  // namespace

rc::Shrinkable<GenCase> draw(Distribution d, std::uint64_t seed, std::uint64_t index) {
  if (d == Distribution::camera_path) {
    // The case's path, picked from: its shrinks are simpler paths, seen at the same frame and object.
    const PathIndex at = path_index(index);
    return rc::gen::map(camera_path(), [at](const CameraPath& p) { return path_case(p, at.frame, at.object); })(
        rc::Random(draw_key(seed, d, at.path)), 100);
  }
  return case_of(d)(rc::Random(draw_key(seed, d, index)), 100);
}

CameraPath draw_path(std::uint64_t seed, std::uint64_t path) {
  return camera_path()(rc::Random(draw_key(seed, Distribution::camera_path, path)), 100).value();
}

Frame draw_frame(Distribution d, std::uint64_t seed, std::uint64_t index, std::size_t size, unsigned kinds) {
  // Frames are drawn from streams apart from the cases' ("frame" in ASCII mixed into the seed).
  constexpr std::uint64_t kFrameStream = 0x6672616d65ull;
  if (kinds == 0) throw std::invalid_argument("draw_frame: no volume kind asked for");
  // Up to 64 draws per volume asked for: a kind the distribution rarely makes (points) still
  // fills the frame; one it never makes leaves it short, which the caller sees.
  const std::size_t attempts = 64 * size;
  Frame out;
  if (d == Distribution::camera_path) {
    const CameraPath p = draw_path(seed ^ kFrameStream, index / kPathFrames);
    out.frustum = p.frames[index % kPathFrames];
    out.continues = index % kPathFrames != 0;
    for (const Volume& v : p.objects)
      if ((kinds & volume_kind(v)) && out.volumes.size() < size) out.volumes.push_back(v);
    return out;
  }
  const bool generic = [&] {
    for (Distribution g : generic_distributions())
      if (g == d) return true;
    return false;
  }();
  if (generic) {
    // One camera, then volumes of the distribution around its frustum: an engine's frame.
    out = rc::gen::exec([&] {
      Frame fr;
      const Camera cam = generic_camera();
      const Placement p = placement_for(cam);
      fr.frustum = realize(cam);
      for (std::size_t k = 0; k < attempts && fr.volumes.size() < size; ++k) {
        Volume v = generic_volume(d, p);
        if (kinds & volume_kind(v)) fr.volumes.push_back(std::move(v));
      }
      return fr;
    })(rc::Random(draw_key(seed ^ kFrameStream, d, index)), 100).value();
  } else {
    // The hard families build frustum and volume together: the first case's frustum with the
    // volumes of the cases that follow it.
    for (std::uint64_t k = 0; k < attempts && out.volumes.size() < size; ++k) {
      GenCase c = draw(d, seed ^ kFrameStream, index * attempts + k).value();
      if (k == 0) out.frustum = c.frustum;
      if (kinds & volume_kind(c.volume)) out.volumes.push_back(std::move(c.volume));
    }
  }
  return out;
}

double case_scale(const CaseFrustum& f, const Volume& v) {
  // M: the largest coordinate magnitude of the volume (centre plus extent), in double.
  const double m = volume_magnitude(v);
  // Per plane, the magnitude of what its evaluation rounds, in distance units:
  // (A M + a_d + 2^-124) / |n|, with a the bound on the coefficients (|plane| for planes;
  // |r4| + |rk| for a matrix, whose float extraction rounds that much: see
  // cullproof/certified.hpp; halved together with the plane where the extraction halves the
  // rows). 2^-124 is the underflow: a product that underflows errs by up to 2^-150 absolutely,
  // as much as the relative rounding u = 2^-24 of a magnitude 2^-126, four products per plane.
  // In double: the bounds are finite floats (at most FLT_MAX each), so nothing here overflows.
  const CertifiedFrustum::Data c = certify(f).data();
  double s = m;
  for (int k = 0; k < kPlaneCount; ++k) {
    const Plane& p = c.planes[k];
    if (p.is_degenerate()) continue;
    const double len = glm::length(glm::dvec3(p.n));
    const double a = double(c.bound[k].x) + double(c.bound[k].y) + double(c.bound[k].z);
    s = std::max(s, (a * m + double(c.bound[k].w) + 0x1p-124) / len);
  }
  return s > 0.0 ? s : 1.0;
}

}  // namespace cullproof::gen

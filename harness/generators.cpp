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
          Distribution::ill_conditioned, Distribution::rod, Distribution::corner};
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
  // M: the largest coordinate magnitude of the volume (centre plus extent).
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
  // Per plane, the magnitude of what its evaluation rounds, in distance units:
  // (A M + a_d) / |n|, with a the bound on the coefficients (|plane| for planes; |r4| + |rk| for
  // a matrix, whose float extraction rounds that much: see cullproof/certified.hpp).
  const CertifiedFrustum c = certify(f);
  double s = m;
  for (int k = 0; k < kPlaneCount; ++k) {
    const Plane& p = c.planes[k];
    if (p.is_degenerate()) continue;
    const double len = glm::length(glm::dvec3(p.n));
    const double a = double(c.bound[k].x) + double(c.bound[k].y) + double(c.bound[k].z);
    s = std::max(s, (a * m + double(c.bound[k].w)) / len);
  }
  return s > 0.0 ? s : 1.0;
}

}  // namespace cullproof::gen

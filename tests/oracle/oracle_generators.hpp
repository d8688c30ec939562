// Case generators for the oracle cross-check. They construct the cases they want (exact touching
// at a vertex, an edge or a face, 1-ulp moves, containment both ways, degenerate volumes,
// infinite far planes, matrix frusta in every depth convention) instead of filtering random ones.
//
// "Exact" frusta are truncated pyramids with integer corners: each plane passes through three
// integer points, so its coefficients are small integers, exactly representable, and points
// built from the corners with dyadic weights lie exactly on the planes.
#pragma once

#include "cullproof/case_io.hpp"
#include "cullproof/frustum_build.hpp"
#include "cullproof/geometry.hpp"

#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <rapidcheck.h>

#include <array>
#include <cmath>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

namespace cullproof {
/// RapidCheck printers for the core enums (found by argument-dependent lookup).
inline void showValue(Visibility v, std::ostream& os) { os << to_string(v); }
inline void showValue(const DepthConvention& d, std::ostream& os) {
  os << (d.range == DepthRange::zero_to_one ? "zero_to_one" : "negative_one_to_one")
     << (d.reversed_z ? " reversed_z" : "");
}
}  // namespace cullproof

namespace cullproof::oracle::test {

/// One generated case and the family that made it.
struct GenCase {
  CaseFrustum frustum;
  Volume volume;
  std::string how;  ///< the construction, for the failure log
};

inline int pick_int(int lo, int hi) { return *rc::gen::inRange(lo, hi + 1); }
inline bool coin(int one_in = 2) { return pick_int(1, one_in) == 1; }

/// x moved by k ulps (k may be negative) with std::nextafter.
inline float ulps(float x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<float>::infinity());
  for (; k < 0; ++k) x = std::nextafter(x, -std::numeric_limits<float>::infinity());
  return x;
}
/// Mostly 0, sometimes ±1 or ±2 ulps.
inline int small_nudge() { return *rc::gen::element(0, 0, 0, 1, -1, 2, -2); }

/// An integer-cornered truncated pyramid (perspective, off-axis or orthographic) and its
/// corners (index bits: 0 right, 1 top, 2 far).
struct ExactFrustum {
  Frustum planes;
  std::array<glm::vec3, 8> corners;
};

inline Plane plane_through(glm::vec3 p, glm::vec3 q, glm::vec3 r, glm::vec3 centre8) {
  // Integer inputs: every product below is a small integer, exact in float.
  const glm::vec3 n = glm::cross(q - p, r - p);
  const float d = -glm::dot(n, p);
  // Orient towards the interior: the sum of the 8 corners (8 × centroid) must be inside.
  const float side = glm::dot(n, centre8) + 8.0f * d;
  return side >= 0 ? Plane{n, d} : Plane{-n, -d};
}

inline ExactFrustum gen_exact_frustum() {
  const int zn = pick_int(1, 4), zf = zn + pick_int(1, 12);
  const int a = pick_int(1, 4), b = pick_int(1, 4);
  const bool ortho = coin(4);
  const int A = ortho ? a : a + pick_int(0, 8), B = ortho ? b : b + pick_int(1, 8);
  const int ox = pick_int(-3, 3), oy = pick_int(-3, 3);
  const int fx = ortho ? ox : pick_int(-3, 3), fy = ortho ? oy : pick_int(-3, 3);
  ExactFrustum out;
  for (int i = 0; i < 8; ++i) {
    const bool right = i & 1, top = i & 2, far = i & 4;
    const int hx = far ? A : a, hy = far ? B : b, cx = far ? fx : ox, cy = far ? fy : oy;
    out.corners[static_cast<std::size_t>(i)] =
        glm::vec3(float(cx + (right ? hx : -hx)), float(cy + (top ? hy : -hy)), float(far ? -zf : -zn));
  }
  glm::vec3 sum(0.0f);
  for (const auto& c : out.corners) sum += c;
  const auto& C = out.corners;
  out.planes[kLeft] = plane_through(C[0], C[2], C[4], sum);
  out.planes[kRight] = plane_through(C[1], C[3], C[5], sum);
  out.planes[kBottom] = plane_through(C[0], C[1], C[4], sum);
  out.planes[kTop] = plane_through(C[2], C[3], C[6], sum);
  out.planes[kNear] = plane_through(C[0], C[1], C[2], sum);
  out.planes[kFar] = plane_through(C[4], C[5], C[6], sum);
  // Planes need not be normalised: scale some by a power of two (still exact).
  for (auto& p : out.planes.planes) {
    const float s = *rc::gen::element(1.0f, 1.0f, 0.5f, 2.0f, 0.0625f, 1024.0f);
    p.n *= s;
    p.d *= s;
  }
  return out;
}

/// A point exactly on F's boundary: a vertex, a point of an edge, or a point of a face (affine
/// combinations of coplanar integer corners with dyadic weights).
inline glm::vec3 gen_boundary_point(const ExactFrustum& f, std::string& how) {
  const auto& C = f.corners;
  const int kind = pick_int(0, 2);
  if (kind == 0) {
    how += "vertex ";
    return C[static_cast<std::size_t>(pick_int(0, 7))];
  }
  if (kind == 1) {
    how += "edge ";
    // Edges join corners differing in one index bit.
    const int i = pick_int(0, 7), bit = 1 << pick_int(0, 2);
    const glm::vec3 p = C[static_cast<std::size_t>(i)], q = C[static_cast<std::size_t>(i ^ bit)];
    const float w = float(pick_int(0, 8)) / 8.0f;
    return p + (q - p) * w;
  }
  how += "face ";
  // Face: fix one index bit; bilinear weights on its four corners are affine, dyadic, exact.
  const int axis = pick_int(0, 2), value = pick_int(0, 1);
  std::array<glm::vec3, 4> q;
  int n = 0;
  for (int i = 0; i < 8; ++i)
    if (((i >> axis) & 1) == value) q[static_cast<std::size_t>(n++)] = C[static_cast<std::size_t>(i)];
  const float u = float(pick_int(0, 4)) / 4.0f, v = float(pick_int(0, 4)) / 4.0f;
  const glm::vec3 e0 = q[0] + (q[1] - q[0]) * u, e1 = q[2] + (q[3] - q[2]) * u;
  return e0 + (e1 - e0) * v;
}

inline float gen_extent() { return *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 2.0f, 3.0f, 40.0f); }

/// A volume with a vertex (box), an extreme point (sphere) or its only point at `p`, extending
/// in random directions, then possibly nudged by an ulp or two.
inline Volume gen_volume_at(glm::vec3 p, std::string& how, bool allow_rotation = true) {
  const int kind = pick_int(0, 3);
  if (kind == 0) {  // AABB with a corner at p
    how += "aabb-corner ";
    Aabb b{p, p};
    for (int k = 0; k < 3; ++k) {
      const float L = gen_extent();
      if (coin()) b.max[k] = p[k] + L;
      else b.min[k] = p[k] - L;
      b.min[k] = ulps(b.min[k], small_nudge());
      b.max[k] = ulps(b.max[k], small_nudge());
      if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
    }
    return b;
  }
  if (kind == 1) {  // OBB with a vertex at p
    Obb o;
    if (!allow_rotation || coin()) {
      how += "obb-int-axes ";
      // Small integer axes (not orthonormal; the geometry is the parallelepiped as given).
      for (int i = 0; i < 3; ++i) {
        glm::vec3 u(0.0f);
        while (u == glm::vec3(0.0f)) u = glm::vec3(float(pick_int(-2, 2)), float(pick_int(-2, 2)), float(pick_int(-2, 2)));
        o.axes[i] = u;
      }
    } else {
      how += "obb-rotated ";
      const glm::vec3 angles(float(pick_int(0, 359)), float(pick_int(0, 359)), float(pick_int(0, 359)));
      o.axes = glm::mat3_cast(glm::quat(glm::radians(angles)));
    }
    glm::vec3 c = p;
    for (int i = 0; i < 3; ++i) {
      o.half[i] = *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 2.0f);
      c += (coin() ? 1.0f : -1.0f) * o.half[i] * o.axes[i];
    }
    for (int k = 0; k < 3; ++k) c[k] = ulps(c[k], small_nudge());
    o.center = c;
    return o;
  }
  if (kind == 2) {  // sphere touching p from one axis direction
    how += "sphere-axis ";
    Sphere s;
    s.radius = *rc::gen::element(0.0f, 0.25f, 0.5f, 1.0f, 3.0f);
    glm::vec3 c = p;
    c[pick_int(0, 2)] += (coin() ? 1.0f : -1.0f) * s.radius;
    for (int k = 0; k < 3; ++k) c[k] = ulps(c[k], small_nudge());
    s.center = c;
    s.radius = ulps(s.radius, s.radius > 0 ? small_nudge() : std::max(0, small_nudge()));
    return s;
  }
  how += "point ";
  Point q = p;
  for (int k = 0; k < 3; ++k) q[k] = ulps(q[k], small_nudge());
  return q;
}

/// Exact frustum, volume touching its boundary by construction (then maybe 1-2 ulps off).
inline GenCase gen_touching() {
  GenCase c;
  c.how = "touching ";
  const ExactFrustum f = gen_exact_frustum();
  c.frustum = frustum_spec(f.planes);
  const glm::vec3 p = gen_boundary_point(f, c.how);
  c.volume = gen_volume_at(p, c.how);
  return c;
}

/// Exact frustum with boxes and balls containing it, inside it, equal to its bounding box.
inline GenCase gen_containment() {
  GenCase c;
  c.how = "containment ";
  const ExactFrustum f = gen_exact_frustum();
  c.frustum = frustum_spec(f.planes);
  glm::vec3 lo(1e30f), hi(-1e30f), sum(0.0f);
  for (const auto& q : f.corners) {
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
    sum += q;
  }
  const glm::vec3 centre = sum / 8.0f;  // dyadic, exact
  switch (pick_int(0, 4)) {
    case 0: {  // the bounding box of F, grown or shrunk by a few units or ulps
      c.how += "bbox ";
      const float g = *rc::gen::element(0.0f, 0.0f, 1.0f, -0.5f, 10.0f);
      Aabb b{lo - g, hi + g};
      for (int k = 0; k < 3; ++k) {
        b.min[k] = ulps(b.min[k], small_nudge());
        b.max[k] = ulps(b.max[k], small_nudge());
        if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      }
      c.volume = b;
      break;
    }
    case 1: {  // a small box around the centroid
      c.how += "small-box ";
      const float h = *rc::gen::element(0.0f, 0.125f, 0.25f, 0.5f, 1.0f);
      c.volume = Aabb{centre - h, centre + h};
      break;
    }
    case 2: {  // a ball around the centroid
      c.how += "ball ";
      c.volume = Sphere{centre, *rc::gen::element(0.0f, 0.25f, 1.0f, 4.0f, 100.0f)};
      break;
    }
    case 3: {  // a rotated box around the centroid
      c.how += "rotated ";
      Obb o;
      const glm::vec3 angles(float(pick_int(0, 359)), float(pick_int(0, 359)), float(pick_int(0, 359)));
      o.axes = glm::mat3_cast(glm::quat(glm::radians(angles)));
      o.center = centre;
      const float h = *rc::gen::element(0.25f, 1.0f, 4.0f, 30.0f);
      o.half = glm::vec3(h, h * 0.5f, h * 2.0f);
      c.volume = o;
      break;
    }
    default: {  // a corner of F itself, as a point box
      c.how += "corner-point ";
      const glm::vec3 q = f.corners[static_cast<std::size_t>(pick_int(0, 7))];
      c.volume = Aabb{q, q};
      break;
    }
  }
  return c;
}

/// Exact frustum with special planes (infinite far, all-space, empty, flipped) and degenerate
/// volumes (flat, segment, point boxes; zero-radius balls; points).
inline GenCase gen_degenerate() {
  GenCase c;
  c.how = "degenerate ";
  ExactFrustum f = gen_exact_frustum();
  const int special = pick_int(0, 9);
  if (special == 0) {
    c.how += "infinite-far ";
    f.planes[kFar] = Plane{glm::vec3(0.0f), 1.0f};
  } else if (special == 1) {
    c.how += "empty-plane ";
    f.planes[pick_int(0, 5)] = Plane{glm::vec3(0.0f), -1.0f};
  } else if (special == 2) {
    c.how += "flipped-plane ";  // often an empty or unbounded F
    auto& p = f.planes[pick_int(0, 5)];
    p = Plane{-p.n, -p.d};
  } else if (special == 3) {
    c.how += "zero-plane ";  // n == 0, d == 0: 0 >= 0 holds everywhere
    f.planes[pick_int(0, 5)] = Plane{glm::vec3(0.0f), 0.0f};
  }
  c.frustum = frustum_spec(f.planes);
  const glm::vec3 p = gen_boundary_point(f, c.how);
  switch (pick_int(0, 3)) {
    case 0: {  // flat box: one zero extent
      c.how += "flat ";
      Aabb b{p, p};
      const int flat = pick_int(0, 2);
      for (int k = 0; k < 3; ++k) {
        if (k == flat) continue;
        b.min[k] = p[k] - gen_extent();
        b.max[k] = p[k] + gen_extent();
      }
      b.min[flat] = b.max[flat] = ulps(p[flat], small_nudge());
      c.volume = b;
      break;
    }
    case 1: {  // segment box
      c.how += "segment ";
      Aabb b{p, p};
      const int k = pick_int(0, 2);
      b.min[k] = p[k] - gen_extent();
      b.max[k] = ulps(p[k], small_nudge());
      if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      c.volume = b;
      break;
    }
    case 2: {  // zero-radius ball
      c.how += "zero-ball ";
      glm::vec3 q = p;
      for (int k = 0; k < 3; ++k) q[k] = ulps(q[k], small_nudge());
      c.volume = Sphere{q, 0.0f};
      break;
    }
    default:
      c.volume = gen_volume_at(p, c.how);
      break;
  }
  return c;
}

/// A random float camera (perspective, infinite, off-axis, orthographic) in one of the four depth
/// conventions, given as a matrix (end-to-end truth) or as its float-extracted planes.
inline GenCase gen_matrix() {
  GenCase c;
  c.how = "matrix ";
  const DepthConvention depth = *rc::gen::element(
      DepthConvention{DepthRange::negative_one_to_one, false}, DepthConvention{DepthRange::zero_to_one, false},
      DepthConvention{DepthRange::zero_to_one, true}, DepthConvention{DepthRange::negative_one_to_one, true});
  const glm::vec3 eye(float(pick_int(-100, 100)) / 10.0f, float(pick_int(-100, 100)) / 10.0f,
                      float(pick_int(-100, 100)) / 10.0f);
  glm::vec3 dir(float(pick_int(-10, 10)), float(pick_int(-10, 10)), float(pick_int(-10, 10)));
  if (dir == glm::vec3(0.0f)) dir = glm::vec3(0, 0, -1);
  glm::vec3 up(0, 1, 0);
  if (glm::length(glm::cross(dir, up)) == 0.0f) up = glm::vec3(1, 0, 0);
  const glm::mat4 view = glm::lookAtRH(eye, eye + dir, up);
  const float near_dist = float(pick_int(1, 40)) / 20.0f;
  const int proj = pick_int(0, 3);
  glm::mat4 m;
  bool infinite = false;
  if (proj == 0 || proj == 1) {
    PerspectiveCamera cam;
    cam.fovy_degrees = float(pick_int(20, 120));
    cam.aspect = float(pick_int(5, 20)) / 10.0f;
    cam.near_dist = near_dist;
    infinite = proj == 1;
    cam.far_dist = infinite ? INFINITY : near_dist * float(pick_int(2, 1000));
    cam.eye = eye;
    cam.target = eye + dir;
    cam.up = up;
    m = view_projection(cam, depth);
    c.how += infinite ? "infinite-perspective " : "perspective ";
  } else if (proj == 2) {
    const float l = -float(pick_int(1, 20)) / 10.0f, r = float(pick_int(1, 20)) / 10.0f;
    const float b = -float(pick_int(1, 20)) / 10.0f, t = float(pick_int(1, 20)) / 10.0f;
    m = off_axis_projection(l, r, b, t, near_dist, near_dist * float(pick_int(2, 300)), depth) * view;
    c.how += "off-axis ";
  } else {
    const float h = float(pick_int(1, 50));
    m = orthographic_projection(-h, h * 0.5f, -h, h, near_dist, near_dist + float(pick_int(1, 200)), depth) * view;
    c.how += "ortho ";
  }
  c.frustum = frustum_spec(m, depth);
  if (coin(3)) {
    c.how += "as-planes ";
    c.frustum.matrix.reset();
    c.frustum.depth = DepthConvention{};
  }
  // A point near the boundary: a clip-space point with one coordinate on the clip boundary,
  // unprojected in double and rounded to float (so within rounding of the boundary).
  const glm::dmat4 inv = glm::inverse(glm::dmat4(m));
  const bool zo = depth.range == DepthRange::zero_to_one;
  double cx = pick_int(-100, 100) / 100.0, cy = pick_int(-100, 100) / 100.0;
  double cz = (zo ? 0.0 : -1.0) + (infinite ? 0.9 : 1.0) * (zo ? 1.0 : 2.0) * pick_int(0, 100) / 100.0;
  switch (pick_int(0, 3)) {
    case 0: cx = coin() ? 1.0 : -1.0; break;
    case 1: cy = coin() ? 1.0 : -1.0; break;
    case 2: cz = zo ? (depth.reversed_z ? 1.0 : 0.0) : (depth.reversed_z ? 1.0 : -1.0); break;  // near
    default: cx = coin() ? 1.0 : -1.0; cy = coin() ? 1.0 : -1.0; break;                   // an edge
  }
  const glm::dvec4 h = inv * glm::dvec4(cx, cy, cz, 1.0);
  glm::vec3 p = glm::vec3(glm::dvec3(h) / h.w);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) p = eye + dir;
  // Volumes sized to the scene around p; half the time p is first moved off the boundary by up
  // to 10% of its distance to the eye, so volumes also lie just outside or just inside.
  const float scale = std::max(0.01f, glm::length(p - eye));
  if (coin()) p[pick_int(0, 2)] += scale * float(pick_int(-10, 10)) / 100.0f;
  switch (pick_int(0, 3)) {
    case 0: {
      c.how += "aabb ";
      Aabb b{p, p};
      for (int k = 0; k < 3; ++k) {
        if (coin()) b.max[k] = p[k] + scale * float(pick_int(0, 10)) / 100.0f;
        else b.min[k] = p[k] - scale * float(pick_int(0, 10)) / 100.0f;
        b.min[k] = ulps(b.min[k], small_nudge());
        b.max[k] = ulps(b.max[k], small_nudge());
        if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      }
      c.volume = b;
      break;
    }
    case 1: {
      c.how += "obb ";
      Obb o;
      const glm::vec3 angles(float(pick_int(0, 359)), float(pick_int(0, 359)), float(pick_int(0, 359)));
      o.axes = glm::mat3_cast(glm::quat(glm::radians(angles)));
      o.half = glm::vec3(float(pick_int(0, 10)), float(pick_int(0, 10)), float(pick_int(0, 10))) * (scale / 100.0f);
      o.center = p;
      for (int k = 0; k < 3; ++k) o.center[k] = ulps(o.center[k], small_nudge());
      c.volume = o;
      break;
    }
    case 2: {
      c.how += "sphere ";
      c.volume = Sphere{p, ulps(scale * float(pick_int(0, 10)) / 100.0f, small_nudge() > 0 ? 1 : 0)};
      break;
    }
    default: {
      c.how += "point ";
      Point q = p;
      for (int k = 0; k < 3; ++k) q[k] = ulps(q[k], small_nudge());
      c.volume = q;
      break;
    }
  }
  return c;
}

/// The case as one case-format JSON line (exact: shortest round-trip decimals).
inline std::string describe(const GenCase& c) {
  Case k;
  k.id = "generated";
  k.frustum = c.frustum;
  k.volume = c.volume;
  k.note = c.how;
  return format_case(k);
}

}  // namespace cullproof::oracle::test

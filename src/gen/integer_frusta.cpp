// The exact families for exact methods: frusta with integer corners (blocks.hpp).
#include "blocks.hpp"

#include <glm/gtc/quaternion.hpp>

#include <cmath>

namespace cullproof::gen::detail {

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

int between(int lo, int hi) { return int(integer(lo, hi)); }  // lo .. hi inclusive

// x moved by k ulps (k may be negative).
float ulps(float x, int k) {
  for (; k > 0; --k) x = std::nextafter(x, std::numeric_limits<float>::infinity());
  for (; k < 0; ++k) x = std::nextafter(x, -std::numeric_limits<float>::infinity());
  return x;
}
// Mostly 0, sometimes +-1 or +-2 ulps.
int small_nudge() { return one_of({0, 0, 0, 1, -1, 2, -2}); }

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
    const float s = one_of({1.0f, 1.0f, 0.5f, 2.0f, 0.0625f, 1024.0f});
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

float small_extent() { return one_of({0.0f, 0.25f, 0.5f, 1.0f, 2.0f, 3.0f, 40.0f}); }

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
      o.half[i] = one_of({0.0f, 0.25f, 0.5f, 1.0f, 2.0f});
      c += (coin(50) ? 1.0f : -1.0f) * o.half[i] * o.axes[i];
    }
    for (int k = 0; k < 3; ++k) c[k] = ulps(c[k], small_nudge());
    o.center = c;
    return o;
  }
  if (kind == 2) {  // a sphere touching p from one axis direction
    Sphere s;
    s.radius = one_of({0.0f, 0.25f, 0.5f, 1.0f, 3.0f});
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
      const float grow = one_of({0.0f, 0.0f, 1.0f, -0.5f, 10.0f});
      Aabb b{lo - grow, hi + grow};
      for (int k = 0; k < 3; ++k) {
        b.min[k] = ulps(b.min[k], small_nudge());
        b.max[k] = ulps(b.max[k], small_nudge());
        if (b.min[k] > b.max[k]) std::swap(b.min[k], b.max[k]);
      }
      return integer_case(f, b);
    }
    case 1: {  // a small box about the centroid
      const float h = one_of({0.0f, 0.125f, 0.25f, 0.5f, 1.0f});
      return integer_case(f, Aabb{centre - h, centre + h});
    }
    case 2:  // a ball about the centroid, from a point to one containing the frustum
      return integer_case(f, Sphere{centre, one_of({0.0f, 0.25f, 1.0f, 4.0f, 100.0f})});
    case 3: {  // a rotated box about the centroid
      const float h = one_of({0.25f, 1.0f, 4.0f, 30.0f});
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

}  // namespace cullproof::gen::detail

// The huge and subnormal families: generic scenes carried to the ends of the float range.
#include "blocks.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cullproof::gen::detail {

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
    scale_to(g, length, int(integer(118, 127)));
    if (coin(75)) {
      if (g.frustum.matrix) scale_matrix_to(g, int(integer(120, 127)));
      else
        for (Plane& pl : g.frustum.planes.planes) scale_plane_to(pl, int(integer(110, 127)));
    }
  } else if (kind < 60) {
    // A volume as large as a float gets about a frustum at any scale.
    const int k = scale_to(g, p.size, int(integer(-2, 119)));
    g.volume = huge_volume(scale_placement(p, k));
  } else if (kind < 80) {
    // Planes with coefficients up to FLT_MAX, ordinary volumes: n.x overflows. A power of two
    // keeps the half-space exactly; another factor rounds every coefficient.
    for (Plane& pl : g.frustum.planes.planes) {
      if (coin(50)) {
        scale_normal_to(pl, int(integer(116, 127)));
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
    scale_to(g, p.size, int(integer(0, 99)));
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
    scale_to(g, p.size, int(integer(-140, -112)));
    return g;
  }
  if (kind < 75) {
    // Planes with subnormal coefficients (largest at 2^-146 .. 2^-127), ordinary volumes: a
    // product n_i x_i underflows wherever it is below 2^-126, which with these coefficients is
    // at every coordinate below 2 in magnitude, and at larger ones for the smaller coefficients.
    GenCase g = make(cam, p, around(p));
    for (Plane& pl : g.frustum.planes.planes) scale_plane_to(pl, int(integer(-146, -127)));
    return g;
  }
  // A tiny frustum (size 2^-120 .. 2^-100) and volumes 1e-7 .. 1e-4 of it near its faces and
  // corners: subnormal extents at subnormal distances.
  const double s = p.size * rel_size(-7, -4);
  GenCase g = make(cam, p, coin(50) ? near_boundary(p, any_shape(), s) : near_corner(p, any_shape(), s));
  scale_to(g, p.size, int(integer(-120, -100)));
  return g;
}

}  // namespace cullproof::gen::detail

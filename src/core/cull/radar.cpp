// The radar approach for points and spheres.
//
// Source: Lighthouse3D "View Frustum Culling Tutorial", sections "Radar Approach - Testing
// Points", "Testing Points II", "Implementation", "Testing Spheres" and "Implementation II"
//, after F. Puig Placeres, "Improved Frustum Culling", Game Programming
// Gems 5.
// Claims: radar-point exact (the radar region is the frustum of the camera); radar-sphere
// conservative (it is the per-plane sphere test written in camera coordinates: the sphere
// factor 1/cos(alpha) turns the distance to a side plane into a distance along y or x); the
// as-published sphere variant: none (it tests a wider frustum, see below).
// Touching: every rejection is a strict `>`/`<` against the bound, so a point on the boundary
// is inside and a sphere touching a plane from outside is intersecting, as docs/semantics.md.
//
// Text errors found, and how they are handled:
//  1. "Implementation II" setCamInternals computes `tang = tan(angle)` and
//     `sphereFactorY = 1.0/cos(angle)` with `angle` the full vertical fov of gluPerspective,
//     where "Implementation" (points) uses tan(angle * 0.5). The full angle describes a frustum
//     about twice as wide: spheres outside the true frustum are reported inside (false
//     inside) or intersecting. Kept as radar_camera_as_published ("radar-sphere-as-published");
//     radar_camera uses the half angle ("radar-sphere").
//  2. setCamDef defines Z = l - p (the view direction) but pointInFrustum and sphereInFrustum
//     compute `pcz = v.innerProduct(-Z)`, which is negative in front of the camera, so read
//     literally every point in front is rejected; the prose says `pc.z = v . Z`. Both are
//     implemented with pc.z = v . Z (z_axis is the view direction). The literal reading is not
//     kept as a method: it rejects everything in front of the camera.
//  3. `camPos` in the test functions is the `cc` member of the class.
//  4. The text's pointInFrustum rejects on `pcz > farDist || pcz < nearDist`; with an infinite
//     far plane far_dist is +infinity and the comparison never rejects, as it should.
// Camera parameters from planes: radar_camera_from_frustum derives apex, axes and fov from a
// symmetric perspective frustum in double and refuses (std::nullopt) any other frustum, and any
// whose camera does not fit in float (an apex or a distance beyond FLT_MAX would be infinite).
// radar_sphere_wide (radar-sphere, cullproof's own): the test of radar_sphere, taken again in
// double when a float value overflows. Near FLT_MAX, centre - eye and the dot products overflow
// to +-inf or NaN, whose comparisons are false: a sphere at 3e38 was answered inside.
#include "cullproof/core/cull.hpp"

#include <cmath>
#include <limits>

namespace cullproof {

namespace {

constexpr double kPi = 3.14159265358979323846;

void set_factors(RadarCamera& r, double half_fovy, double ratio, bool as_published) {
  // Implementation II: `angle *= ANG2RAD; tang = tan(angle); sphereFactorY = 1/cos(angle);
  // anglex = atan(tang*ratio); sphereFactorX = 1/cos(anglex)` with angle the full fov.
  const double angle = as_published ? 2.0 * half_fovy : half_fovy;
  const double tang = std::tan(angle);
  r.tang = static_cast<float>(tang);
  r.ratio = static_cast<float>(ratio);
  r.sphere_factor_y = static_cast<float>(1.0 / std::cos(angle));
  r.sphere_factor_x = static_cast<float>(1.0 / std::cos(std::atan(tang * ratio)));
}

RadarCamera camera_impl(const PerspectiveCamera& cam, bool as_published) {
  (void)frustum_from_camera(cam);  // validates the camera (throws ValidationError)
  RadarCamera r;
  const glm::dvec3 p(cam.eye), l(cam.target), u(cam.up);
  const glm::dvec3 z = glm::normalize(l - p);  // setCamDef: Z = l - p, the view direction
  const glm::dvec3 x = glm::normalize(glm::cross(z, u));
  const glm::dvec3 y = glm::cross(x, z);
  r.eye = cam.eye;
  r.x_axis = glm::vec3(x);
  r.y_axis = glm::vec3(y);
  r.z_axis = glm::vec3(z);
  r.near_dist = cam.near_dist;
  r.far_dist = cam.far_dist;
  set_factors(r, 0.5 * double(cam.fovy_degrees) * kPi / 180.0, double(cam.aspect), as_published);
  return r;
}

struct DPlane {
  glm::dvec3 n;
  double d;
};

}  // namespace

RadarCamera radar_camera(const PerspectiveCamera& cam) { return camera_impl(cam, false); }
RadarCamera radar_camera_as_published(const PerspectiveCamera& cam) { return camera_impl(cam, true); }

std::optional<RadarCamera> radar_camera_from_frustum(const Frustum& f, bool as_published) {
  constexpr double kTol = 1e-5;
  DPlane pl[6];
  for (int i = 0; i < 5; ++i) {
    if (f[i].is_degenerate()) return std::nullopt;
    const glm::dvec3 n(f[i].n);
    const double len = glm::length(n);
    pl[i] = DPlane{n / len, double(f[i].d) / len};
  }
  const bool infinite_far = f[kFar].is_degenerate();
  if (infinite_far && !(f[kFar].d > 0.0f)) return std::nullopt;
  if (!infinite_far) {
    const glm::dvec3 n(f[kFar].n);
    const double len = glm::length(n);
    pl[kFar] = DPlane{n / len, double(f[kFar].d) / len};
  }
  const glm::dvec3 z = pl[kNear].n;
  const glm::dvec3 xr = pl[kLeft].n - pl[kRight].n, yr = pl[kBottom].n - pl[kTop].n;
  const glm::dvec3 sx = pl[kLeft].n + pl[kRight].n, sy = pl[kBottom].n + pl[kTop].n;
  const double lxr = glm::length(xr), lyr = glm::length(yr);
  const double lsx = glm::length(sx), lsy = glm::length(sy);
  if (lxr == 0.0 || lyr == 0.0 || lsx == 0.0 || lsy == 0.0) return std::nullopt;  // orthographic
  // Symmetry: the side normals' sums lie along the view axis (pointing forward), the
  // differences span the image plane, and the axes are orthogonal.
  if (glm::dot(sx, z) <= 0.0 || glm::dot(sy, z) <= 0.0) return std::nullopt;
  if (glm::length(glm::cross(sx / lsx, z)) > kTol || glm::length(glm::cross(sy / lsy, z)) > kTol)
    return std::nullopt;
  const glm::dvec3 x = xr / lxr, y = yr / lyr;
  if (std::abs(glm::dot(x, z)) > kTol || std::abs(glm::dot(y, z)) > kTol ||
      std::abs(glm::dot(x, y)) > kTol)
    return std::nullopt;
  if (!infinite_far && glm::length(pl[kFar].n + z) > kTol) return std::nullopt;
  // Apex: the point common to left, right and bottom (Cramer's rule), checked on top.
  const glm::dvec3 a = pl[kLeft].n, b = pl[kRight].n, c = pl[kBottom].n;
  const double det = glm::dot(a, glm::cross(b, c));
  if (det == 0.0) return std::nullopt;
  const glm::dvec3 apex =
      (-pl[kLeft].d * glm::cross(b, c) - pl[kRight].d * glm::cross(c, a) - pl[kBottom].d * glm::cross(a, b)) / det;
  const double scale = std::max(1.0, glm::length(apex));
  if (std::abs(glm::dot(pl[kTop].n, apex) + pl[kTop].d) > kTol * scale) return std::nullopt;
  const double near_dist = -(glm::dot(z, apex) + pl[kNear].d);
  const double far_dist = infinite_far ? std::numeric_limits<double>::infinity()
                                       : glm::dot(pl[kFar].n, apex) + pl[kFar].d;
  if (!(near_dist > 0.0) || !(far_dist > near_dist)) return std::nullopt;
  constexpr double kFloatMax = double(std::numeric_limits<float>::max());
  if (!(glm::length(apex) <= kFloatMax) || !(near_dist <= kFloatMax) || !(infinite_far || far_dist <= kFloatMax))
    return std::nullopt;
  RadarCamera r;
  r.eye = glm::vec3(apex);
  r.x_axis = glm::vec3(x);
  r.y_axis = glm::vec3(y);
  r.z_axis = glm::vec3(z);
  r.near_dist = static_cast<float>(near_dist);
  r.far_dist = static_cast<float>(far_dist);
  const double tan_hx = lsx / lxr, tan_hy = lsy / lyr;
  set_factors(r, std::atan(tan_hy), tan_hx / tan_hy, as_published);
  return r;
}

Visibility radar_point(const RadarCamera& cam, const Point& p) noexcept {
  const glm::vec3 v = p - cam.eye;
  const float pcz = dot(v, cam.z_axis);
  if (pcz > cam.far_dist || pcz < cam.near_dist) return Visibility::outside;
  const float pcy = dot(v, cam.y_axis);
  float aux = pcz * cam.tang;
  if (pcy > aux || pcy < -aux) return Visibility::outside;
  const float pcx = dot(v, cam.x_axis);
  aux = aux * cam.ratio;
  if (pcx > aux || pcx < -aux) return Visibility::outside;
  return Visibility::inside;
}

namespace {

// radar_sphere's operations in T. With T = float, `overflowed` is set (and the verdict is not to
// be used) when a value it compares is not finite. A bound that overflows alone keeps the sign
// of its exact value and compares right; an infinite coordinate or dot product, or a NaN, does
// not, and every value is checked rather than reasoning about which.
template <class T>
Visibility radar_sphere_in(const RadarCamera& cam, const Sphere& s, bool& overflowed) noexcept {
  const T radius = T(s.radius);
  const T vx = T(s.center.x) - T(cam.eye.x), vy = T(s.center.y) - T(cam.eye.y), vz = T(s.center.z) - T(cam.eye.z);
  auto dot = [&](const glm::vec3& a) { return (vx * T(a.x) + vy * T(a.y)) + vz * T(a.z); };
  const T az = dot(cam.z_axis), ay = dot(cam.y_axis), ax = dot(cam.x_axis);
  const T far_hi = T(cam.far_dist) + radius, far_lo = T(cam.far_dist) - radius;
  const T near_lo = T(cam.near_dist) - radius, near_hi = T(cam.near_dist) + radius;
  const T dy = T(cam.sphere_factor_y) * radius, zy = az * T(cam.tang);
  const T dx = T(cam.sphere_factor_x) * radius, zx = zy * T(cam.ratio);
  const T y_out = zy + dy, y_in = zy - dy, x_out = zx + dx, x_in = zx - dx;
  const bool infinite_far = std::isinf(cam.far_dist);
  overflowed = !(std::isfinite(vx) && std::isfinite(vy) && std::isfinite(vz) && std::isfinite(az) && std::isfinite(ay) &&
                 std::isfinite(ax) && std::isfinite(near_lo) && std::isfinite(near_hi) && std::isfinite(y_out) &&
                 std::isfinite(y_in) && std::isfinite(x_out) && std::isfinite(x_in) &&
                 (infinite_far || (std::isfinite(far_hi) && std::isfinite(far_lo))));
  Visibility result = Visibility::inside;
  if (az > far_hi || az < near_lo) return Visibility::outside;
  if (az > far_lo || az < near_hi) result = Visibility::intersecting;
  if (ay > y_out || ay < -y_out) return Visibility::outside;
  if (ay > y_in || ay < -y_in) result = Visibility::intersecting;
  if (ax > x_out || ax < -x_out) return Visibility::outside;
  if (ax > x_in || ax < -x_in) result = Visibility::intersecting;
  return result;
}

}  // namespace

Visibility radar_sphere_wide(const RadarCamera& cam, const Sphere& s) noexcept {
  bool overflowed = false;
  const Visibility v = radar_sphere_in<float>(cam, s, overflowed);
  if (!overflowed) return v;
  return radar_sphere_in<double>(cam, s, overflowed);
}

Visibility radar_sphere(const RadarCamera& cam, const Sphere& s) noexcept {
  const float radius = s.radius;
  Visibility result = Visibility::inside;
  const glm::vec3 v = s.center - cam.eye;
  float az = dot(v, cam.z_axis);
  if (az > cam.far_dist + radius || az < cam.near_dist - radius) return Visibility::outside;
  if (az > cam.far_dist - radius || az < cam.near_dist + radius) result = Visibility::intersecting;
  const float ay = dot(v, cam.y_axis);
  float d = cam.sphere_factor_y * radius;
  az *= cam.tang;
  if (ay > az + d || ay < -az - d) return Visibility::outside;
  if (ay > az - d || ay < -az + d) result = Visibility::intersecting;
  const float ax = dot(v, cam.x_axis);
  az *= cam.ratio;
  d = cam.sphere_factor_x * radius;
  if (ax > az + d || ax < -az - d) return Visibility::outside;
  if (ax > az - d || ax < -az + d) result = Visibility::intersecting;
  return result;
}

}  // namespace cullproof

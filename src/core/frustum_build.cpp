// Frustum construction. Sources are listed in cullproof/core/frustum_build.hpp.
#include "cullproof/core/frustum_build.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace cullproof {

glm::vec4 matrix_row(const glm::mat4& m, int i) noexcept {
  return glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]);
}

bool gribb_hartmann_halves(const glm::vec4& a, const glm::vec4& b) noexcept {
  constexpr double kMax = double(std::numeric_limits<float>::max());
  for (int i = 0; i < 4; ++i)
    if (double(std::fabs(a[i])) + double(std::fabs(b[i])) > kMax) return true;
  return false;
}

namespace {

Plane plane_of(const glm::vec4& r) noexcept { return Plane{glm::vec3(r), r.w}; }

// Rows are added in float, one rounding per coefficient. For an infinite projection the two
// rows agree exactly in their first three entries, so the difference is exactly zero: the far
// plane comes out as n == 0, d > 0 without any special case. Rows that reach past FLT_MAX
// (gribb_hartmann_halves) are halved first: the sum of two halves cannot overflow, and half the
// plane is the same half-space.
glm::vec4 row_add(const glm::vec4& a, const glm::vec4& b) noexcept {
  return gribb_hartmann_halves(a, b) ? a * 0.5f + b * 0.5f : a + b;
}
glm::vec4 row_sub(const glm::vec4& a, const glm::vec4& b) noexcept {
  return gribb_hartmann_halves(a, b) ? a * 0.5f - b * 0.5f : a - b;
}

void require(bool ok, const char* field, const std::string& problem) {
  if (!ok) throw ValidationError(std::string(field) + ": " + problem);
}

glm::dvec3 to_d(const glm::vec3& v) { return glm::dvec3(v); }

// Reversal of depth in clip space: z' = w - z for [0,1], z' = -z for [-1,1].
glm::mat4 reverse_depth(const glm::mat4& proj, DepthRange range) {
  glm::mat4 r(1.0f);
  r[2][2] = -1.0f;
  if (range == DepthRange::zero_to_one) r[3][2] = 1.0f;
  return r * proj;
}

}  // namespace

Frustum frustum_from_matrix(const glm::mat4& m, DepthConvention depth) {
  const glm::vec4 r1 = matrix_row(m, 0), r2 = matrix_row(m, 1), r3 = matrix_row(m, 2),
                  r4 = matrix_row(m, 3);
  Frustum f;
  f[kLeft] = plane_of(row_add(r4, r1));
  f[kRight] = plane_of(row_sub(r4, r1));
  f[kBottom] = plane_of(row_add(r4, r2));
  f[kTop] = plane_of(row_sub(r4, r2));
  // Lower and upper depth bounds: z >= lo and z <= w.
  const glm::vec4 lower = depth.range == DepthRange::negative_one_to_one ? row_add(r4, r3) : r3;
  const glm::vec4 upper = row_sub(r4, r3);
  f[kNear] = plane_of(depth.reversed_z ? upper : lower);
  f[kFar] = plane_of(depth.reversed_z ? lower : upper);
  return f;
}

CaseFrustum frustum_spec(const Frustum& planes) { return CaseFrustum{planes, std::nullopt, {}}; }

CaseFrustum frustum_spec(const glm::mat4& matrix, DepthConvention depth) {
  return CaseFrustum{frustum_from_matrix(matrix, depth), matrix, depth};
}

Frustum local_frustum(const glm::mat4& view_proj, const glm::mat4& model, DepthConvention depth) {
  return frustum_from_matrix(view_proj * model, depth);
}

namespace {

void validate_camera(const PerspectiveCamera& c) {
  validate(c.eye, "camera.eye");
  validate(c.target, "camera.target");
  validate(c.up, "camera.up");
  require(std::isfinite(c.fovy_degrees) && c.fovy_degrees > 0.0f && c.fovy_degrees < 180.0f,
          "camera.fovy_degrees", "must be in (0, 180), got " + std::to_string(c.fovy_degrees));
  require(std::isfinite(c.aspect) && c.aspect > 0.0f, "camera.aspect",
          "must be positive and finite, got " + std::to_string(c.aspect));
  require(std::isfinite(c.near_dist) && c.near_dist > 0.0f, "camera.near_dist",
          "must be positive and finite, got " + std::to_string(c.near_dist));
  require(!std::isnan(c.far_dist) && c.far_dist > c.near_dist, "camera.far_dist",
          "must be greater than near_dist (or +infinity), got " + std::to_string(c.far_dist));
  const glm::dvec3 dir = to_d(c.target) - to_d(c.eye);
  require(glm::length(dir) > 0.0, "camera.target", "equals camera.eye (no view direction)");
  require(glm::length(glm::cross(dir, to_d(c.up))) > 0.0, "camera.up",
          "is zero or parallel to the view direction");
}

}  // namespace

Frustum frustum_from_camera(const PerspectiveCamera& c) {
  validate_camera(c);
  // Lighthouse3D setCamInternals / setCamDef, in double. Z points away from the view direction;
  // X = up x Z; Y = Z x X (the tutorial's "*" is the cross product).
  const double tang = std::tan(glm::radians(double(c.fovy_degrees)) * 0.5);
  const double nh = c.near_dist * tang, nw = nh * c.aspect;
  const glm::dvec3 p = to_d(c.eye);
  const glm::dvec3 Z = glm::normalize(p - to_d(c.target));
  const glm::dvec3 X = glm::normalize(glm::cross(to_d(c.up), Z));
  const glm::dvec3 Y = glm::cross(Z, X);
  const glm::dvec3 nc = p - Z * double(c.near_dist);

  auto make = [](const glm::dvec3& normal, const glm::dvec3& point) {
    const glm::dvec3 n = glm::normalize(normal);
    return Plane{glm::vec3(n), float(-glm::dot(n, point))};
  };
  Frustum f;
  f[kNear] = make(-Z, nc);
  if (std::isinf(c.far_dist)) {
    f[kFar] = Plane{glm::vec3(0.0f), 1.0f};
  } else {
    f[kFar] = make(Z, p - Z * double(c.far_dist));
  }
  glm::dvec3 aux = glm::normalize((nc + Y * nh) - p);
  f[kTop] = make(glm::cross(aux, X), nc + Y * nh);
  aux = glm::normalize((nc - Y * nh) - p);
  f[kBottom] = make(glm::cross(X, aux), nc - Y * nh);
  aux = glm::normalize((nc - X * nw) - p);
  f[kLeft] = make(glm::cross(aux, Y), nc - X * nw);
  aux = glm::normalize((nc + X * nw) - p);
  f[kRight] = make(glm::cross(Y, aux), nc + X * nw);
  return f;
}

glm::mat4 perspective_projection(float fovy_degrees, float aspect, float near_dist, float far_dist, DepthConvention depth) {
  const float fovy = glm::radians(fovy_degrees);
  glm::mat4 proj;
  if (std::isinf(far_dist)) {
    if (depth.range == DepthRange::negative_one_to_one) {
      proj = glm::infinitePerspective(fovy, aspect, near_dist);
    } else {
      // Infinite [0,1] projection (the limit of perspectiveRH_ZO as far -> infinity).
      const float t = std::tan(fovy / 2.0f);
      proj = glm::mat4(0.0f);
      proj[0][0] = 1.0f / (aspect * t);
      proj[1][1] = 1.0f / t;
      proj[2][2] = -1.0f;
      proj[2][3] = -1.0f;
      proj[3][2] = -near_dist;
    }
  } else if (depth.range == DepthRange::negative_one_to_one) {
    proj = glm::perspectiveRH_NO(fovy, aspect, near_dist, far_dist);
  } else {
    proj = glm::perspectiveRH_ZO(fovy, aspect, near_dist, far_dist);
  }
  if (depth.reversed_z) proj = reverse_depth(proj, depth.range);
  return proj;
}

glm::mat4 view_projection(const PerspectiveCamera& c, DepthConvention depth) {
  validate_camera(c);
  return perspective_projection(c.fovy_degrees, c.aspect, c.near_dist, c.far_dist, depth) *
         glm::lookAtRH(c.eye, c.target, c.up);
}

glm::vec3 hoff_cop_world(const HoffCamera& c) noexcept {
  return c.origin + c.cop.x * c.horizon + c.cop.y * c.view_up + c.cop.z * c.vpn;
}

Frustum frustum_from_hoff_camera(const HoffCamera& c) {
  validate(c.origin, "hoff_camera.origin");
  validate(c.horizon, "hoff_camera.horizon");
  validate(c.view_up, "hoff_camera.view_up");
  validate(c.vpn, "hoff_camera.vpn");
  validate(c.cop, "hoff_camera.cop");
  require(c.window_left < c.window_right, "hoff_camera.window_left", "must be < window_right");
  require(c.window_bottom < c.window_top, "hoff_camera.window_bottom", "must be < window_top");
  require(std::isfinite(c.near_z) && c.near_z < c.cop.z, "hoff_camera.near_z",
          "must be finite and below cop.z (the camera looks along -z)");
  require(!std::isnan(c.far_z) && c.far_z < c.near_z, "hoff_camera.far_z",
          "must be below near_z (or -infinity)");
  // Planes in camera coordinates (derivation: each side plane contains the COP and one window
  // edge; its normal is orthogonal to both and points to the window's inside):
  //   left   n = ( cz, 0, wl - cx)     right n = (-cz, 0, cx - wr)
  //   bottom n = ( 0, cz, wb - cy)     top   n = ( 0, -cz, cy - wt)
  //   near   z <= near_z               far   z >= far_z
  const double cx = c.cop.x, cy = c.cop.y, cz = c.cop.z;
  const glm::dvec3 cop(cx, cy, cz);
  struct P { glm::dvec3 n; double d; };
  auto through_cop = [&](glm::dvec3 n) { return P{n, -glm::dot(n, cop)}; };
  P cam[6] = {
      through_cop({cz, 0.0, c.window_left - cx}),
      through_cop({-cz, 0.0, cx - c.window_right}),
      through_cop({0.0, cz, c.window_bottom - cy}),
      through_cop({0.0, -cz, cy - c.window_top}),
      P{{0.0, 0.0, -1.0}, double(c.near_z)},
      P{{0.0, 0.0, 1.0}, -double(c.far_z)},
  };
  // World = origin + R * camera, with R = [horizon view_up vpn] (columns).
  const glm::dmat3 R(to_d(c.horizon), to_d(c.view_up), to_d(c.vpn));
  Frustum f;
  for (int i = 0; i < 6; ++i) {
    if (i == kFar && std::isinf(c.far_z)) {
      f[i] = Plane{glm::vec3(0.0f), 1.0f};
      continue;
    }
    const glm::dvec3 n = glm::normalize(R * cam[i].n);
    const double scale = glm::length(cam[i].n);
    const double d = cam[i].d / scale - glm::dot(n, to_d(c.origin));
    f[i] = Plane{glm::vec3(n), float(d)};
  }
  return f;
}

glm::mat4 off_axis_projection(float l, float r, float b, float t, float n, float f,
                              DepthConvention depth) {
  glm::mat4 p = depth.range == DepthRange::negative_one_to_one ? glm::frustumRH_NO(l, r, b, t, n, f)
                                                             : glm::frustumRH_ZO(l, r, b, t, n, f);
  return depth.reversed_z ? reverse_depth(p, depth.range) : p;
}

glm::mat4 orthographic_projection(float l, float r, float b, float t, float n, float f,
                                  DepthConvention depth) {
  glm::mat4 p = depth.range == DepthRange::negative_one_to_one ? glm::orthoRH_NO(l, r, b, t, n, f)
                                                             : glm::orthoRH_ZO(l, r, b, t, n, f);
  return depth.reversed_z ? reverse_depth(p, depth.range) : p;
}

std::array<glm::mat4, 2> stereo_view_projections(const StereoRig& rig, DepthConvention depth) {
  const PerspectiveCamera& c = rig.center;
  validate_camera(c);
  require(std::isfinite(rig.convergence) && rig.convergence > 0.0f, "stereo.convergence",
          "must be positive");
  require(std::isfinite(rig.eye_separation) && rig.eye_separation >= 0.0f,
          "stereo.eye_separation", "must be >= 0");
  const float top = c.near_dist * std::tan(glm::radians(c.fovy_degrees) / 2.0f);
  const float half_w = top * c.aspect;
  const glm::vec3 dir = glm::normalize(c.target - c.eye);
  const glm::vec3 right = glm::normalize(glm::cross(dir, c.up));
  std::array<glm::mat4, 2> out;
  for (int eye = 0; eye < 2; ++eye) {
    const float sign = eye == 0 ? -1.0f : 1.0f;  // left eye sits at -right
    const float offset = sign * rig.eye_separation / 2.0f;
    // Window shift so both frusta meet at the convergence plane.
    const float shift = offset * c.near_dist / rig.convergence;
    const glm::mat4 proj =
        off_axis_projection(-half_w - shift, half_w - shift, -top, top, c.near_dist,
                            std::isinf(c.far_dist) ? 1e30f : c.far_dist, depth);
    const glm::vec3 e = c.eye + offset * right;
    out[static_cast<std::size_t>(eye)] = proj * glm::lookAtRH(e, e + dir, c.up);
  }
  return out;
}

namespace {

bool corners_impl(const Frustum& f, std::array<glm::dvec3, 8>& out) {
  for (const Plane& p : f.planes)
    if (p.is_degenerate()) return false;
  for (int i = 0; i < 8; ++i) {
    const Plane& lr = f[(i & 1) ? kRight : kLeft];
    const Plane& bt = f[(i & 2) ? kTop : kBottom];
    const Plane& nf = f[(i & 4) ? kFar : kNear];
    const auto x = planes_meet(lr, bt, nf);
    if (!x) return false;
    out[static_cast<std::size_t>(i)] = *x;
  }
  return true;
}

}  // namespace

std::optional<glm::dvec3> planes_meet(const glm::dvec4& a, const glm::dvec4& b, const glm::dvec4& c) noexcept {
  const glm::dvec3 na(a), nb(b), nc(c);
  const glm::dvec3 bc = glm::cross(nb, nc);
  const double det = glm::dot(na, bc);
  const glm::dvec3 aa = glm::abs(na), ab = glm::abs(nb), ac = glm::abs(nc);
  const double terms = aa.x * (ab.y * ac.z + ab.z * ac.y) + aa.y * (ab.x * ac.z + ab.z * ac.x) +
                       aa.z * (ab.x * ac.y + ab.y * ac.x);
  if (!(std::abs(det) > kMeetCutoff * terms) || !std::isfinite(det)) return std::nullopt;
  const glm::dvec3 x = (-a.w * bc - b.w * glm::cross(nc, na) - c.w * glm::cross(na, nb)) / det;
  if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) return std::nullopt;
  return x;
}

std::optional<glm::dvec3> planes_meet(const Plane& a, const Plane& b, const Plane& c) noexcept {
  return planes_meet(glm::dvec4(glm::dvec3(a.n), double(a.d)), glm::dvec4(glm::dvec3(b.n), double(b.d)),
                     glm::dvec4(glm::dvec3(c.n), double(c.d)));
}

std::array<glm::dvec3, 8> frustum_corners(const Frustum& f) {
  std::array<glm::dvec3, 8> out{};
  if (!corners_impl(f, out))
    throw std::domain_error("frustum_corners: the frustum is unbounded (a degenerate plane, or three planes that do not meet in a point)");
  return out;
}

bool is_bounded(const Frustum& f) noexcept {
  std::array<glm::dvec3, 8> out{};
  return corners_impl(f, out);
}

glm::dvec3 frustum_center(const Frustum& f) {
  const auto c = frustum_corners(f);
  glm::dvec3 s(0.0);
  for (const auto& p : c) s += p;
  return s / 8.0;
}

bool is_symmetric(const Frustum& f, double rel_tol) {
  std::array<glm::dvec3, 8> c{};
  if (!corners_impl(f, c)) return false;
  double size = 0.0;
  for (const auto& p : c) size = std::max(size, glm::length(p - c[0]));
  if (size == 0.0) return false;
  const double tol = rel_tol * size;
  auto face_ok = [&](int base, glm::dvec3& centre) {
    const glm::dvec3 &p0 = c[base], &p1 = c[base + 1], &p2 = c[base + 2], &p3 = c[base + 3];
    // Parallelogram (diagonals bisect each other) with equal diagonals: a rectangle.
    if (glm::length((p0 + p3) - (p1 + p2)) > 2 * tol) return false;
    if (std::abs(glm::length(p3 - p0) - glm::length(p2 - p1)) > tol) return false;
    centre = (p0 + p1 + p2 + p3) / 4.0;
    return true;
  };
  glm::dvec3 cn, cf;
  if (!face_ok(0, cn) || !face_ok(4, cf)) return false;
  const glm::dvec3 axis = cf - cn;
  const double len = glm::length(axis);
  if (len == 0.0) return false;
  const glm::dvec3 a = axis / len;
  // The axis is perpendicular to both faces (near and far parallel, centres aligned).
  for (int base : {0, 4}) {
    const glm::dvec3 e1 = c[base + 1] - c[base], e2 = c[base + 2] - c[base];
    if (std::abs(glm::dot(e1, a)) > tol || std::abs(glm::dot(e2, a)) > tol) return false;
  }
  // Far edges parallel to near edges.
  for (int k : {1, 2}) {
    const glm::dvec3 en = c[k] - c[0], ef = c[4 + k] - c[4];
    const double ln = glm::length(en), lf = glm::length(ef);
    if (ln == 0.0 || lf == 0.0) return false;
    if (glm::length(glm::cross(en / ln, ef / lf)) * size > tol) return false;
  }
  return true;
}

}  // namespace cullproof

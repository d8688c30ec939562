// Perspective-transform baseline (the DirectModel culler).
//
// Source: Assarsson & Möller 2000, §2 "Related Work" and figure 1: "perspective transform the
// bounding volume ... bounded by a minimal AABB ... testing two AABBs against each other, which
// can be done with only six comparisons after the transformation has been done"; §4: Table 1's
// speedups are relative to this culler [DirectModel 1.0 Specification, HP 1998]
//. The DirectModel source is not public; this is the procedure as the paper
// describes it: 8 corners times the clip matrix (72+ multiplications), division by w, the NDC
// AABB of the 8 results, and the six comparisons with the NDC cube ([-1,1]^3, or depth [0,1]
// for zero_to_one / reversed-Z, whose cube is the same set).
//
// perspective_transform_as_published: exactly that. The paper does not say what happens to
// corners behind the eye plane (w <= 0). Dividing by a negative w mirrors the point through
// the eye, and w == 0 gives infinities or NaN, so the NDC AABB of a box straddling the eye plane
// is not a bound of its projection. Confirmed false reject (tests): a visible box from behind the
// eye (z = 1) to beyond the far plane (z = -20) around the view axis; behind the eye ndc z =
// clip.z / w > 1, beyond far ndc z > 1, so the NDC box lies above z = 1 and is rejected. (A
// search over 750k boxes straddling the eye plane but ending before the far plane found no
// error: the mirrored corners then make the NDC box large, not wrong in the rejecting way.)
// Claim: none (published method under test).
//
// perspective_transform (corrected): when every corner has w > 0 the box lies in front of the
// eye plane, where the projective map preserves convexity, so the NDC AABB of the corners
// bounds the projected box and the published comparison is sound. Otherwise the test falls
// back to homogeneous outcodes (Cohen–Sutherland in clip space: -w <= x <= w, ...), which need
// no division: all eight corners outside one clip half-space -> outside, else intersecting.
// Claim: none. Conservative in exact arithmetic, but in float the 8 clip transforms and the
// divisions by w round in proportion to the matrix entries and 1/w, which for narrow fields of
// view and planes far from the origin exceeds any rounding tolerance measured on the planes:
// the oracle found false rejects at distances up to ~1e-3 of the scene (corpus cases under
// corpus/perspective-transform/). cullproof keeps it as Table 1's baseline and measures it.
// Touching (both): rejections are strict (`hi.x < -1`, `w + x < 0`), acceptance is `>=`/`<=`,
// so a box touching a plane from outside is intersecting and one touching from inside is
// inside, as docs/semantics.md.
#include "cullproof/core/cull.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cullproof {

namespace {

void corners_clip(const glm::mat4& m, const Aabb& b, glm::vec4 (&out)[8]) noexcept {
  for (int k = 0; k < 8; ++k) {
    const glm::vec4 p((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y,
                      (k & 4) ? b.max.z : b.min.z, 1.0f);
    out[k] = m * p;
  }
}

Visibility ndc_compare(const glm::vec4 (&c)[8], DepthConvention depth) noexcept {
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const glm::vec4& v : c) {
    const glm::vec3 ndc = glm::vec3(v) / v.w;
    lo = glm::min(lo, ndc);
    hi = glm::max(hi, ndc);
  }
  const float zlo = depth.range == DepthRange::negative_one_to_one ? -1.0f : 0.0f;
  if (hi.x < -1.0f || lo.x > 1.0f || hi.y < -1.0f || lo.y > 1.0f || hi.z < zlo || lo.z > 1.0f)
    return Visibility::outside;
  if (lo.x >= -1.0f && hi.x <= 1.0f && lo.y >= -1.0f && hi.y <= 1.0f && lo.z >= zlo && hi.z <= 1.0f)
    return Visibility::inside;
  return Visibility::intersecting;
}

}  // namespace

Visibility perspective_transform_as_published(const glm::mat4& m, DepthConvention depth,
                                              const Aabb& box) noexcept {
  glm::vec4 c[8];
  corners_clip(m, box, c);
  return ndc_compare(c, depth);
}

Visibility perspective_transform(const glm::mat4& m, DepthConvention depth, const Aabb& box) noexcept {
  glm::vec4 c[8];
  corners_clip(m, box, c);
  bool all_front = true;
  for (const glm::vec4& v : c) all_front = all_front && v.w > 0.0f;
  if (all_front) return ndc_compare(c, depth);
  // Homogeneous outcodes: bit set when the corner is outside that clip half-space.
  unsigned all = 0x3fu;
  for (const glm::vec4& v : c) {
    unsigned code = 0;
    if (v.w + v.x < 0.0f) code |= 1u;
    if (v.w - v.x < 0.0f) code |= 2u;
    if (v.w + v.y < 0.0f) code |= 4u;
    if (v.w - v.y < 0.0f) code |= 8u;
    if ((depth.range == DepthRange::negative_one_to_one ? v.w + v.z : v.z) < 0.0f) code |= 16u;
    if (v.w - v.z < 0.0f) code |= 32u;
    all &= code;
  }
  return all != 0 ? Visibility::outside : Visibility::intersecting;
}

std::optional<glm::mat4> clip_matrix_from_frustum(const Frustum& f) {
  // Normalise (double) so that residuals compare across planes.
  glm::dvec4 p[6];
  for (int i = 0; i < 6; ++i) {
    glm::dvec4 v(f[i].n.x, f[i].n.y, f[i].n.z, f[i].d);
    const double len = f[i].is_degenerate() ? std::abs(v.w) : glm::length(glm::dvec3(v));
    if (len == 0.0) return std::nullopt;
    p[i] = v / len;
  }
  // Unknown positive scales s = (b, c, e, g, h) with L + b R = c B + e T = g N + h F
  // (OpenGL: 2 r4 = (r4 + r1) + (r4 - r1) = (r4 + r2) + (r4 - r2) = (r4 + r3) + (r4 - r3)).
  double a[8][5] = {}, rhs[8];
  for (int k = 0; k < 4; ++k) {
    a[k][0] = p[kRight][k]; a[k][1] = -p[kBottom][k]; a[k][2] = -p[kTop][k];
    rhs[k] = -p[kLeft][k];
    a[4 + k][0] = p[kRight][k]; a[4 + k][3] = -p[kNear][k]; a[4 + k][4] = -p[kFar][k];
    rhs[4 + k] = -p[kLeft][k];
  }
  double m[5][6] = {};  // normal equations, augmented
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 8; ++k) m[i][j] += a[k][i] * a[k][j];
    for (int k = 0; k < 8; ++k) m[i][5] += a[k][i] * rhs[k];
  }
  for (int col = 0; col < 5; ++col) {
    int piv = col;
    for (int r = col + 1; r < 5; ++r)
      if (std::abs(m[r][col]) > std::abs(m[piv][col])) piv = r;
    if (std::abs(m[piv][col]) < 1e-14) return std::nullopt;
    for (int j = 0; j < 6; ++j) std::swap(m[col][j], m[piv][j]);
    for (int r = 0; r < 5; ++r) {
      if (r == col) continue;
      const double fct = m[r][col] / m[col][col];
      for (int j = col; j < 6; ++j) m[r][j] -= fct * m[col][j];
    }
  }
  double s[5];
  for (int i = 0; i < 5; ++i) {
    s[i] = m[i][5] / m[i][i];
    if (!(s[i] > 0.0)) return std::nullopt;
  }
  double res = 0.0;
  for (int k = 0; k < 8; ++k) {
    double r = -rhs[k];
    for (int j = 0; j < 5; ++j) r += a[k][j] * s[j];
    res = std::max(res, std::abs(r));
  }
  if (res > 1e-6) return std::nullopt;
  const glm::dvec4 r4 = 0.5 * (p[kLeft] + s[0] * p[kRight]);
  const glm::dvec4 r1 = 0.5 * (p[kLeft] - s[0] * p[kRight]);
  const glm::dvec4 r2 = 0.5 * (s[1] * p[kBottom] - s[2] * p[kTop]);
  const glm::dvec4 r3 = 0.5 * (s[3] * p[kNear] - s[4] * p[kFar]);
  glm::mat4 out(0.0f);
  const glm::dvec4 rows[4] = {r1, r2, r3, r4};
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) out[col][row] = static_cast<float>(rows[row][col]);
  if (f[kFar].is_degenerate()) {
    // Infinite far plane: make r4 - r3 come out with an exactly zero normal in float, as
    // docs/semantics.md requires ("contains all space"), keeping its offset positive.
    for (int col = 0; col < 3; ++col) out[col][2] = out[col][3];
    out[3][2] = static_cast<float>(r4.w - s[4] * p[kFar].w);
  }
  return out;
}

}  // namespace cullproof

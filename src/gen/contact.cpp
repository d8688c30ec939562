// The contact family: float-exact contact with faces, edges and corners (blocks.hpp).
#include "blocks.hpp"

#include <glm/ext/matrix_clip_space.hpp>

namespace cullproof::gen::detail {

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
// A frame (contact_frame) draws the frustum; its volumes (contact_volume) are drawn each on its
// own, all in contact with that frustum.

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

// An orthographic frame: the box, its world frame and its form (unit planes, or a matrix in any
// depth convention).
void ortho_frame(ContactFrame& cf) {
  cf.ortho = true;
  cf.e = exact_frame();
  cf.w = std::ldexp(1.0f, int(integer(-1, 2)));  // 0.5 .. 4
  cf.f = cf.e.n + std::ldexp(1.0f, int(integer(0, 4)));
  const ExactFrame& e = cf.e;
  const float w = cf.w, n = e.n, f = cf.f;
  cf.unit_planes = coin(50);
  if (cf.unit_planes) {
    Frustum fr;
    fr.planes[kLeft] = world_plane(e, {1, 0, 0}, w);
    fr.planes[kRight] = world_plane(e, {-1, 0, 0}, w);
    fr.planes[kBottom] = world_plane(e, {0, 1, 0}, w);
    fr.planes[kTop] = world_plane(e, {0, -1, 0}, w);
    fr.planes[kNear] = world_plane(e, {0, 0, -1}, -n);
    fr.planes[kFar] = world_plane(e, {0, 0, 1}, f);
    cf.frustum = frustum_spec(fr);
  } else {
    const DepthConvention depth = any_depth();
    glm::mat4 p = depth.range == DepthRange::negative_one_to_one ? glm::orthoRH_NO(-w, w, -w, w, n, f)
                                                                  : glm::orthoRH_ZO(-w, w, -w, w, n, f);
    if (depth.reversed_z) p = reverse_depth(p, depth.range);
    cf.frustum = frustum_spec(p * view_of(e), depth);
  }
}

// A volume in contact with an orthographic frame's box.
GenCase ortho_volume(const ContactFrame& cf) {
  const ExactFrame& e = cf.e;
  const float w = cf.w, n = e.n, f = cf.f;
  // 0-3 box, 4-5 OBB, 6-7 point, 8-13 sphere (on unit planes only, where its test is exact: one
  // case in ten a sphere, as many as when every sphere drew its own frustum)
  const int shape = pick(cf.unit_planes ? 14 : 8);
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
  g.frustum = cf.frustum;
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

// A perspective frame: the touch family's integer frustum, in any depth convention, with a finite
// or an infinite far plane, as planes or as the matrix.
void perspective_frame(ContactFrame& cf) {
  cf.ortho = false;
  const DepthConvention depth = any_depth();
  const bool infinite = coin(25), as_matrix = coin(50);
  cf.e = exact_frame();
  const ExactFrame& e = cf.e;
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
  cf.frustum = frustum_spec(p * view_of(e), depth);
  if (!as_matrix) cf.frustum.matrix.reset();
}

// The touch family's contacts on a perspective frame. A sphere (the lateral planes' normals are
// not unit) becomes its bounding box, which keeps the contact with a near or far face.
GenCase perspective_volume(const ContactFrame& cf) {
  GenCase g = touch_on(cf.e, false, [&] { return cf.frustum; });
  if (const Sphere* sp = std::get_if<Sphere>(&g.volume)) g.volume = Aabb{sp->center - sp->radius, sp->center + sp->radius};
  return g;
}

ContactFrame contact_frame() {
  ContactFrame cf;
  if (coin(50)) ortho_frame(cf);
  else perspective_frame(cf);
  return cf;
}

GenCase contact_volume(const ContactFrame& cf) { return cf.ortho ? ortho_volume(cf) : perspective_volume(cf); }

GenCase contact_case() { return contact_volume(contact_frame()); }

}  // namespace cullproof::gen::detail

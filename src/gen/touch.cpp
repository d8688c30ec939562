// The touch and ulp families: exactly touching a plane, then moved an ulp (blocks.hpp), on
// exact frames, which the contact family shares.
#include "blocks.hpp"

#include <glm/ext/matrix_clip_space.hpp>

namespace cullproof::gen::detail {


ExactFrame exact_frame() {
  ExactFrame e;
  static const int kPerm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  const int* perm = kPerm[pick(6)];
  glm::mat3 r(0.0f);
  for (int i = 0; i < 3; ++i) r[i][perm[i]] = coin(50) ? 1.0f : -1.0f;
  e.rot = r;
  e.shift = glm::vec3(float(integer(-64, 64)), float(integer(-64, 64)), float(integer(-64, 64)));
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
  return lo + float(integer(0, steps)) / 16.0f;
}

GenCase touch_case(bool nudge, const std::function<CaseFrustum(const ExactFrame&)>& frustum) {
  const ExactFrame e = exact_frame();
  return touch_on(e, nudge, [&] { return frustum ? frustum(e) : exact_frustum(e, coin(30)); });
}

GenCase touch_on(const ExactFrame& e, bool nudge, const std::function<CaseFrustum()>& frustum) {
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
  g.frustum = frustum();
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


}  // namespace cullproof::gen::detail

// A culler as an engine writes it: its own plane type, its own plane extraction from the
// view-projection matrix (Gribb & Hartmann 2001), and the n/p-vertex box test (Assarsson &
// Möller 2000, §3.1). Nothing here depends on cullproof.
#pragma once

#include <glm/glm.hpp>

#include <array>

namespace my {

struct Plane {
  glm::vec3 n;  // points into the frustum
  float d;
  float at(const glm::vec3& x) const { return n.x * x.x + n.y * x.y + n.z * x.z + d; }
};
using Planes = std::array<Plane, 6>;

// Left, right, bottom, top, near, far of clip = M * x, for depth in [-1, 1] (OpenGL) or [0, 1].
inline Planes planes_from_matrix(const glm::mat4& m, bool zero_to_one) {
  auto row = [&](int i) { return glm::vec4(m[0][i], m[1][i], m[2][i], m[3][i]); };
  const glm::vec4 r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
  const glm::vec4 p[6] = {r3 + r0, r3 - r0, r3 + r1, r3 - r1, zero_to_one ? r2 : r3 + r2, r3 - r2};
  Planes out;
  for (int i = 0; i < 6; ++i) out[i] = Plane{glm::vec3(p[i]), p[i].w};
  return out;
}

enum class Result { outside, intersecting, inside };

// The n/p-vertex test. `bug` plants a one-token mistake: "inside" decided from the p-vertex
// instead of the n-vertex, so a box straddling a plane is reported inside.
inline Result classify_box(const Planes& planes, const glm::vec3& lo, const glm::vec3& hi, bool bug = false) {
  bool inside = true;
  for (const Plane& p : planes) {
    const glm::vec3 pv(p.n.x >= 0 ? hi.x : lo.x, p.n.y >= 0 ? hi.y : lo.y, p.n.z >= 0 ? hi.z : lo.z);
    const glm::vec3 nv(p.n.x >= 0 ? lo.x : hi.x, p.n.y >= 0 ? lo.y : hi.y, p.n.z >= 0 ? lo.z : hi.z);
    if (p.at(pv) < 0) return Result::outside;
    if (p.at(bug ? pv : nv) < 0) inside = false;
  }
  return inside ? Result::inside : Result::intersecting;
}

}  // namespace my

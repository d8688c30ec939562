// n/p-vertex test for OBBs: the plane normal projected on the box axes.
//
// Sources: Assarsson & Möller 2000, §3.1 ("finding the n- and p-vertices can be done in 9
// multiplications and 3 comparisons by projecting the normal of the view frustum plane on to
// the box's axes and test the signs") and figure 4; Lighthouse3D "Geometric Approach - Testing
// Boxes II" (nb = (bx.n, by.n, bz.n), after Möller & Haines) .
// The p-vertex is c + sum_i s_i h_i u_i with s_i = +1 when dot(u_i, n) > 0 (else -1); the
// n-vertex is c - sum_i s_i h_i u_i. Each is built in float, then evaluated; sign translation
// as in pn_vertex.cpp.
// Claim: conservative (in exact arithmetic the p-vertex is the farthest point of the
// parallelepiped along n, so rejection is exact per plane); in float the corners are rounded,
// so errors only within rounding distance of the boundary.
// Touching: p-vertex value == 0 is intersecting, n-vertex value == 0 is inside, as docs/semantics.md.
#include "cullproof/core/cull.hpp"

namespace cullproof {

Visibility obb_pn_vertex(const Frustum& frustum, const Obb& box) noexcept {
  const glm::vec3 e0 = box.axes[0] * box.half.x;
  const glm::vec3 e1 = box.axes[1] * box.half.y;
  const glm::vec3 e2 = box.axes[2] * box.half.z;
  bool intersect = false;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& pl = frustum[i];
    // Normal in the box's frame: nb = (u0.n, u1.n, u2.n); its signs pick the vertex.
    const glm::vec3 a = dot(box.axes[0], pl.n) > 0.0f ? e0 : -e0;
    const glm::vec3 b = dot(box.axes[1], pl.n) > 0.0f ? e1 : -e1;
    const glm::vec3 c = dot(box.axes[2], pl.n) > 0.0f ? e2 : -e2;
    const glm::vec3 offset = (a + b) + c;
    if (pl.eval(box.center + offset) < 0.0f) return Visibility::outside;
    if (pl.eval(box.center - offset) < 0.0f) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

}  // namespace cullproof

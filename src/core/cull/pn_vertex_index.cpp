// p-vertex selection with the branch-free min/max index trick.
//
// Source: blog post "View frustum culling (AABB vs Frustum)", section "Implementation",
// intersectFrustumAABB.
// Two functions:
//  - p_vertex_post: as published. box[] = {min, max}, index = (int)(a > 0), only the p-vertex
//    is tested and `dp < -p.d` rejects. The post's test is two-way (intersects or not): it
//    returns outside or intersecting, never inside. The post visits planes in the order
//    near, left, right, bottom, top, far; the verdict does not depend on the order.
//  - pn_vertex_index: the same trick made three-way (the n-vertex index is 1 - p index), so the
//    verdicts equal pn_vertex (A&M fig. 4) wherever the float plane values are finite. Where a
//    value overflows float (coordinates or coefficients near FLT_MAX: two products of opposite
//    signs overflow to +inf and -inf and make NaN, whose every comparison is false), it is taken
//    again in double (plane_value): without that, a box from -3e38 to 3e38 around the frustum
//    came out inside.
// Claim: conservative (both), as pn_vertex; pn_vertex_index also on the whole float range.
// Touching: `dp < -d` is false for dp == -d, so a box touching a plane from outside is not
// rejected (intersecting). In float, dp < -d and dp + d < 0 give the same answer (the rounded
// sum of two floats has the sign of the exact sum), so this is docs/semantics.md's `>= 0` inside.
// Text errors noted: the post's prose says "(a,b,d) is the plane normal" and "if sign(d) > 0,
// take zmax" in one revision (readers' comments 1-2); the code uses (a,b,c), which is right.
#include "cullproof/core/cull.hpp"

namespace cullproof {

Visibility p_vertex_post(const Frustum& f, const Aabb& b) noexcept {
  const glm::vec3 box[] = {b.min, b.max};
  static constexpr int kOrder[kPlaneCount] = {kNear, kLeft, kRight, kBottom, kTop, kFar};
  for (int i : kOrder) {
    const Plane& p = f[i];
    const int px = static_cast<int>(p.n.x > 0.0f);
    const int py = static_cast<int>(p.n.y > 0.0f);
    const int pz = static_cast<int>(p.n.z > 0.0f);
    const float dp = (p.n.x * box[px].x) + (p.n.y * box[py].y) + (p.n.z * box[pz].z);
    if (dp < -p.d) return Visibility::outside;
  }
  return Visibility::intersecting;
}

Visibility pn_vertex_index(const Frustum& f, const Aabb& b) noexcept {
  const glm::vec3 box[] = {b.min, b.max};
  bool intersect = false;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& p = f[i];
    const int px = static_cast<int>(p.n.x > 0.0f);
    const int py = static_cast<int>(p.n.y > 0.0f);
    const int pz = static_cast<int>(p.n.z > 0.0f);
    const glm::vec3 pv(box[px].x, box[py].y, box[pz].z);
    const glm::vec3 nv(box[1 - px].x, box[1 - py].y, box[1 - pz].z);
    if (plane_value(p, pv) < 0.0) return Visibility::outside;
    if (plane_value(p, nv) < 0.0) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

}  // namespace cullproof

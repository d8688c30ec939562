// n/p-vertex test for AABBs with per-box sign selection.
//
// Source: U. Assarsson, T. Möller, "Optimized View Frustum Culling Algorithms for Bounding
// Boxes", JGT 2000, §3.1 "Basic Intersection Test", figure 4; the same test
// is Lighthouse3D "Geometric Approach - Testing Boxes II".
// Sign translation: A&M call x outside plane i when n_i.x + d_i > 0 (normals point out). With
// docs/semantics.md (inside when dot(n, x) + d >= 0, normals in) their n-vertex ("negative far
// point") is our p-vertex (the corner farthest along our inward normal), and their `a > 0`
// rejection is our `eval(p-vertex) < 0`; their `b > 0` (intersect) is `eval(n-vertex) < 0`.
// Claim: conservative. Outside only when the box is outside one plane; a box outside the
// frustum near an edge is reported intersecting (A&M fig. 2: "this is an approximation").
// Touching: p-vertex value == 0 is not rejected (touching from outside is intersecting);
// n-vertex value == 0 is inside (touching from inside). Agrees with docs/semantics.md.
// The plane value is evaluated as ((n.x*x + n.y*y) + n.z*z) + d (Plane::eval); the SIMD batch
// (batch_soa.cpp) uses the same order so that its verdicts are bit-for-bit the same.
#include "cullproof/core/cull.hpp"

namespace cullproof {

Visibility pn_vertex(const Frustum& frustum, const Aabb& box) noexcept {
  bool intersect = false;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& pl = frustum[i];
    // Per-box sign selection: the p-vertex takes the max along each axis where n > 0.
    glm::vec3 p, n;
    if (pl.n.x > 0.0f) { p.x = box.max.x; n.x = box.min.x; } else { p.x = box.min.x; n.x = box.max.x; }
    if (pl.n.y > 0.0f) { p.y = box.max.y; n.y = box.min.y; } else { p.y = box.min.y; n.y = box.max.y; }
    if (pl.n.z > 0.0f) { p.z = box.max.z; n.z = box.min.z; } else { p.z = box.min.z; n.z = box.max.z; }
    if (pl.eval(p) < 0.0f) return Visibility::outside;
    if (pl.eval(n) < 0.0f) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

}  // namespace cullproof

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
// The plane value is evaluated as ((n.x*x + n.y*y) + n.z*z) + d (Plane::eval, test_selected_plane);
// the SIMD batch (batch_soa.cpp) uses the same order so that its verdicts are bit-for-bit the same.
#include "cullproof/core/cull.hpp"
#include "cullproof/core/node_tests.hpp"

namespace cullproof {

Visibility pn_vertex(const Frustum& frustum, const Aabb& box) noexcept {
  // Per-box sign selection: the p-vertex takes the max along each axis where n > 0
  // (select_plane), then each plane's test in order (node::all_planes).
  std::uint64_t tests = 0;
  return node::all_planes(node::SelectedPlanes(frustum), box, tests);
}

}  // namespace cullproof

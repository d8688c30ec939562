// The "reverse" test: n/p-vertex, then the frustum's corners against the box's planes.
//
// Source: the blog post "View frustum culling (AABB vs Frustum)", readers' comments 5-6: "since a frustum is a
// convex solid, the same optimization should work in reverse ... take the normal of the sides of
// the AABB and test the closest corner of the frustum against it". The forward stage is the
// n/p-vertex test of Assarsson & Möller 2000 §3.1 (normal projected on the box axes for an OBB).
// Claim: conservative. It removes the false intersects whose separating axis is a box face
// normal; the ones that need an edge-cross-edge axis remain (sat-exact removes those).
// Touching: a corner on a box face plane is not outside it, so touching stays intersecting.
#include "cullproof/exact.hpp"

#include "hull.hpp"

namespace cullproof {

using namespace exact_detail;

Visibility pn_vertex_reverse(const Frustum& f, const Obb& b) {
  bool straddles = false;
  for (const Plane& p : f.planes) {
    const float s = p.eval(b.center), r = obb_radius(b, p.n);
    if (s + r < 0.0f) return Visibility::outside;
    if (s - r < 0.0f) straddles = true;
  }
  if (!straddles) return Visibility::inside;
  const auto hull = frustum_hull(f);
  if (!hull) return Visibility::intersecting;
  if (hull->empty) return Visibility::outside;
  // Each box face plane: outward normal m = +-(u_j x u_l), through c +- h_k u_k.
  for (int k = 0; k < 3; ++k) {
    glm::vec3 m = glm::cross(b.axes[(k + 1) % 3], b.axes[(k + 2) % 3]);
    if (glm::dot(m, b.axes[k]) < 0.0f) m = -m;  // left-handed axes: point m along u_k
    for (float side : {1.0f, -1.0f}) {
      const glm::vec3 n = side * m;
      const float off = glm::dot(b.center + (side * b.half[k]) * b.axes[k], n);
      bool all_out = true;
      for (const glm::vec3& v : hull->vertices) all_out = all_out && glm::dot(v, n) > off;
      for (const glm::vec3& r : hull->rays) all_out = all_out && glm::dot(r, n) >= 0.0f;
      if (all_out) return Visibility::outside;
    }
  }
  return Visibility::intersecting;
}

}  // namespace cullproof

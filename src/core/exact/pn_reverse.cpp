// The "reverse" test: n/p-vertex, then the frustum's corners against the box's planes.
//
// Source: the blog post "View frustum culling (AABB vs Frustum)", readers' comments 5-6: "since a frustum is a
// convex solid, the same optimization should work in reverse ... take the normal of the sides of
// the AABB and test the closest corner of the frustum against it". The forward stage is the
// n/p-vertex test of Assarsson & Möller 2000 §3.1 (normal projected on the box axes for an OBB).
// Claim: conservative. It removes the false intersects whose separating axis is a box face
// normal; the ones that need an edge-cross-edge axis remain (sat-exact removes those).
// Touching: a corner on a box face plane is not outside it, so touching stays intersecting.
// The whole float range: where the case's magnitudes leave float's comfortable range
// (float_range_ok, hull_range_ok), the same operations run in double; in float the centre value
// and projected radius of a box near FLT_MAX overflow (a box from -3e38 to 3e38 around the
// frustum came out inside), and so do the frustum's vertices beyond FLT_MAX.
#include "cullproof/core/exact.hpp"

#include "hull.hpp"

#include <type_traits>

namespace cullproof {

using namespace exact_detail;

namespace {

template <class T>
int pn_vertex_reverse_in(const Frustum& f, const Obb& b) {
  bool straddles = false;
  const Vec3<T> center = vec_as<T>(b.center);
  for (const Plane& p : f.planes) {
    const T s = plane_eval(p, center), r = obb_radius_as<T>(b, vec_as<T>(p.n));
    if (s + r < T(0)) return int(Visibility::outside);
    if (s - r < T(0)) straddles = true;
  }
  if (!straddles) return int(Visibility::inside);
  const auto hull = frustum_hull_as<T>(f);
  if (!hull) return int(Visibility::intersecting);
  if (hull->empty) return int(Visibility::outside);
  if (std::is_same_v<T, float> && !hull_range_ok(f, b, hull->magnitude)) return kRedo;
  // Each box face plane: outward normal m = +-(u_j x u_l), through c +- h_k u_k.
  const Vec3<T> axes[3] = {vec_as<T>(b.axes[0]), vec_as<T>(b.axes[1]), vec_as<T>(b.axes[2])};
  for (int k = 0; k < 3; ++k) {
    Vec3<T> m = glm::cross(axes[(k + 1) % 3], axes[(k + 2) % 3]);
    if (glm::dot(m, axes[k]) < T(0)) m = -m;  // left-handed axes: point m along u_k
    for (T side : {T(1), T(-1)}) {
      const Vec3<T> n = side * m;
      const T off = glm::dot(center + (side * T(b.half[k])) * axes[k], n);
      bool all_out = true;
      for (const Vec3<T>& v : hull->vertices) all_out = all_out && glm::dot(v, n) > off;
      for (const Vec3<T>& r : hull->rays) all_out = all_out && glm::dot(r, n) >= T(0);
      if (all_out) return int(Visibility::outside);
    }
  }
  return int(Visibility::intersecting);
}

}  // namespace

Visibility pn_vertex_reverse(const Frustum& f, const Obb& b) {
  int r = float_range_ok(f, b) ? pn_vertex_reverse_in<float>(f, b) : kRedo;
  if (r == kRedo) r = pn_vertex_reverse_in<double>(f, b);
  return Visibility(r);
}

}  // namespace cullproof

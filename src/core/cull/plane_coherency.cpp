// Plane-coherency test.
//
// Source: Assarsson & Möller 2000, §3.2 "The Plane-Coherency Test";
// Lighthouse3D "Further Optimization - Plane Coherence".
// "If the BV was outside a plane last frame, then an index to this plane is cached in the BV
// structure. For each intersection test, we start testing against that plane and test the
// others afterwards if necessary. We test the planes in the order: left, right, near, far, up,
// and down." Each plane test is the n/p-vertex test of §3.1 (sign translation as in
// pn_vertex.cpp). A plane that does not reject leaves the cache as it was.
// Valid for every frustum. Claim: conservative; the verdict equals pn_vertex for any cache
// content (the same six plane tests, only their order changes).
// Touching: as pn_vertex (touching from outside: intersecting; from inside: inside).
#include "cullproof/core/cull_coherence.hpp"

namespace cullproof {

Visibility plane_coherency_test(const Frustum& f, const Aabb& box, PlaneCoherencyCache& cache,
                                std::uint64_t* plane_tests) noexcept {
  static constexpr int kOrder[kPlaneCount] = {kLeft, kRight, kNear, kFar, kTop, kBottom};
  const int first = cache.last_outside_plane;
  bool intersect = false;
  std::uint64_t tests = 0;
  auto test = [&](int i) -> bool {  // true: rejected by plane i
    const Plane& pl = f[i];
    ++tests;
    const glm::vec3 p(pl.n.x > 0.0f ? box.max.x : box.min.x, pl.n.y > 0.0f ? box.max.y : box.min.y,
                      pl.n.z > 0.0f ? box.max.z : box.min.z);
    if (pl.eval(p) < 0.0f) return true;
    const glm::vec3 n(pl.n.x > 0.0f ? box.min.x : box.max.x, pl.n.y > 0.0f ? box.min.y : box.max.y,
                      pl.n.z > 0.0f ? box.min.z : box.max.z);
    if (pl.eval(n) < 0.0f) intersect = true;
    return false;
  };
  Visibility result = Visibility::inside;
  if (first >= 0 && first < kPlaneCount && test(first)) {
    result = Visibility::outside;
  } else {
    for (int i : kOrder) {
      if (i == first) continue;
      if (test(i)) {
        cache.last_outside_plane = static_cast<std::int8_t>(i);
        result = Visibility::outside;
        break;
      }
    }
    if (result != Visibility::outside && intersect) result = Visibility::intersecting;
  }
  if (plane_tests) *plane_tests += tests;
  return result;
}

}  // namespace cullproof

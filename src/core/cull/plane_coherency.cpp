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
#include "cullproof/core/node_tests.hpp"

namespace cullproof {

Visibility plane_coherency_test(const Frustum& f, const Aabb& box, PlaneCoherencyCache& cache,
                                std::uint64_t* plane_tests) noexcept {
  std::uint64_t tests = 0;
  const Visibility v = node::plane_coherency(node::SelectedPlanes(f), box, cache.last_outside_plane, tests);
  if (plane_tests) *plane_tests += tests;
  return v;
}

}  // namespace cullproof

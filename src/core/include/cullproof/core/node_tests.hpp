// Per-node culling tests over planes whose p- and n-vertex selection is done once per frame
// (plane_select.hpp), each counting the plane tests it makes: the building blocks of the per-case
// tests (pn_vertex, plane_coherency_test) and of the hierarchical cullers the simulator times
// (Assarsson & Möller 2000, Table 1). Inline, so that every composition pays the same call
// overhead. Every plane test is test_selected_plane: A&M §3.1's n/p-vertex test, evaluated
// ((nx*x + ny*y) + nz*z) + d (value < 0 at the p-vertex: outside the plane; at the n-vertex:
// straddling it), so a verdict is bit for bit pn_vertex's.
#pragma once

#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/core/geometry.hpp"
#include "cullproof/core/plane_select.hpp"

#include <algorithm>
#include <cstdint>

namespace cullproof::node {

/// The six planes of a frustum, selected.
struct SelectedPlanes {
  SelectedPlane p[6];
  SelectedPlanes() = default;
  explicit SelectedPlanes(const Frustum& f) noexcept {
    for (int i = 0; i < 6; ++i) p[i] = select_plane(f[i]);
  }
};

/// All six planes in the plane order of docs/semantics.md, stopping at the first that rejects
/// (A&M §3.1).
inline Visibility all_planes(const SelectedPlanes& s, const Aabb& box, std::uint64_t& tests) noexcept {
  const float* b = box_floats(box);
  bool intersect = false;
  for (int i = 0; i < 6; ++i) {
    ++tests;
    const int r = test_selected_plane(s.p[i], b);
    if (r == 0) return Visibility::outside;
    if (r == 1) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

/// A&M §3.2 plane coherency: the plane that rejected the box last time first (`cache`, -1: none),
/// then left, right, near, far, top, bottom; a plane that rejects is cached, one that does not
/// leaves the cache as it was. The verdict is all_planes' for any cache content.
inline Visibility plane_coherency(const SelectedPlanes& s, const Aabb& box, std::int8_t& cache,
                                  std::uint64_t& tests) noexcept {
  static constexpr int kOrder[6] = {kLeft, kRight, kNear, kFar, kTop, kBottom};
  const float* b = box_floats(box);
  const int first = cache >= 0 && cache < 6 ? cache : -1;
  bool intersect = false;
  if (first >= 0) {
    ++tests;
    const int r = test_selected_plane(s.p[first], b);
    if (r == 0) return Visibility::outside;
    if (r == 1) intersect = true;
  }
  for (int i : kOrder) {
    if (i == first) continue;
    ++tests;
    const int r = test_selected_plane(s.p[i], b);
    if (r == 0) {
      cache = static_cast<std::int8_t>(i);
      return Visibility::outside;
    }
    if (r == 1) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

/// The masking step (A&M §3.4 after Bishop et al. 1998; Cesium's "mask[planeIndex]"): the planes
/// whose bit is set in `mask` (lowest first), clearing the bits of planes the box is inside.
/// Outside when one rejects; inside when the mask ends empty; else intersecting.
inline Visibility masked(const SelectedPlanes& s, const Aabb& box, std::uint32_t& mask, std::uint64_t& tests) noexcept {
  const float* b = box_floats(box);
  for (std::uint32_t m = mask; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    ++tests;
    const int r = test_selected_plane(s.p[i], b);
    if (r == 0) return Visibility::outside;
    if (r == 2) mask &= ~(1u << i);
  }
  return mask == 0 ? Visibility::inside : Visibility::intersecting;
}

/// The octant of a box centre (A&M §3.3, fig. 5): of each pair of opposite planes (left/right,
/// bottom/top, near/far) of the normalised frustum, the one the centre is nearer to is outer, the
/// other inner; `nearer[k]` is the centre's value at the outer one. The choice OctantCuller makes.
inline void octant_sides(const Frustum& normalised, const glm::vec3& centre, int (&outer)[3], int (&inner)[3],
                         float (&nearer)[3]) noexcept {
  for (int k = 0; k < 3; ++k) {
    const int a = 2 * k, b = 2 * k + 1;
    const float va = normalised[a].eval(centre), vb = normalised[b].eval(centre);
    outer[k] = va <= vb ? a : b;
    inner[k] = va <= vb ? b : a;
    nearer[k] = std::min(va, vb);
  }
}

/// Plane coherency and the octant test together (A&M Table 1 "plane coherency + octant"): the
/// plane that rejected the box last time first (`cache`, -1: none; `given` the frustum's planes
/// as given, selected), then OctantCuller's corrected octant test, whose rejecting outer plane is
/// cached. The verdict is classify_corrected's wherever the cached plane does not reject.
inline Visibility octant_coherent(const OctantCuller& octant, const SelectedPlanes& given, const Aabb& box,
                                  std::int8_t& cache, std::uint64_t& tests) noexcept {
  if (cache >= 0 && cache < 6) {
    ++tests;
    if (test_selected_plane(given.p[cache], box_floats(box)) == 0) return Visibility::outside;
  }
  return octant.classify_corrected(box, tests, cache);
}

}  // namespace cullproof::node

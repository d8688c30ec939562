// Per-node culling tests over planes whose p- and n-vertex selection is done once per frame
// (plane_select.hpp), each counting the plane tests it makes: the building blocks of the per-case
// tests (pn_vertex, plane_coherency_test) and of the hierarchical cullers the simulator times
// (Assarsson & Möller 2000, Table 1). Inline, so that every composition pays the same call
// overhead. Every plane test is test_selected_plane: A&M §3.1's n/p-vertex test, evaluated
// ((nx*x + ny*y) + nz*z) + d (value < 0 at the p-vertex: outside the plane; at the n-vertex:
// straddling it), so a verdict is bit for bit pn_vertex's.
#pragma once

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

/// Per-frame data of octant_coherent: the normalised planes, selected, and the squared centre
/// distance d1^2 (-1 when the frustum centre is outside a plane: the octant never applies).
struct OctantFrame {
  Frustum planes;
  SelectedPlanes sel;
  double d1_sq = -1.0;
  OctantFrame() = default;
  /// From a frustum OctantCuller accepts and its centre_distance().
  OctantFrame(const Frustum& f, double centre_distance) noexcept {
    planes = f.normalized();
    sel = SelectedPlanes(planes);
    d1_sq = centre_distance > 0.0 ? centre_distance * centre_distance : -1.0;
  }
};

/// Plane coherency and the octant test together (A&M Table 1 "plane coherency + octant"): when
/// the box's half-diagonal d2 is at most d1 (fig. 6's precondition), the cached plane first, then
/// the three outer planes; inside when the box's bounding sphere is inside the three outer planes
/// (its centre's value at least d2, in float), else as the three inner planes confirm; a box
/// larger than that takes plane_coherency. A rejecting plane is cached.
inline Visibility octant_coherent(const OctantFrame& o, const Aabb& box, std::int8_t& cache,
                                  std::uint64_t& tests) noexcept {
  const glm::vec3 h = box.half_extent();
  const double d2_sq = double(h.x) * h.x + double(h.y) * h.y + double(h.z) * h.z;
  if (!(d2_sq <= o.d1_sq)) return plane_coherency(o.sel, box, cache, tests);
  const float* b = box_floats(box);
  const int first = cache >= 0 && cache < 6 ? cache : -1;
  int r_first = -1;
  if (first >= 0) {  // the plane that rejected the box last frame, first
    ++tests;
    r_first = test_selected_plane(o.sel.p[first], b);
    if (r_first == 0) return Visibility::outside;
  }
  int outer[3], inner[3];
  float nearer[3];
  octant_sides(o.planes, box.center(), outer, inner, nearer);
  bool sphere_inside = true;
  for (int k = 0; k < 3; ++k) {
    const double m = nearer[k];
    sphere_inside = sphere_inside && m >= 0.0 && m * m >= d2_sq;
  }
  bool intersect = false;
  for (int k = 0; k < 3; ++k) {
    if (outer[k] == first) {  // already tested above (not outside)
      if (r_first == 1) intersect = true;
      continue;
    }
    ++tests;
    const int r = test_selected_plane(o.sel.p[outer[k]], b);
    if (r == 0) {
      cache = static_cast<std::int8_t>(outer[k]);
      return Visibility::outside;
    }
    if (r == 1) intersect = true;
  }
  if (sphere_inside) return Visibility::inside;
  if (intersect) return Visibility::intersecting;
  for (int k = 0; k < 3; ++k) {
    ++tests;
    if (test_selected_plane(o.sel.p[inner[k]], b) != 2) return Visibility::intersecting;
  }
  return Visibility::inside;
}

}  // namespace cullproof::node

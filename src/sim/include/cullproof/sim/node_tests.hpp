// Per-node tests of the simulator's configurations, inline so that every configuration pays the
// same traversal and call overhead (Table 1 compares them by time).
//
// Each test is the library's algorithm with identical float evaluation (tests/sim checks verdicts
// bit for bit against cull.hpp / cull_coherence.hpp on random boxes):
//  - np_test          = the per-plane n/p-vertex test of pn_vertex.cpp / bvh_traverse.cpp
//                       (A&M 2000 §3.1; value < 0 at the p-vertex: outside; at the n-vertex:
//                       intersecting), evaluated ((nx*x + ny*y) + nz*z) + d;
//  - basic_np         = pn_vertex (planes in the plane order of docs/semantics.md);
//  - plane_coherency  = plane_coherency_test (cached plane first, then left, right, near, far,
//                       top, bottom);
//  - octant_pc        = OctantCuller::classify_corrected (A&M §3.3 with fig. 6's precondition;
//                       inside only when the bounding sphere is inside the three outer planes or
//                       the inner planes confirm it) with the plane-coherency cache tested first
//                       and updated by the rejecting plane (the composition "plane coherency +
//                       octant" of A&M Table 1);
//  - masked_np        = the masking step of cull_bvh_masked (A&M §3.4, Cesium): planes whose bit
//                       is clear in the mask are skipped, planes the box is inside are cleared.
#pragma once

#include "cullproof/core/geometry.hpp"
#include "cullproof/core/plane_select.hpp"

#include <cstdint>

namespace cullproof::sim {

using SelPlane = SelectedPlane;
inline int np_test(const SelPlane& s, const float* b) noexcept { return test_selected_plane(s, b); }

inline Visibility from_code(bool outside, bool intersect) noexcept {
  return outside ? Visibility::outside : intersect ? Visibility::intersecting : Visibility::inside;
}

/// Six planes, the plane order of docs/semantics.md, early exit on the first rejecting plane.
inline Visibility basic_np(const SelPlane (&p)[6], const Aabb& box, std::uint64_t& tests) noexcept {
  const float* b = box_floats(box);
  bool intersect = false;
  for (int i = 0; i < 6; ++i) {
    ++tests;
    const int r = np_test(p[i], b);
    if (r == 0) return Visibility::outside;
    if (r == 1) intersect = true;
  }
  return from_code(false, intersect);
}

/// A&M §3.2 plane coherency; `cache` is the plane that rejected the box last time (-1: none).
inline Visibility plane_coherency(const SelPlane (&p)[6], const Aabb& box, std::int8_t& cache,
                                  std::uint64_t& tests) noexcept {
  static constexpr int kOrder[6] = {kLeft, kRight, kNear, kFar, kTop, kBottom};
  const float* b = box_floats(box);
  const int first = cache;
  bool intersect = false;
  if (first >= 0) {
    ++tests;
    const int r = np_test(p[first], b);
    if (r == 0) return Visibility::outside;
    if (r == 1) intersect = true;
  }
  for (int i : kOrder) {
    if (i == first) continue;
    ++tests;
    const int r = np_test(p[i], b);
    if (r == 0) {
      cache = static_cast<std::int8_t>(i);
      return Visibility::outside;
    }
    if (r == 1) intersect = true;
  }
  return from_code(false, intersect);
}

/// Per-frame data of the octant test: normalised planes and the squared centre distance d1^2
/// (as OctantCuller: -1 when the frustum centre is outside a plane, so the octant never applies).
struct OctantFrame {
  Plane planes[6];      ///< normalised (Frustum::normalized)
  SelPlane sel[6];      ///< of the normalised planes
  double d1_sq = -1.0;
};

/// Plane coherency + octant (A&M Table 1 row 2), on the normalised planes.
inline Visibility octant_pc(const OctantFrame& o, const Aabb& box, std::int8_t& cache, std::uint64_t& tests) noexcept {
  const glm::vec3 h = box.half_extent();
  const double d2_sq = double(h.x) * h.x + double(h.y) * h.y + double(h.z) * h.z;
  if (!(d2_sq <= o.d1_sq)) return plane_coherency(o.sel, box, cache, tests);
  const float* b = box_floats(box);
  const int first = cache;
  int r_first = -1;
  if (first >= 0) {  // the plane that rejected the box last frame, first
    ++tests;
    r_first = np_test(o.sel[first], b);
    if (r_first == 0) return Visibility::outside;
  }
  const glm::vec3 c = box.center();
  int outer[3], inner[3];
  bool sphere_inside = true;
  for (int k = 0; k < 3; ++k) {
    const int a = 2 * k, bb = 2 * k + 1;
    const float va = o.planes[a].eval(c), vb = o.planes[bb].eval(c);
    outer[k] = va <= vb ? a : bb;
    inner[k] = va <= vb ? bb : a;
    const double m = std::min(va, vb);
    sphere_inside = sphere_inside && m >= 0.0 && m * m >= d2_sq;
  }
  bool intersect = false;
  for (int k = 0; k < 3; ++k) {
    if (outer[k] == first) {  // already tested above (not outside)
      if (r_first == 1) intersect = true;
      continue;
    }
    ++tests;
    const int r = np_test(o.sel[outer[k]], b);
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
    if (np_test(o.sel[inner[k]], b) != 2) return Visibility::intersecting;
  }
  return Visibility::inside;
}

/// Masking step: tests the planes whose bit is set in `mask`, clears the bits of planes the box
/// is inside. Returns outside, or intersecting/inside (inside when the mask ends empty).
inline Visibility masked_np(const SelPlane (&p)[6], const Aabb& box, std::uint32_t& mask, std::uint64_t& tests) noexcept {
  const float* b = box_floats(box);
  for (std::uint32_t m = mask; m != 0; m &= m - 1) {
    const int i = __builtin_ctz(m);
    ++tests;
    const int r = np_test(p[i], b);
    if (r == 0) return Visibility::outside;
    if (r == 2) mask &= ~(1u << i);
  }
  return mask == 0 ? Visibility::inside : Visibility::intersecting;
}

}  // namespace cullproof::sim

// A plane with its p- and n-vertex selection hoisted: the per-plane part of the n/p-vertex test
// (Assarsson & Möller 2000, §3.1, after Haines & Wallace 1994) done once per frame, so that the
// per-box part is two evaluations with no selection. The BVH traversals, the SIMD batch and the
// simulator's node tests all select through select_plane.
#pragma once

#include "cullproof/core/geometry.hpp"

#include <cstddef>

namespace cullproof {

static_assert(sizeof(Aabb) == 6 * sizeof(float), "Aabb must be six packed floats");
static_assert(offsetof(Aabb, max) == 3 * sizeof(float), "Aabb layout: min then max");

/// A plane and, per axis, which of a box's six floats (min x, y, z, max x, y, z) its p-vertex
/// (px, py, pz: the corner farthest along the normal) and n-vertex (qx, qy, qz) read.
struct SelectedPlane {
  float nx = 0, ny = 0, nz = 0, d = 0;
  int px = 0, py = 1, pz = 2, qx = 3, qy = 4, qz = 5;
};

/// The p-vertex reads max where the normal component is > 0, as pn_vertex does.
inline SelectedPlane select_plane(const Plane& pl) noexcept {
  SelectedPlane s;
  s.nx = pl.n.x; s.ny = pl.n.y; s.nz = pl.n.z; s.d = pl.d;
  s.px = pl.n.x > 0.0f ? 3 : 0; s.qx = 3 - s.px;
  s.py = pl.n.y > 0.0f ? 4 : 1; s.qy = 5 - s.py;
  s.pz = pl.n.z > 0.0f ? 5 : 2; s.qz = 7 - s.pz;
  return s;
}

/// A box as its six floats, in select_plane's order.
inline const float* box_floats(const Aabb& b) noexcept { return &b.min.x; }

/// One plane against a box's six floats: 0 outside, 1 intersecting, 2 inside the plane. Evaluated
/// ((nx*x + ny*y) + nz*z) + d, Plane::eval's order, so the verdict is bit for bit pn_vertex's.
inline int test_selected_plane(const SelectedPlane& s, const float* b) noexcept {
  const float pv = ((s.nx * b[s.px] + s.ny * b[s.py]) + s.nz * b[s.pz]) + s.d;
  if (pv < 0.0f) return 0;
  const float nv = ((s.nx * b[s.qx] + s.ny * b[s.qy]) + s.nz * b[s.qz]) + s.d;
  return nv < 0.0f ? 1 : 2;
}

}  // namespace cullproof

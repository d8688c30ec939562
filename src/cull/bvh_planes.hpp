// Internal to src/cull: the frustum planes as the BVH traversals use them (bvh_traverse.cpp,
// bvh_wide_traverse.cpp), with each plane's p- and n-vertex selection hoisted once per call.
// Node test: Assarsson & Möller 2000 §3.1 (the n/p-vertex test of pn_vertex.cpp), evaluated as
// ((nx*x + ny*y) + nz*z) + d, Plane::eval's order, so a verdict is bit-for-bit pn_vertex's.
#pragma once

#include "cullproof/geometry.hpp"

#include <cstddef>
#include <cstdint>

namespace cullproof::bvh_detail {

static_assert(sizeof(Aabb) == 6 * sizeof(float), "Aabb must be six packed floats");
static_assert(offsetof(Aabb, max) == 3 * sizeof(float), "Aabb layout: min then max");

// A plane with its p-vertex selection hoisted: index of the coordinate among a box's six floats
// (Aabb: min x, y, z, max x, y, z; BvhWideNode::box rows in the same order).
struct SelPlane {
  float nx, ny, nz, d;
  int px, py, pz, qx, qy, qz;  // p-vertex and n-vertex coordinate indices
};

struct Prepared {
  SelPlane p[6];
  explicit Prepared(const Frustum& f) {
    for (int i = 0; i < 6; ++i) {
      const Plane& pl = f[i];
      SelPlane& s = p[i];
      s.nx = pl.n.x; s.ny = pl.n.y; s.nz = pl.n.z; s.d = pl.d;
      s.px = pl.n.x > 0.0f ? 3 : 0; s.qx = 3 - s.px;
      s.py = pl.n.y > 0.0f ? 4 : 1; s.qy = 5 - s.py;
      s.pz = pl.n.z > 0.0f ? 5 : 2; s.qz = 7 - s.pz;
    }
  }
};

inline const float* floats(const Aabb& b) noexcept { return &b.min.x; }

// One plane against a box's six floats: 0 outside, 1 intersecting, 2 inside the plane.
inline int test_plane(const SelPlane& s, const float* b) noexcept {
  const float pv = ((s.nx * b[s.px] + s.ny * b[s.py]) + s.nz * b[s.pz]) + s.d;
  if (pv < 0.0f) return 0;
  const float nv = ((s.nx * b[s.qx] + s.ny * b[s.qy]) + s.nz * b[s.qz]) + s.d;
  return nv < 0.0f ? 1 : 2;
}

// A primitive's box against the planes of `mask` (bit k: plane k), lowest first, stopping at the
// first plane it is outside: 0 outside, 1 intersecting, 2 inside those planes. `tests` counts the
// planes evaluated.
inline int test_masked(const Prepared& prep, const float* b, std::uint32_t mask, std::uint64_t& tests) noexcept {
  int result = 2;
  for (std::uint32_t m = mask; m != 0; m &= m - 1) {
    ++tests;
    const int r = test_plane(prep.p[__builtin_ctz(m)], b);
    if (r == 0) return 0;
    if (r == 1) result = 1;
  }
  return result;
}

}  // namespace cullproof::bvh_detail

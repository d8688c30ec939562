// Internal to src/cull: the frustum planes as the BVH traversals use them (bvh_traverse.cpp,
// bvh_wide_traverse.cpp), with each plane's p- and n-vertex selection hoisted once per call
// (cullproof/core/plane_select.hpp).
// Node test: Assarsson & Möller 2000 §3.1 (the n/p-vertex test of pn_vertex.cpp), evaluated as
// ((nx*x + ny*y) + nz*z) + d, Plane::eval's order, so a verdict is bit-for-bit pn_vertex's.
#pragma once

#include "cullproof/core/geometry.hpp"
#include "cullproof/core/node_tests.hpp"
#include "cullproof/core/plane_select.hpp"

#include <cstdint>

namespace cullproof::bvh_detail {

using SelPlane = SelectedPlane;

using Prepared = node::SelectedPlanes;

inline const float* floats(const Aabb& b) noexcept { return box_floats(b); }
inline int test_plane(const SelPlane& s, const float* b) noexcept { return test_selected_plane(s, b); }

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

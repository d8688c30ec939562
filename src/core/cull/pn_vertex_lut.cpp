// n/p-vertex test for AABBs with the sign bitfields precomputed once per frame.
//
// Source: Assarsson & Möller 2000, §3.1, last two paragraphs ("we can use this bitfield to get
// the p-vertex from a Look Up Table", "precompute the bitfields ... once each frame
// [Haines94]") and §4 (5-10% faster than per-box selection).
// Bitfield: bit k set when component k of the (inward) normal is > 0; the p-vertex takes max
// on those axes. The n-vertex uses the inverted bitfield ("if we order the LUT properly, we can
// invert the bitfield to get the n-vertex"). Sign translation as in pn_vertex.cpp.
// Claim: conservative; verdicts identical to pn_vertex (same vertices, same evaluation order).
// Touching: as pn_vertex (touching from outside: intersecting; from inside: inside).
#include "cullproof/core/cull.hpp"

namespace cullproof {

PnLut make_pn_lut(const Frustum& frustum) noexcept {
  PnLut lut;
  lut.frustum = frustum;
  for (int i = 0; i < kPlaneCount; ++i) {
    const glm::vec3& n = frustum[i].n;
    lut.p_bits[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(
        (n.x > 0.0f ? 1u : 0u) | (n.y > 0.0f ? 2u : 0u) | (n.z > 0.0f ? 4u : 0u));
  }
  return lut;
}

Visibility pn_vertex_lut(const PnLut& lut, const Aabb& box) noexcept {
  // The eight corners as a LUT indexed by the bitfield: corner k takes max on axis j iff bit j.
  const float xs[2] = {box.min.x, box.max.x};
  const float ys[2] = {box.min.y, box.max.y};
  const float zs[2] = {box.min.z, box.max.z};
  bool intersect = false;
  for (int i = 0; i < kPlaneCount; ++i) {
    const unsigned pb = lut.p_bits[static_cast<std::size_t>(i)];
    const unsigned nb = ~pb & 7u;
    const Plane& pl = lut.frustum[i];
    const glm::vec3 p(xs[pb & 1u], ys[(pb >> 1) & 1u], zs[(pb >> 2) & 1u]);
    if (pl.eval(p) < 0.0f) return Visibility::outside;
    const glm::vec3 n(xs[nb & 1u], ys[(nb >> 1) & 1u], zs[(nb >> 2) & 1u]);
    if (pl.eval(n) < 0.0f) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

}  // namespace cullproof

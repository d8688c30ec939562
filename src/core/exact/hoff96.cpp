// Hoff 1996 as published.
//
// Source: Kenny Hoff, "A 'Fast' Method for Culling of Oriented-Bounding Boxes (OBBs) Against a
// Perspective Viewing Frustum in Large 'Walkthrough' Models", 5/23/96, the
// whole procedure ("here is the proposed implementation").
// Claim: exact (the text presents it as an exact overlap test); cullproof checks the claim.
//
// The procedure, step by step as written:
//  1. the eight OBB vertices from its axes and extents;
//  2. a 6-bit in/out code per vertex, a set bit meaning outside that plane;
//  3. planes processed in the order near, left, right, bottom, top, far: encode the eight
//     vertices against the plane; if the AND of the eight codes is non-zero, REJECT;
//  4. if any code is zero (the first one found), ACCEPT;
//  5. each of the 12 frustum edges against each of the 6 OBB faces: ACCEPT on the first hit;
//  6. the "origin of the frustum" inside the OBB: ACCEPT;
//  7. otherwise REJECT.
// Touching: a vertex on a plane is inside it (eval < 0 sets the bit), face tests are closed.
// Step 6's point: the caller passes it. The registry passes the centre of projection (the apex
// of the four side planes), reading Hoff's "origin" as the centre of projection. Hoff adds
// "(assuming viewplane lies between near and far planes)", which suggests a point on the
// viewplane inside the frustum; the COP is never inside a frustum whose near plane lies in front
// of it, which is one of the gaps hoff-exact closes.
// Three-way output (an addition that changes no accept/reject): inside when every code is zero.
#include "cullproof/core/exact.hpp"

#include "hull.hpp"

namespace cullproof {

using namespace exact_detail;

std::optional<Visibility> hoff96(const Frustum& f, const Obb& b, const glm::vec3& origin, HoffStage* stage) {
  const auto poly = frustum_polyhedron(f);
  if (!poly) return std::nullopt;
  auto end = [&](HoffStage s, Visibility v) {
    if (stage) *stage = s;
    return v;
  };
  const auto v = obb_corners(b);
  if (const auto decided = hoff_trivial_stages(f, v, stage)) return *decided;
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      if (i & bit) continue;
      const glm::vec3& a = poly->corners[static_cast<std::size_t>(i)];
      const glm::vec3& e = poly->corners[static_cast<std::size_t>(i | bit)];
      for (int k = 0; k < 3; ++k)
        for (float s : {1.0f, -1.0f})
          if (segment_hits_obb_face(a, e, b, k, s)) return end(HoffStage::edge_face, Visibility::intersecting);
    }
  if (point_in_obb(origin, b)) return end(HoffStage::containment, Visibility::intersecting);
  return end(HoffStage::final_reject, Visibility::outside);
}

}  // namespace cullproof

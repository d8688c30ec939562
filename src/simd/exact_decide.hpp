// The exact stage of the certified-exact cascade (not installed): decisions in exact integer
// arithmetic on the float values, for what the float stages could not prove. No tolerance, no
// rounding: every float is an integer times a power of two, and so is every sum and product.
#pragma once

#include "cullproof/simd/exact_certified.hpp"

#include <cstdint>

namespace cullproof::exact_detail {

/// The integers the decisions run on: 512-bit integers checked for overflow, then unbounded ones if
/// an operation overflows (the cascade's route); or one of the two alone, to compare them (bounded
/// alone throws std::overflow_error where it would overflow).
enum class Width : std::uint8_t { bounded_first, bounded, unbounded };

/// A box as the exact stage sees it: an AABB, or an OBB (the parallelepiped of its float values).
struct BoxRef {
  const Aabb* aabb = nullptr;
  const Obb* obb = nullptr;
};

/// Whether plane `k` (CONVENTIONS index) of f holds every point of the box: min over the box of
/// n.x + d >= 0, exactly.
bool box_in_plane(const ExactCertifiedFrustum& f, int k, BoxRef b, Width w = Width::bounded_first);
/// Whether the box meets the intersection of the planes listed (CONVENTIONS indices, `count` of
/// them, at most 6): the polytope {t in [-1,1]^3 : plane_j(c + sum t_i e_i) >= 0} is bounded, so
/// it is non-empty iff it has a vertex; every vertex candidate is solved by Cramer's rule in
/// integers and tested against all the constraints.
bool box_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, BoxRef b, Width w = Width::bounded_first);

/// Whether plane `k` holds the whole ball: n.c + d >= 0 and (n.c + d)^2 >= r^2 |n|^2.
bool sphere_in_plane(const ExactCertifiedFrustum& f, int k, const Sphere& s, Width w = Width::bounded_first);
/// Whether the ball meets the intersection of the planes listed: the point of that intersection
/// nearest the centre is the projection of the centre onto the affine hull of the face holding
/// it, cut out by at most three planes with independent normals; every such projection is tried.
bool sphere_meets_planes(const ExactCertifiedFrustum& f, const int* planes, int count, const Sphere& s, Width w = Width::bounded_first);

}  // namespace cullproof::exact_detail

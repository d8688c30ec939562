// Octant test for symmetric frusta, with the box precondition of figure 6.
//
// Source: Assarsson & Möller 2000, §3.3 "The Octant Test", figures 5 and 6, footnotes 5 and 6.
// Set-up (once per frame): normalised planes; the frustum centre c_VF (mean of the 8 corners,
// footnote 5) and d1, its distance to the nearest plane. Refuses (CullerPreconditionError) an
// unbounded or asymmetric frustum: "for asymmetric frustums the octant test cannot be used".
// Per box: d2 = |half extent| (centre to corner). If d2 > d1 the fig. 6 precondition fails and
// the box gets the full n/p-vertex test (§3.1). Otherwise the octant of the box centre is found
// pair by pair: of left/right, bottom/top and near/far, the outer plane of the octant is the one
// the centre is nearer to (smaller normalised plane value; the mid-planes of a symmetric
// frustum are where the two values are equal). Only those three planes are tested.
//
// classify (as published): n/p-vertex against the three outer planes. Claim: conservative, as
// the paper claims ("an arbitrary BV cannot intersect the planes of another octant without
// intersecting the planes of the selected octant"). Our doubt, to be measured by the oracle:
// the argument holds for the bounding sphere (if the sphere is inside the nearer plane of a
// pair it is inside the farther one), but a box thin along one normal and long along the other
// can be inside the outer plane and cross the inner one, which would be a false inside.
// classify_corrected: `outside` when one of the three outer planes, as given (normalising rounds:
// a box exactly touching a plane could be culled), rejects the box; `inside` only when the three
// accept all of it and the bounding sphere (radius d2) is inside both planes of every pair with
// a margin for double rounding, or the n/p-vertex tests of the three inner planes confirm it;
// otherwise intersecting. Claim: conservative, with no rounding allowance on float-exact cases,
// on the whole float range: its plane values are taken in double where float overflows
// (plane_value), and a box whose half-extent overflows gets the full test (pn_vertex_index, the
// same); the octant it picks from a centre that overflowed may be any, which costs only speed
// (the verdict is decided by the planes and the bounding sphere in double).
// Touching: as pn_vertex (touching from outside: intersecting; from inside: inside).
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/core/node_tests.hpp"

#include <cmath>
#include <limits>

namespace cullproof {

namespace {

// n/p-vertex test of one plane: 0 outside, 1 intersecting, 2 inside.
int plane_test(const Plane& pl, const Aabb& box) noexcept {
  const glm::vec3 p(pl.n.x > 0.0f ? box.max.x : box.min.x, pl.n.y > 0.0f ? box.max.y : box.min.y,
                    pl.n.z > 0.0f ? box.max.z : box.min.z);
  if (pl.eval(p) < 0.0f) return 0;
  const glm::vec3 n(pl.n.x > 0.0f ? box.min.x : box.max.x, pl.n.y > 0.0f ? box.min.y : box.max.y,
                    pl.n.z > 0.0f ? box.min.z : box.max.z);
  return pl.eval(n) < 0.0f ? 1 : 2;
}

// plane_test with the values taken by plane_value: in double where float overflows.
int plane_test_wide(const Plane& pl, const Aabb& box) noexcept {
  const glm::vec3 p(pl.n.x > 0.0f ? box.max.x : box.min.x, pl.n.y > 0.0f ? box.max.y : box.min.y,
                    pl.n.z > 0.0f ? box.max.z : box.min.z);
  if (plane_value(pl, p) < 0.0) return 0;
  const glm::vec3 n(pl.n.x > 0.0f ? box.min.x : box.max.x, pl.n.y > 0.0f ? box.min.y : box.max.y,
                    pl.n.z > 0.0f ? box.min.z : box.max.z);
  return plane_value(pl, n) < 0.0 ? 1 : 2;
}

}  // namespace

OctantCuller::OctantCuller(const Frustum& frustum) {
  if (!is_bounded(frustum))
    throw CullerPreconditionError("octant: frustum is unbounded (a degenerate plane or planes "
                                  "that do not meet); the octant test needs the frustum centre");
  if (!is_symmetric(frustum, 1e-5))
    throw CullerPreconditionError("octant: frustum is not symmetric (A&M 2000 §3.3 and footnote 6: "
                                  "for asymmetric frustums the octant test cannot be used)");
  const Frustum planes = frustum.normalized();
  const glm::dvec3 c = frustum_center(frustum);
  double d1 = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& p = planes[i];
    const double v = double(p.n.x) * c.x + double(p.n.y) * c.y + double(p.n.z) * c.z + p.d;
    d1 = std::min(d1, v);
  }
  *this = OctantCuller(frustum, d1);
}

OctantCuller::OctantCuller(const Frustum& frustum, double centre_distance) {
  given_ = frustum;
  planes_ = frustum.normalized();
  for (int i = 0; i < kPlaneCount; ++i) inv_len_[i] = 1.0 / glm::length(glm::dvec3(frustum[i].n));
  d1_ = centre_distance;
  d1_sq_ = d1_ > 0.0 ? d1_ * d1_ : -1.0;  // a frustum centre outside a plane: never octant
}

Visibility OctantCuller::classify(const Aabb& box) const noexcept {
  // d2 <= d1 compared squared, in double (no square root per box).
  const glm::vec3 h = box.half_extent();
  const double d2_sq = double(h.x) * h.x + double(h.y) * h.y + double(h.z) * h.z;
  const int count = d2_sq <= d1_sq_ ? 3 : 6;
  int outer[6];
  if (count == 3) {
    int octant_outer[3], inner[3];
    float nearer[3];
    node::octant_sides(planes_, box.center(), octant_outer, inner, nearer);
    for (int k = 0; k < 3; ++k) outer[k] = octant_outer[k];
  } else {
    for (int i = 0; i < 6; ++i) outer[i] = i;
  }
  bool intersect = false;
  for (int k = 0; k < count; ++k) {
    const int r = plane_test(planes_[outer[k]], box);
    if (r == 0) return Visibility::outside;
    if (r == 1) intersect = true;
  }
  return intersect ? Visibility::intersecting : Visibility::inside;
}

Visibility OctantCuller::classify_corrected(const Aabb& box) const noexcept {
  std::uint64_t tests = 0;
  std::int8_t rejecting = -1;
  return classify_corrected(box, tests, rejecting);
}

Visibility OctantCuller::classify_corrected(const Aabb& box, std::uint64_t& tests, std::int8_t& rejecting) const noexcept {
  const glm::vec3 h = box.half_extent();
  const double d2_sq = double(h.x) * h.x + double(h.y) * h.y + double(h.z) * h.z;
  // A half-extent that overflows float (a box reaching across most of the range) is infinite
  // here and takes the full test.
  if (!(d2_sq <= d1_sq_)) {
    tests += 6;
    return pn_vertex_index(given_, box);
  }
  int outer[3], inner[3];
  float nearer[3];
  node::octant_sides(planes_, box.center(), outer, inner, nearer);
  bool intersect = false;
  for (int k = 0; k < 3; ++k) {
    ++tests;
    const int r = plane_test_wide(given_[outer[k]], box);
    if (r == 0) {
      rejecting = static_cast<std::int8_t>(outer[k]);
      return Visibility::outside;
    }
    if (r == 1) intersect = true;
  }
  if (intersect) return Visibility::intersecting;
  // The bounding sphere, centre and radius in double (exact from the float corners: halves and
  // sums of floats), against both planes of each pair: its signed distance minus the radius must
  // exceed what the double evaluation can round (4 roundings of the sum, the length, the
  // division: 8 units of 2^-53 of the magnitudes involved, generously).
  const glm::dvec3 cd = (glm::dvec3(box.min) + glm::dvec3(box.max)) * 0.5;
  const glm::dvec3 hd = (glm::dvec3(box.max) - glm::dvec3(box.min)) * 0.5;
  const double d2 = glm::length(hd);
  constexpr double kUnit = 0x1p-53;
  bool sphere_inside = true;
  for (int i = 0; i < kPlaneCount && sphere_inside; ++i) {
    const Plane& p = given_[i];
    const double terms[4] = {double(p.n.x) * cd.x, double(p.n.y) * cd.y, double(p.n.z) * cd.z, double(p.d)};
    const double v = (terms[0] + terms[1] + terms[2] + terms[3]) * inv_len_[i];
    const double mag = (std::abs(terms[0]) + std::abs(terms[1]) + std::abs(terms[2]) + std::abs(terms[3])) * inv_len_[i];
    sphere_inside = v - d2 > 16 * kUnit * (mag + d2);
  }
  if (sphere_inside) return Visibility::inside;
  for (int k = 0; k < 3; ++k) {
    ++tests;
    if (plane_test_wide(given_[inner[k]], box) != 2) return Visibility::intersecting;
  }
  return Visibility::inside;
}

}  // namespace cullproof

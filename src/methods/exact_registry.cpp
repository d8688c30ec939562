// Registration of Hoff's test and the exact float tests (src/exact/). Every method takes AABBs
// and OBBs; AABBs go through the OBB code with identity axes (the same geometry), against the
// case's float planes.
#include "builtin.hpp"
#include "cullproof/core/exact.hpp"

namespace cullproof::detail {

namespace {

constexpr double kTol = 1e-5;

// classify for both kinds from one OBB function.
template <class Fn>
auto boxes(Fn fn) {
  return overload{[fn](const auto& state, const Aabb& a) { return fn(state, to_obb(a)); },
                  [fn](const auto& state, const Obb& b) { return fn(state, b); }};
}

struct PlanesAndApex {
  Frustum planes;
  glm::vec3 apex;
};

}  // namespace

void register_exact_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      describe("hoff96", Origin::published)
          .as("Hoff's OBB test as published: outcodes, trivial reject/accept, frustum edges x OBB faces, COP in OBB")
          .from("Hoff 1996, 'A Fast Method for Culling of OBBs Against a Perspective Viewing Frustum' (whole procedure)")
          .claims(Claim::exact, kTol)
          .on(kAabbKind | kObbKind)
          .touching("intersecting: a corner on a plane counts as inside it; edge-face tests are closed"),
      [](const CaseFrustum& f) -> std::optional<PlanesAndApex> {
        const auto cop = frustum_apex(f.planes);
        if (!cop) return std::nullopt;  // orthographic: no centre of projection
        return PlanesAndApex{f.planes, *cop};
      },
      boxes([](const PlanesAndApex& p, const Obb& b) { return hoff96(p.planes, b, p.apex); })));
  out.push_back(make_method(
      describe("hoff-exact", Origin::own)
          .as("Hoff's structure completed: adds OBB edges x frustum faces and frustum corners in the OBB")
          .from("Hoff 1996 + convex-polyhedra vertex/edge-face characterisation (src/core/exact/hoff_exact.cpp)")
          .claims(Claim::exact, kTol)
          .on(kAabbKind | kObbKind)
          .touching("intersecting: closed vertex, edge-face and containment tests"),
      planes, boxes([](const Frustum& f, const Obb& b) { return hoff_exact(f, b); })));
  out.push_back(make_method(
      describe("sat-exact", Origin::own)
          .as("Separating axes in float: box and frustum face normals, box x frustum edge cross products")
          .from("Gottschalk, Lin & Manocha 1996 §4 (separating axis theorem); Eberly 2001")
          .claims(Claim::exact, kTol)
          .on(kAabbKind | kObbKind)
          .touching("intersecting: separated only when the projections are strictly apart"),
      planes, boxes([](const Frustum& f, const Obb& b) { return sat_classify(f, b); })));
  out.push_back(make_method(
      describe("pn-vertex-reverse", Origin::own)
          .as("n/p-vertex test, then the frustum's corners against the box's face planes")
          .from("p-vertex post, readers' comments 5-6; Assarsson & Möller 2000 §3.1 for the forward stage")
          .claims(Claim::conservative, kTol)
          .on(kAabbKind | kObbKind)
          .touching("intersecting: a p-vertex on the plane is not outside; a corner on a box face is not outside it"),
      planes, boxes([](const Frustum& f, const Obb& b) { return pn_vertex_reverse(f, b); })));
}

}  // namespace cullproof::detail

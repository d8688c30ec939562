// Registration of Hoff's test and the exact float tests (src/exact/).
#include "cullproof/exact.hpp"
#include "cullproof/methods.hpp"

namespace cullproof::detail {

namespace {

// A method on AABBs and OBBs; AABBs go through the OBB code with identity axes (the same
// geometry). `fn` sees the case's float planes.
Method box_method(std::string name, std::string description, std::string source, Claim claim, bool published,
                  std::string touching,
                  std::function<std::optional<Visibility>(const Frustum&, const Obb&)> fn) {
  Method m;
  m.name = std::move(name);
  m.description = std::move(description);
  m.source = std::move(source);
  m.claim = claim;
  m.published = published;
  m.tolerance = 1e-5;
  m.volumes = kAabbKind | kObbKind;
  m.touching = std::move(touching);
  m.classify = [fn = std::move(fn)](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
    if (const Aabb* a = std::get_if<Aabb>(&v)) return fn(f.planes, to_obb(*a));
    return fn(f.planes, std::get<Obb>(v));
  };
  return m;
}

}  // namespace

void register_exact_methods(std::vector<Method>& out) {
  out.push_back(box_method(
      "hoff96", "Hoff's OBB test as published: outcodes, trivial reject/accept, frustum edges x OBB faces, COP in OBB",
      "Hoff 1996, 'A Fast Method for Culling of OBBs Against a Perspective Viewing Frustum' (whole procedure)",
      Claim::exact, /*published=*/true, "intersecting: a corner on a plane counts as inside it; edge-face tests are closed",
      [](const Frustum& f, const Obb& b) -> std::optional<Visibility> {
        const auto cop = frustum_apex(f);
        if (!cop) return std::nullopt;  // orthographic: no centre of projection
        return hoff96(f, b, *cop);
      }));
  out.push_back(box_method(
      "hoff-exact", "Hoff's structure completed: adds OBB edges x frustum faces and frustum corners in the OBB",
      "Hoff 1996 + convex-polyhedra vertex/edge-face characterisation (src/exact/hoff_exact.cpp)", Claim::exact,
      /*published=*/false, "intersecting: closed vertex, edge-face and containment tests",
      [](const Frustum& f, const Obb& b) { return hoff_exact(f, b); }));
  out.push_back(box_method(
      "sat-exact", "Separating axes in float: box and frustum face normals, box x frustum edge cross products",
      "Gottschalk, Lin & Manocha 1996 §4 (separating axis theorem); Eberly 2001", Claim::exact, /*published=*/false,
      "intersecting: separated only when the projections are strictly apart",
      [](const Frustum& f, const Obb& b) { return sat_classify(f, b); }));
  out.push_back(box_method(
      "pn-vertex-reverse", "n/p-vertex test, then the frustum's corners against the box's face planes",
      "p-vertex post, readers' comments 5-6; Assarsson & Möller 2000 §3.1 for the forward stage", Claim::conservative,
      /*published=*/false, "intersecting: a p-vertex on the plane is not outside; a corner on a box face is not outside it",
      [](const Frustum& f, const Obb& b) -> std::optional<Visibility> { return pn_vertex_reverse(f, b); }));
}

}  // namespace cullproof::detail

// Registration of Hoff's test and the exact float tests (src/exact/).
#include "cullproof/exact.hpp"
#include "cullproof/methods.hpp"

namespace cullproof::detail {

namespace {

// AABBs go through the OBB code with identity axes: the same geometry.
const Obb* as_obb(const Volume& v, Obb& storage) {
  if (const Obb* o = std::get_if<Obb>(&v)) return o;
  if (const Aabb* a = std::get_if<Aabb>(&v)) {
    storage = to_obb(*a);
    return &storage;
  }
  return nullptr;
}

}  // namespace

void register_exact_methods(std::vector<Method>& out) {
  {
    Method m;
    m.name = "hoff96";
    m.description = "Hoff's OBB test as published: outcodes, trivial reject/accept, frustum edges x OBB faces, COP in OBB";
    m.source = "Hoff 1996, 'A Fast Method for Culling of OBBs Against a Perspective Viewing Frustum' (whole procedure)";
    m.claim = Claim::exact;
    m.tolerance = 1e-5;
    m.volumes = kAabbKind | kObbKind;
    m.touching = "intersecting: a corner on a plane counts as inside it; edge-face tests are closed";
    m.classify = [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
      Obb tmp;
      const Obb* b = as_obb(v, tmp);
      const auto cop = frustum_apex(f.planes);
      if (!cop) return std::nullopt;  // orthographic: no centre of projection
      return hoff96(f.planes, *b, *cop);
    };
    out.push_back(std::move(m));
  }
  {
    Method m;
    m.name = "hoff-exact";
    m.published = false;
    m.description = "Hoff's structure completed: adds OBB edges x frustum faces and frustum corners in the OBB";
    m.source = "Hoff 1996 + convex-polyhedra vertex/edge-face characterisation (src/exact/hoff_exact.cpp)";
    m.claim = Claim::exact;
    m.tolerance = 1e-5;
    m.volumes = kAabbKind | kObbKind;
    m.touching = "intersecting: closed vertex, edge-face and containment tests";
    m.classify = [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
      Obb tmp;
      return hoff_exact(f.planes, *as_obb(v, tmp));
    };
    out.push_back(std::move(m));
  }
  {
    Method m;
    m.name = "sat-exact";
    m.published = false;
    m.description = "Separating axes in float: box and frustum face normals, box x frustum edge cross products";
    m.source = "Gottschalk, Lin & Manocha 1996 §4 (separating axis theorem); Eberly 2001";
    m.claim = Claim::exact;
    m.tolerance = 1e-5;
    m.volumes = kAabbKind | kObbKind;
    m.touching = "intersecting: separated only when the projections are strictly apart";
    m.classify = [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
      Obb tmp;
      return sat_classify(f.planes, *as_obb(v, tmp));
    };
    out.push_back(std::move(m));
  }
  {
    Method m;
    m.name = "pn-vertex-reverse";
    m.published = false;
    m.description = "n/p-vertex test, then the frustum's corners against the box's face planes";
    m.source = "p-vertex post, readers' comments 5-6; Assarsson & Möller 2000 §3.1 for the forward stage";
    m.claim = Claim::conservative;
    m.tolerance = 1e-5;
    m.volumes = kAabbKind | kObbKind;
    m.touching = "intersecting: a p-vertex on the plane is not outside; a corner on a box face is not outside it";
    m.classify = [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
      Obb tmp;
      return pn_vertex_reverse(f.planes, *as_obb(v, tmp));
    };
    out.push_back(std::move(m));
  }
}

}  // namespace cullproof::detail

// Registration of the certified conservative cullers (src/certified/).
#include "cullproof/certified.hpp"
#include "cullproof/methods.hpp"

namespace cullproof::detail {

namespace {

Method certified(std::string name, std::string description, std::string source, unsigned volumes,
                 std::function<std::optional<Visibility>(const CaseFrustum&, const Volume&)> fn) {
  Method m;
  m.name = std::move(name);
  m.description = std::move(description);
  m.source = std::move(source);
  m.claim = Claim::certified_conservative;
  m.tolerance = 0.0;
  m.volumes = volumes;
  m.touching = "intersecting: a plane within the rounding bound is never decided, so touching stays intersecting";
  m.published = false;
  m.classify = std::move(fn);
  return m;
}

}  // namespace

void register_certified_methods(std::vector<Method>& out) {
  const std::string derivation = "; error bound derived in src/certified/certified.cpp (Higham 2002 §2.2, §3.1)";
  out.push_back(certified("point-certified", "plane test with a derived rounding margin, end to end from the matrix",
                          "Lighthouse3D pointInFrustum" + derivation, kPointKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            return certified_point(certify(f), std::get<Point>(v));
                          }));
  out.push_back(certified("sphere-certified", "sphere plane test (r |n|) with a derived rounding margin",
                          "Lighthouse3D sphereInFrustum" + derivation, kSphereKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            return certified_sphere(certify(f), std::get<Sphere>(v));
                          }));
  out.push_back(certified("pn-vertex-certified", "n/p-vertex AABB test with a derived rounding margin per plane",
                          "Assarsson & Möller 2000 §3.1" + derivation, kAabbKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            return certified_pn_vertex(certify(f), std::get<Aabb>(v));
                          }));
  out.push_back(certified("obb-pn-vertex-certified", "n/p-vertex OBB test (normal on the box axes) with a derived margin",
                          "Assarsson & Möller 2000 §3.1; Lighthouse3D Testing Boxes II" + derivation, kObbKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            return certified_obb_pn_vertex(certify(f), std::get<Obb>(v));
                          }));
  out.push_back(certified("sat-certified", "separating axes, each separation proved by a Farkas combination of planes",
                          "Gottschalk, Lin & Manocha 1996 §4 + Farkas certificate; src/certified/certified_sat.cpp",
                          kAabbKind | kObbKind, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            if (const Aabb* a = std::get_if<Aabb>(&v)) return certified_sat(certify(f), to_obb(*a));
                            return certified_sat(certify(f), std::get<Obb>(v));
                          }));
}

}  // namespace cullproof::detail

// Registration of the certified conservative cullers (src/certified/).
#include "cullproof/certified.hpp"
#include "cullproof/certified_batch.hpp"
#include "cullproof/methods.hpp"

#include <vector>

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

// The batch kernels run on 64 copies of the volume (one full SIMD word), so that the vector code
// is what the harness checks, as the culler family's batch methods do.
template <class Soa, class Fill, class Run>
Visibility via_batch(Fill&& fill, Run&& run) {
  std::vector<float> arrays[6];
  for (auto& a : arrays) a.resize(64);
  Soa soa = fill(arrays);
  std::uint64_t visible = 0, inside = 0;
  run(soa, &visible, &inside);
  return (visible & 1u) == 0 ? Visibility::outside : (inside & 1u) ? Visibility::inside : Visibility::intersecting;
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
  out.push_back(certified("pn-vertex-batch-certified", "SIMD SoA batch of the certified n/p-vertex test (Highway dispatch)",
                          "Assarsson & Möller 2000 §3.1, per-plane hoisted min/max" + derivation, kAabbKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            const Aabb& b = std::get<Aabb>(v);
                            const CertifiedFrustum cf = certify(f);
                            return via_batch<AabbSoa>(
                                [&](std::vector<float>(&a)[6]) {
                                  for (int i = 0; i < 64; ++i) {
                                    a[0][i] = b.min.x, a[1][i] = b.min.y, a[2][i] = b.min.z;
                                    a[3][i] = b.max.x, a[4][i] = b.max.y, a[5][i] = b.max.z;
                                  }
                                  return AabbSoa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), 64};
                                },
                                [&](const AabbSoa& s, std::uint64_t* vis, std::uint64_t* ins) {
                                  certified_cull_aabbs_bitset(cf, s, vis, ins);
                                });
                          }));
  out.push_back(certified("sphere-batch-certified", "SIMD SoA batch of the certified sphere test (Highway dispatch)",
                          "Lighthouse3D sphereInFrustum" + derivation, kSphereKind,
                          [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            const Sphere& sp = std::get<Sphere>(v);
                            const CertifiedFrustum cf = certify(f);
                            return via_batch<SphereSoa>(
                                [&](std::vector<float>(&a)[6]) {
                                  for (int i = 0; i < 64; ++i)
                                    a[0][i] = sp.center.x, a[1][i] = sp.center.y, a[2][i] = sp.center.z, a[3][i] = sp.radius;
                                  return SphereSoa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), 64};
                                },
                                [&](const SphereSoa& s, std::uint64_t* vis, std::uint64_t* ins) {
                                  certified_cull_spheres_bitset(cf, s, vis, ins);
                                });
                          }));
  out.push_back(certified("sat-certified", "separating axes, each separation proved by a Farkas combination of planes",
                          "Gottschalk, Lin & Manocha 1996 §4 + Farkas certificate; src/certified/certified_sat.cpp",
                          kAabbKind | kObbKind, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                            if (const Aabb* a = std::get_if<Aabb>(&v)) return certified_sat(certify(f), to_obb(*a));
                            return certified_sat(certify(f), std::get<Obb>(v));
                          }));
}

}  // namespace cullproof::detail

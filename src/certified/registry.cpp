// Registration of the certified conservative cullers (src/certified/). The certified frustum
// (rounded planes, their error bounds and the per-frame margins) is derived once per frame.
#include "batch_adapter.hpp"
#include "builtin.hpp"
#include "cullproof/certified.hpp"
#include "cullproof/certified_batch.hpp"

#include <vector>

namespace cullproof::detail {

namespace {

const char* const kTouching =
    "intersecting: a plane within the rounding bound is never decided, so touching stays intersecting";
const std::string kDerivation = "; error bound derived in src/certified/certified.cpp (Higham 2002 §2.2, §3.1)";

describe certified(std::string name, std::string description, std::string source, unsigned volumes,
                   bool margin_derived_in_certified_cpp = true) {
  describe d(std::move(name), Origin::own);
  if (margin_derived_in_certified_cpp) source += kDerivation;
  d.as(std::move(description)).from(std::move(source)).claims(Claim::certified_conservative, 0.0);
  d.on(volumes).touching(kTouching);
  return d;
}

const auto certified_frustum = [](const CaseFrustum& f) { return certify(f); };

const auto aabb_kernel = [](const CertifiedFrustum& f) {
  return [&f](const AabbSoa& s, std::uint64_t* vis, std::uint64_t* ins) { certified_cull_aabbs_bitset(f, s, vis, ins); };
};
const auto sphere_kernel = [](const CertifiedFrustum& f) {
  return [&f](const SphereSoa& s, std::uint64_t* vis, std::uint64_t* ins) {
    certified_cull_spheres_bitset(f, s, vis, ins);
  };
};

}  // namespace

void register_certified_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      certified("point-certified", "plane test with a derived rounding margin, end to end from the matrix",
                "Lighthouse3D pointInFrustum", kPointKind),
      certified_frustum, [](const CertifiedFrustum& f, const Point& p) { return certified_point(f, p); }));
  out.push_back(make_method(
      certified("sphere-certified", "sphere plane test (r |n|) with a derived rounding margin",
                "Lighthouse3D sphereInFrustum", kSphereKind),
      certified_frustum, [](const CertifiedFrustum& f, const Sphere& s) { return certified_sphere(f, s); }));
  out.push_back(make_method(
      certified("pn-vertex-certified", "n/p-vertex AABB test with a derived rounding margin per plane",
                "Assarsson & Möller 2000 §3.1", kAabbKind),
      certified_frustum, [](const CertifiedFrustum& f, const Aabb& b) { return certified_pn_vertex(f, b); }));
  out.push_back(make_method(
      certified("obb-pn-vertex-certified", "n/p-vertex OBB test (normal on the box axes) with a derived margin",
                "Assarsson & Möller 2000 §3.1; Lighthouse3D Testing Boxes II", kObbKind),
      certified_frustum, [](const CertifiedFrustum& f, const Obb& b) { return certified_obb_pn_vertex(f, b); }));
  out.push_back(make_method(
      certified("pn-vertex-batch-certified",
                "SIMD SoA batch of the certified n/p-vertex test (Highway dispatch); one volume runs as a full word of 64 copies",
                "Assarsson & Möller 2000 §3.1, per-plane hoisted min/max", kAabbKind),
      certified_frustum, [](const CertifiedFrustum& f, const Aabb& b) { return aabb_as_word(b, aabb_kernel(f)); },
      [](const CertifiedFrustum& f, const Aabb* b, std::size_t n, Visibility* v) { aabb_batch(b, n, v, aabb_kernel(f)); }));
  out.push_back(make_method(
      certified("sphere-batch-certified",
                "SIMD SoA batch of the certified sphere test (Highway dispatch); one volume runs as a full word of 64 copies",
                "Lighthouse3D sphereInFrustum", kSphereKind),
      certified_frustum, [](const CertifiedFrustum& f, const Sphere& s) { return sphere_as_word(s, sphere_kernel(f)); },
      [](const CertifiedFrustum& f, const Sphere* s, std::size_t n, Visibility* v) {
        sphere_batch(s, n, v, sphere_kernel(f));
      }));
  out.push_back(make_method(
      certified("sat-certified", "separating axes, each separation proved by a Farkas combination of planes",
                "Gottschalk, Lin & Manocha 1996 §4 + Farkas certificate; src/certified/certified_sat.cpp",
                kAabbKind | kObbKind, false),
      certified_frustum,
      overload{[](const CertifiedFrustum& f, const Aabb& a) { return certified_sat(f, to_obb(a)); },
               [](const CertifiedFrustum& f, const Obb& b) { return certified_sat(f, b); }}));
}

}  // namespace cullproof::detail

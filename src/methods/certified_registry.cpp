// Registration of the certified conservative cullers (src/certified/). The certified frustum
// (rounded planes, their error bounds and the per-frame margins) is derived once per frame.
#include "cullproof/simd/batch_adapter.hpp"
#include "builtin.hpp"
#include "cullproof/core/certified.hpp"
#include "cullproof/simd/certified_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"
#include "cullproof/simd/exact_certified_batch.hpp"

#include <algorithm>
#include <vector>

namespace cullproof::detail {

namespace {

const char* const kTouching =
    "intersecting: a plane within the rounding bound is never decided, so touching stays intersecting";
const std::string kDerivation = "; error bound derived in src/core/certified/certified.cpp (Higham 2002 §2.2, §3.1)";

describe certified(std::string name, std::string description, std::string source, unsigned volumes,
                   bool margin_derived_in_certified_cpp = true) {
  describe d(std::move(name), Origin::own);
  if (margin_derived_in_certified_cpp) source += kDerivation;
  d.as(std::move(description)).from(std::move(source)).claims(Claim::certified_conservative, 0.0);
  d.on(volumes).touching(kTouching);
  return d;
}

const auto certified_frustum = [](const CaseFrustum& f) { return certify(f); };

const auto certified_aabb_kernel = [](const CertifiedFrustum& f) {
  return [&f](const AabbSoa& s, std::uint64_t* vis, std::uint64_t* ins) { certified_cull_aabbs_bitset(f, s, vis, ins); };
};
const auto certified_sphere_kernel = [](const CertifiedFrustum& f) {
  return [&f](const SphereSoa& s, std::uint64_t* vis, std::uint64_t* ins) {
    certified_cull_spheres_bitset(f, s, vis, ins);
  };
};

const auto exact_frustum = [](const CaseFrustum& f) { return prepare_exact_certified(f); };

// One volume through the array form as a full word of 64 copies (detail::as_word).
Visibility exact_aabb_as_word(const ExactCertifiedFrustum& f, const Aabb& b) {
  return detail::as_word(b, [&](const Aabb* c, std::size_t n, Visibility* v) { exact_certified_aabbs(f, c, n, v); });
}
Visibility exact_sphere_as_word(const ExactCertifiedFrustum& f, const Sphere& s) {
  return detail::as_word(s, [&](const Sphere* c, std::size_t n, Visibility* v) { exact_certified_spheres(f, c, n, v); });
}

describe exact_certified(std::string name, std::string description, unsigned volumes) {
  describe d(std::move(name), Origin::own);
  d.as(std::move(description))
      .from("Assarsson & Möller 2000 §3.1 and Gottschalk, Lin & Manocha 1996 §4 as Farkas combinations, each "
            "stage's bound derived in src/simd/exact_certified.cpp; exact stage in integers "
            "(src/simd/exact_decide.cpp)")
      .claims(Claim::certified_exact, 0.0);
  d.on(volumes).touching("exact: touching from outside is intersecting, from inside inside (decided exactly)");
  return d;
}

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
      certified_frustum, [](const CertifiedFrustum& f, const Aabb& b) { return aabb_as_word(b, certified_aabb_kernel(f)); },
      [](const CertifiedFrustum& f, const Aabb* b, std::size_t n, Visibility* v) { aabb_batch(b, n, v, certified_aabb_kernel(f)); }));
  out.push_back(make_method(
      certified("sphere-batch-certified",
                "SIMD SoA batch of the certified sphere test (Highway dispatch); one volume runs as a full word of 64 copies",
                "Lighthouse3D sphereInFrustum", kSphereKind),
      certified_frustum, [](const CertifiedFrustum& f, const Sphere& s) { return sphere_as_word(s, certified_sphere_kernel(f)); },
      [](const CertifiedFrustum& f, const Sphere* s, std::size_t n, Visibility* v) {
        sphere_batch(s, n, v, certified_sphere_kernel(f));
      }));
  out.push_back(make_method(
      certified("sat-certified", "separating axes, each separation proved by a Farkas combination of planes",
                "Gottschalk, Lin & Manocha 1996 §4 + Farkas certificate; src/core/certified/certified_sat.cpp",
                kAabbKind | kObbKind, false),
      certified_frustum,
      overload{[](const CertifiedFrustum& f, const Aabb& a) { return certified_sat(f, enclosing_obb(a)); },
               [](const CertifiedFrustum& f, const Obb& b) { return certified_sat(f, b); }}));
  out.push_back(make_method(
      exact_certified("aabb-exact-certified",
                      "the exact verdict: certified n/p-vertex test, certified separating combinations and witness "
                      "points, then exact integers for what lies within the bounds",
                      kAabbKind),
      exact_frustum, [](const ExactCertifiedFrustum& f, const Aabb& b) { return exact_certified_aabb(f, b); }));
  out.push_back(make_method(
      exact_certified("obb-exact-certified",
                      "the exact verdict: certified projected-radius test, certified separating combinations and "
                      "witness points, then exact integers",
                      kObbKind),
      exact_frustum, [](const ExactCertifiedFrustum& f, const Obb& b) { return exact_certified_obb(f, b); }));
  out.push_back(make_method(
      exact_certified("sphere-exact-certified",
                      "the exact verdict: certified r |n| test, certified distances to the frustum's faces, edges "
                      "and corners, then exact integers",
                      kSphereKind),
      exact_frustum, [](const ExactCertifiedFrustum& f, const Sphere& s) { return exact_certified_sphere(f, s); }));
  out.push_back(make_method(
      exact_certified("aabb-batch-exact-certified",
                      "array form of aabb-exact-certified: the SIMD certified batch, its witness and float passes, the cascade for the rest; one volume runs as a full word of 64 copies",
                      kAabbKind),
      exact_frustum, [](const ExactCertifiedFrustum& f, const Aabb& b) { return exact_aabb_as_word(f, b); },
      [](const ExactCertifiedFrustum& f, const Aabb* b, std::size_t n, Visibility* v) { exact_certified_aabbs(f, b, n, v); }));
  out.push_back(make_method(
      exact_certified("sphere-batch-exact-certified",
                      "array form of sphere-exact-certified: the SIMD certified batch, its witness pass, the cascade for the rest; one volume runs as a full word of 64 copies",
                      kSphereKind),
      exact_frustum, [](const ExactCertifiedFrustum& f, const Sphere& s) { return exact_sphere_as_word(f, s); },
      [](const ExactCertifiedFrustum& f, const Sphere* s, std::size_t n, Visibility* v) {
        exact_certified_spheres(f, s, n, v);
      }));
}

}  // namespace cullproof::detail

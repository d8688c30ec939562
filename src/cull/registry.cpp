// Registration of the fast culler family (src/cull/). Each algorithm lives in its own file;
// this file only wires them to the registry (cullproof/methods.hpp) with their name, source,
// claim, volume kinds and treatment of touching volumes.
//
// Tolerances (Method::tolerance, relative to the case scale) are the rounding allowances of
// the `conservative` / `exact` claims: 1e-6 for tests that evaluate the given planes directly
// (a few roundings of dot(n, x) + d), 1e-5 for tests that derive data first (normalised planes,
// camera parameters, OBB corners, clip-space corners, frustum corners, accumulated deltas).
#include "cullproof/cull.hpp"
#include "cullproof/cull_batch.hpp"
#include "cullproof/cull_coherence.hpp"
#include "cullproof/methods.hpp"

#include <cstdint>

namespace cullproof::detail {

namespace {

constexpr double kDirectTol = 1e-6;
constexpr double kDerivedTol = 1e-5;

const char* const kTouchPn =
    "plane value at the p-vertex == 0 is not rejected (touching from outside: intersecting); "
    "value at the n-vertex == 0 counts as inside (touching from inside: inside)";

using Classify = std::function<std::optional<Visibility>(const CaseFrustum&, const Volume&)>;

Method make(std::string name, std::string description, std::string source, Claim claim,
            unsigned volumes, std::string touching, double tolerance, bool stateful, Classify fn) {
  Method m;
  m.name = std::move(name);
  m.description = std::move(description);
  m.source = std::move(source);
  m.claim = claim;
  m.volumes = volumes;
  m.touching = std::move(touching);
  m.tolerance = tolerance;
  m.stateful = stateful;
  m.classify = std::move(fn);
  return m;
}

// cullproof's own variants (corrections, three-way adaptations, SIMD batch forms): a broken
// claim is a bug, not a finding about a text.
Method own(Method m) {
  m.published = false;
  return m;
}

std::optional<glm::mat4> case_matrix(const CaseFrustum& f, DepthConvention& depth) {
  if (f.matrix) {
    depth = f.depth;
    return f.matrix;
  }
  depth = DepthConvention{};
  return clip_matrix_from_frustum(f.planes);
}

template <class F>
Classify on_aabb(F fn) {
  return [fn](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
    return fn(f.planes, std::get<Aabb>(v));
  };
}

// One box through the SIMD kernel: 64 copies (a full bitset word), so that the vector code
// runs (a batch shorter than 64 would go through the scalar tail).
Visibility batch_aabb(const Frustum& f, const Aabb& b) {
  float a[6][64];
  for (int i = 0; i < 64; ++i)
    for (int k = 0; k < 3; ++k) {
      a[k][i] = b.min[k];
      a[3 + k][i] = b.max[k];
    }
  const AabbSoa soa{a[0], a[1], a[2], a[3], a[4], a[5], 64};
  std::uint64_t vis = 0, ins = 0;
  classify_aabbs_bitset(f, soa, &vis, &ins);
  return (vis & 1u) == 0 ? Visibility::outside : ((ins & 1u) ? Visibility::inside : Visibility::intersecting);
}

Visibility batch_sphere(const Frustum& normalized, const Sphere& s) {
  float a[4][64];
  for (int i = 0; i < 64; ++i) {
    a[0][i] = s.center.x;
    a[1][i] = s.center.y;
    a[2][i] = s.center.z;
    a[3][i] = s.radius;
  }
  std::uint64_t vis = 0, ins = 0;
  classify_spheres_bitset(normalized, SphereSoa{a[0], a[1], a[2], a[3], 64}, &vis, &ins);
  return (vis & 1u) == 0 ? Visibility::outside : ((ins & 1u) ? Visibility::inside : Visibility::intersecting);
}

}  // namespace

void register_cull_methods(std::vector<Method>& out) {
  const std::string am = "Assarsson & Möller 2000, ";
  const std::string lh = "Lighthouse3D View Frustum Culling Tutorial, ";

  // ---- points
  out.push_back(make("point-plane", "point against the six planes, outside on the first plane < 0",
                     lh + "Geometric Approach - Testing Points and Spheres (pointInFrustum)",
                     Claim::exact, kPointKind, "a point on a plane is inside (distance < 0 rejects)",
                     kDirectTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       return point_plane_test(f.planes, std::get<Point>(v));
                     }));
  out.push_back(make("radar-point", "radar test in camera coordinates (camera derived from a symmetric perspective frustum)",
                     lh + "Radar Approach - Testing Points, Implementation (pc.z = v.Z reading)",
                     Claim::exact, kPointKind, "a point on the boundary is inside (strict > / < reject)",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const auto cam = radar_camera_from_frustum(f.planes);
                       if (!cam) return std::nullopt;
                       return radar_point(*cam, std::get<Point>(v));
                     }));
  // ---- spheres
  out.push_back(make("sphere-plane", "sphere against the normalised planes: d < -r outside, d < r intersecting",
                     lh + "Geometric Approach - Testing Points and Spheres (sphereInFrustum)",
                     Claim::conservative, kSphereKind,
                     "touching from outside (d == -r) intersecting; touching from inside (d == r) inside",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       return sphere_plane_test(f.planes.normalized(), std::get<Sphere>(v));
                     }));
  out.push_back(own(make("radar-sphere", "radar sphere test with sphere factors 1/cos(half fov) (corrected)",
                     lh + "Radar Approach - Testing Spheres, Implementation II, with tan(fov/2)",
                     Claim::conservative, kSphereKind, "touching a bound from outside is intersecting (strict compares)",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const auto cam = radar_camera_from_frustum(f.planes);
                       if (!cam) return std::nullopt;
                       return radar_sphere(*cam, std::get<Sphere>(v));
                     })));
  out.push_back(make("radar-sphere-as-published", "radar sphere test as published: tang = tan(fov), 1/cos(fov) (full angle)",
                     lh + "Radar Approach - Implementation II (setCamInternals as printed)",
                     Claim::none, kSphereKind, "touching a bound from outside is intersecting (strict compares)",
                     0.0, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const auto cam = radar_camera_from_frustum(f.planes, true);
                       if (!cam) return std::nullopt;
                       return radar_sphere(*cam, std::get<Sphere>(v));
                     }));
  out.push_back(own(make("sphere-batch-simd", "SoA SIMD batch sphere test (Highway, runtime dispatch), one full word of 64 copies",
                     lh + "sphereInFrustum; batch form of sphere-plane",
                     Claim::conservative, kSphereKind, "as sphere-plane (bit-for-bit the same verdicts)",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       return batch_sphere(f.planes.normalized(), std::get<Sphere>(v));
                     })));
  // ---- AABBs
  out.push_back(make("eight-corner", "8 corners counted per plane; outside when all 8 are out of one plane",
                     lh + "Geometric Approach - Testing Boxes (boxInFrustum)", Claim::conservative, kAabbKind,
                     "a corner with distance 0 counts as in: touching from outside is intersecting, from inside inside",
                     kDirectTol, false, on_aabb(aabb_eight_corner)));
  out.push_back(make("pn-vertex", "n/p-vertex test with per-box sign selection (fig. 4)",
                     am + "§3.1, fig. 4", Claim::conservative, kAabbKind, kTouchPn, kDirectTol, false,
                     on_aabb(pn_vertex)));
  out.push_back(own(make("pn-vertex-index", "n/p-vertex test with the branch-free min/max index trick, three-way",
                     "p-vertex blog post (View frustum culling, AABB vs Frustum), Implementation; three-way as A&M §3.1",
                     Claim::conservative, kAabbKind, kTouchPn, kDirectTol, false, on_aabb(pn_vertex_index))));
  out.push_back(make("p-vertex-post", "the p-vertex post as published: p-vertex only, dp < -d rejects, never inside",
                     "p-vertex blog post (View frustum culling, AABB vs Frustum), intersectFrustumAABB",
                     Claim::conservative, kAabbKind,
                     "dp == -d is not rejected: touching from outside is intersecting; never answers inside",
                     kDirectTol, false, on_aabb(p_vertex_post)));
  out.push_back(make("pn-vertex-lut", "n/p-vertex test with the sign bitfields precomputed once per frame",
                     am + "§3.1 (LUT, precomputed per frame) and §4", Claim::conservative, kAabbKind, kTouchPn,
                     kDirectTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       return pn_vertex_lut(make_pn_lut(f.planes), std::get<Aabb>(v));
                     }));
  out.push_back(own(make("pn-vertex-batch-simd", "SoA SIMD batch n/p-vertex test (Highway, runtime dispatch), one full word of 64 copies",
                     am + "§3.1, batch form with the min/max choice hoisted per plane", Claim::conservative,
                     kAabbKind, std::string(kTouchPn) + " (bit-for-bit pn-vertex)", kDirectTol, false,
                     on_aabb(batch_aabb))));
  out.push_back(make("perspective-transform-as-published",
                     "DirectModel baseline: corners to clip space, divide by w, NDC AABB vs cube (w <= 0 not handled)",
                     am + "§2 and fig. 1 (DirectModel)", Claim::none, kAabbKind,
                     "strict rejection in NDC: touching from outside intersecting (when all w > 0)",
                     0.0, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       DepthConvention depth;
                       const auto m = case_matrix(f, depth);
                       if (!m) return std::nullopt;
                       return perspective_transform_as_published(*m, depth, std::get<Aabb>(v));
                     }));
  out.push_back(own(make("perspective-transform",
                     "DirectModel baseline corrected: NDC AABB when all w > 0, homogeneous outcodes otherwise",
                     // Claim none: conservative in exact arithmetic, but the float clip transform and the
                     // division by w carry errors no tolerance of the plane model bounds; the oracle
                     // found false rejects far beyond it on extreme-fov and corner cases (corpus/
                     // perspective-transform/). It stays the Table 1 baseline, measured, not trusted.
                     am + "§2 and fig. 1 (DirectModel), corrected for corners behind the eye", Claim::none,
                     kAabbKind, "strict rejection (hi < -1, w + x < 0): touching from outside intersecting",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       DepthConvention depth;
                       const auto m = case_matrix(f, depth);
                       if (!m) return std::nullopt;
                       return perspective_transform(*m, depth, std::get<Aabb>(v));
                     })));
  // ---- OBBs
  out.push_back(make("obb-pn-vertex", "n/p-vertex test with the plane normal projected on the box axes",
                     am + "§3.1; " + lh + "Geometric Approach - Testing Boxes II", Claim::conservative,
                     kObbKind | kAabbKind, kTouchPn, kDerivedTol, false,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       if (const Aabb* b = std::get_if<Aabb>(&v)) return obb_pn_vertex(f.planes, to_obb(*b));
                       return obb_pn_vertex(f.planes, std::get<Obb>(v));
                     }));
  // ---- pre-test stages in front of pn-vertex
  const std::string notes = lh + "Some Notes and Possible Optimizations, ";
  out.push_back(make("box-sphere-then-pn-vertex", "box's bounding sphere first; when it straddles, the n/p-vertex test",
                     notes + "Spheres as Bounding Volumes for Boxes (case C: test the box)", Claim::conservative,
                     kAabbKind, std::string("sphere stage: touching sphere falls through; then ") + kTouchPn,
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const Aabb& b = std::get<Aabb>(v);
                       if (auto r = box_sphere_stage(f.planes.normalized(), b)) return *r;
                       return pn_vertex(f.planes, b);
                     }));
  out.push_back(make("box-sphere-only", "box's bounding sphere only; a straddling sphere means intersecting",
                     notes + "Spheres as Bounding Volumes for Boxes (case C: consider that the box intersects)",
                     Claim::conservative, kAabbKind, "a touching sphere (hence box) is intersecting",
                     kDerivedTol, false, [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       if (auto r = box_sphere_stage(f.planes.normalized(), std::get<Aabb>(v))) return *r;
                       return Visibility::intersecting;
                     }));
  out.push_back(make("frustum-sphere-then-pn-vertex", "frustum's bounding sphere vs box's sphere first, then n/p-vertex",
                     notes + "Spheres everywhere", Claim::conservative, kAabbKind,
                     std::string("touching spheres fall through; then ") + kTouchPn, kDerivedTol, false,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const Aabb& b = std::get<Aabb>(v);
                       if (auto r = frustum_sphere_stage(frustum_bounds(f.planes), b)) return *r;
                       return pn_vertex(f.planes, b);
                     }));
  out.push_back(make("frustum-aabb-then-pn-vertex", "frustum's AABB vs the box first, then n/p-vertex",
                     notes + "Axis-Aligned Boxes everywhere", Claim::conservative, kAabbKind,
                     std::string("strict compares, a touching box falls through; then ") + kTouchPn, kDerivedTol, false,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       const Aabb& b = std::get<Aabb>(v);
                       if (auto r = frustum_aabb_stage(frustum_bounds(f.planes), b)) return *r;
                       return pn_vertex(f.planes, b);
                     }));
  // ---- frame coherence (fresh state per case)
  out.push_back(make("plane-coherency", "n/p-vertex test starting at the plane that rejected the box last frame",
                     am + "§3.2", Claim::conservative, kAabbKind, kTouchPn, kDirectTol, true,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       PlaneCoherencyCache cache;
                       return plane_coherency_test(f.planes, std::get<Aabb>(v), cache);
                     }));
  out.push_back(make("octant", "octant test as published: three outer planes when d2 <= d1 (symmetric frusta only)",
                     am + "§3.3, fig. 5 and 6", Claim::conservative, kAabbKind, kTouchPn, kDerivedTol, true,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       if (!is_bounded(f.planes) || !is_symmetric(f.planes, 1e-5)) return std::nullopt;
                       return OctantCuller(f.planes).classify(std::get<Aabb>(v));
                     }));
  out.push_back(own(make("octant-corrected", "octant test; inside only via the bounding sphere or the inner planes",
                     am + "§3.3, corrected inside rule", Claim::conservative, kAabbKind, kTouchPn, kDerivedTol, true,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       if (!is_bounded(f.planes) || !is_symmetric(f.planes, 1e-5)) return std::nullopt;
                       return OctantCuller(f.planes).classify_corrected(std::get<Aabb>(v));
                     })));
  out.push_back(make("tr-coherency", "translation/rotation coherency; first frame is a full six-plane test",
                     am + "§3.5, fig. 7", Claim::conservative, kAabbKind, kTouchPn, kDerivedTol, true,
                     [](const CaseFrustum& f, const Volume& v) -> std::optional<Visibility> {
                       TrCoherencyCuller culler;
                       culler.begin_frame(f.planes);
                       TrObjectState st;
                       return culler.classify(std::get<Aabb>(v), st);
                     }));
}

}  // namespace cullproof::detail

// Registration of the fast culler family (src/cull/). Each algorithm lives in its own file;
// this file only wires them to the registry with their description (name, source, claim, volume
// kinds, treatment of touching volumes) and their two phases: what is derived once per frame
// (normalised planes, the LUT, the radar camera, the octant set-up) is derived in prepare.
//
// Tolerances (MethodInfo::tolerance, relative to the case scale) are the rounding allowances of
// the `conservative` / `exact` claims: 1e-6 for tests that evaluate the given planes directly
// (a few roundings of dot(n, x) + d), 1e-5 for tests that derive data first (normalised planes,
// camera parameters, OBB corners, clip-space corners, frustum corners, accumulated deltas).
#include "cullproof/simd/batch_adapter.hpp"
#include "builtin.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/core/cull_coherence.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace cullproof::detail {

namespace {

constexpr double kDirectTol = 1e-6;
constexpr double kDerivedTol = 1e-5;

const char* const kTouchPn =
    "plane value at the p-vertex == 0 is not rejected (touching from outside: intersecting); "
    "value at the n-vertex == 0 counts as inside (touching from inside: inside)";

// Per-frame states.
const auto normalized = [](const CaseFrustum& f) { return f.planes.normalized(); };

struct ClipMatrix {
  glm::mat4 m;
  DepthConvention depth;
};
// The case's matrix, or one rebuilt from its planes; nullopt when none can be.
std::optional<ClipMatrix> case_matrix(const CaseFrustum& f) {
  if (f.matrix) return ClipMatrix{*f.matrix, f.depth};
  const auto m = clip_matrix_from_frustum(f.planes);
  if (!m) return std::nullopt;
  return ClipMatrix{*m, DepthConvention{}};
}

std::optional<RadarCamera> radar(const CaseFrustum& f, bool as_published) {
  return radar_camera_from_frustum(f.planes, as_published);
}

std::optional<OctantCuller> octant_culler(const CaseFrustum& f) {
  if (!is_bounded(f.planes) || !is_symmetric(f.planes, 1e-5)) return std::nullopt;
  return OctantCuller(f.planes);
}

// Per-object states of a frame-coherent culler, by the order objects are classified in a frame.
template <class S>
struct ObjectStates {
  std::vector<S> states;
  std::size_t next = 0;
  S& next_state() {
    if (next == states.size()) states.emplace_back();
    return states[next++];
  }
  void clear() {
    states.clear();
    next = 0;
  }
};
template <class S>
struct PlanesAnd {
  Frustum planes;
  std::shared_ptr<ObjectStates<S>> store;
};

struct PlanesAndBounds {
  Frustum planes;
  FrustumBounds bounds;
};
const auto planes_and_bounds = [](const CaseFrustum& f) { return PlanesAndBounds{f.planes, frustum_bounds(f.planes)}; };

struct PlanesAndNormalized {
  Frustum planes, normalized;
};

const auto aabb_kernel = [](const Frustum& f) {
  return [&f](const AabbSoa& s, std::uint64_t* vis, std::uint64_t* ins) { classify_aabbs_bitset(f, s, vis, ins); };
};
const auto sphere_kernel = [](const Frustum& normalized_planes) {
  return [&normalized_planes](const SphereSoa& s, std::uint64_t* vis, std::uint64_t* ins) {
    classify_spheres_bitset(normalized_planes, s, vis, ins);
  };
};

const std::string am = "Assarsson & Möller 2000, ";
const std::string lh = "Lighthouse3D View Frustum Culling Tutorial, ";
constexpr Origin published = Origin::published, own = Origin::own;

// Points.
void register_point_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      describe("point-plane", published)
          .as("point against the six planes, outside on the first plane < 0")
          .from(lh + "Geometric Approach - Testing Points and Spheres (pointInFrustum)")
          .claims(Claim::exact, kDirectTol)
          .on(kPointKind)
          .touching("a point on a plane is inside (distance < 0 rejects)"),
      planes, [](const Frustum& f, const Point& p) { return point_plane_test(f, p); }));
  out.push_back(make_method(
      describe("radar-point", published)
          .as("radar test in camera coordinates (camera derived from a symmetric perspective frustum)")
          .from(lh + "Radar Approach - Testing Points, Implementation (pc.z = v.Z reading)")
          .claims(Claim::exact, kDerivedTol)
          .on(kPointKind)
          .touching("a point on the boundary is inside (strict > / < reject)"),
      [](const CaseFrustum& f) { return radar(f, false); },
      [](const RadarCamera& c, const Point& p) { return radar_point(c, p); }));
}

// Spheres.
void register_sphere_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      describe("sphere-plane", published)
          .as("sphere against the normalised planes: d < -r outside, d < r intersecting")
          .from(lh + "Geometric Approach - Testing Points and Spheres (sphereInFrustum)")
          .claims(Claim::conservative, kDerivedTol)
          .on(kSphereKind)
          .touching("touching from outside (d == -r) intersecting; touching from inside (d == r) inside"),
      normalized, [](const Frustum& f, const Sphere& s) { return sphere_plane_test(f, s); }));
  out.push_back(make_method(
      describe("radar-sphere", own)
          .as("radar sphere test with sphere factors 1/cos(half fov) (corrected)")
          .from(lh + "Radar Approach - Testing Spheres, Implementation II, with tan(fov/2)")
          .claims(Claim::conservative, kDerivedTol)
          .on(kSphereKind)
          .touching("touching a bound from outside is intersecting (strict compares)"),
      [](const CaseFrustum& f) { return radar(f, false); },
      [](const RadarCamera& c, const Sphere& s) { return radar_sphere_wide(c, s); }));
  out.push_back(make_method(
      describe("radar-sphere-as-published", published)
          .as("radar sphere test as published: tang = tan(fov), 1/cos(fov) (full angle)")
          .from(lh + "Radar Approach - Implementation II (setCamInternals as printed)")
          .claims(Claim::none, 0.0)
          .on(kSphereKind)
          .touching("touching a bound from outside is intersecting (strict compares)"),
      [](const CaseFrustum& f) { return radar(f, true); },
      [](const RadarCamera& c, const Sphere& s) { return radar_sphere(c, s); }));
  out.push_back(make_method(
      describe("sphere-batch-simd", own)
          .as("SoA SIMD batch sphere test (Highway, runtime dispatch); one volume runs as a full word of 64 copies")
          .from(lh + "sphereInFrustum; batch form of sphere-plane")
          .claims(Claim::conservative, kDerivedTol)
          .on(kSphereKind)
          .touching("as sphere-plane (bit-for-bit the same verdicts where the plane values are finite)"),
      normalized, [](const Frustum& f, const Sphere& s) { return sphere_as_word(s, sphere_kernel(f)); },
      [](const Frustum& f, const Sphere* s, std::size_t n, Visibility* v) { sphere_batch(s, n, v, sphere_kernel(f)); }));
}

// AABBs.
void register_aabb_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      describe("eight-corner", published)
          .as("8 corners counted per plane; outside when all 8 are out of one plane")
          .from(lh + "Geometric Approach - Testing Boxes (boxInFrustum)")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching("a corner with distance 0 counts as in: touching from outside is intersecting, from inside inside"),
      planes, [](const Frustum& f, const Aabb& b) { return aabb_eight_corner(f, b); }));
  out.push_back(make_method(
      describe("pn-vertex", published)
          .as("n/p-vertex test with per-box sign selection (fig. 4)")
          .from(am + "§3.1, fig. 4")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching(kTouchPn),
      planes, [](const Frustum& f, const Aabb& b) { return pn_vertex(f, b); }));
  out.push_back(make_method(
      describe("pn-vertex-index", own)
          .as("n/p-vertex test with the branch-free min/max index trick, three-way")
          .from("p-vertex blog post (View frustum culling, AABB vs Frustum), Implementation; three-way as A&M §3.1")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching(kTouchPn),
      planes, [](const Frustum& f, const Aabb& b) { return pn_vertex_index(f, b); }));
  out.push_back(make_method(
      describe("p-vertex-post", published)
          .as("the p-vertex post as published: p-vertex only, dp < -d rejects, never inside")
          .from("p-vertex blog post (View frustum culling, AABB vs Frustum), intersectFrustumAABB")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching("dp == -d is not rejected: touching from outside is intersecting; never answers inside")
          .two_way(),
      planes, [](const Frustum& f, const Aabb& b) { return p_vertex_post(f, b); }));
  out.push_back(make_method(
      describe("pn-vertex-lut", published)
          .as("n/p-vertex test with the sign bitfields precomputed once per frame")
          .from(am + "§3.1 (LUT, precomputed per frame) and §4")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching(kTouchPn),
      [](const CaseFrustum& f) { return make_pn_lut(f.planes); },
      [](const PnLut& lut, const Aabb& b) { return pn_vertex_lut(lut, b); }));
  out.push_back(make_method(
      describe("pn-vertex-batch-simd", own)
          .as("SoA SIMD batch n/p-vertex test (Highway, runtime dispatch); one volume runs as a full word of 64 copies")
          .from(am + "§3.1, batch form with the min/max choice hoisted per plane")
          .claims(Claim::conservative, kDirectTol)
          .on(kAabbKind)
          .touching(std::string(kTouchPn) + " (bit-for-bit pn-vertex-index)"),
      planes, [](const Frustum& f, const Aabb& b) { return aabb_as_word(b, aabb_kernel(f)); },
      [](const Frustum& f, const Aabb* b, std::size_t n, Visibility* v) { aabb_batch(b, n, v, aabb_kernel(f)); }));
  out.push_back(make_method(
      describe("perspective-transform-as-published", published)
          .as("DirectModel baseline: corners to clip space, divide by w, NDC AABB vs cube (w <= 0 not handled)")
          .from(am + "§2 and fig. 1 (DirectModel)")
          .claims(Claim::none, 0.0)
          .on(kAabbKind)
          .touching("strict rejection in NDC: touching from outside intersecting (when all w > 0)"),
      case_matrix,
      [](const ClipMatrix& c, const Aabb& b) { return perspective_transform_as_published(c.m, c.depth, b); }));
  out.push_back(make_method(
      describe("perspective-transform", own)
          .as("DirectModel baseline corrected: NDC AABB when all w > 0, homogeneous outcodes otherwise")
          // Claim none: conservative in exact arithmetic, but the float clip transform and the
          // division by w carry errors no tolerance of the plane model bounds; the oracle found
          // false rejects far beyond it on extreme-fov and corner cases (corpus/
          // perspective-transform/). It stays the Table 1 baseline, measured, not trusted.
          .from(am + "§2 and fig. 1 (DirectModel), corrected for corners behind the eye")
          .claims(Claim::none, kDerivedTol)
          .on(kAabbKind)
          .touching("strict rejection (hi < -1, w + x < 0): touching from outside intersecting"),
      case_matrix, [](const ClipMatrix& c, const Aabb& b) { return perspective_transform(c.m, c.depth, b); }));
}

// OBBs.
void register_obb_methods(std::vector<Method>& out) {
  out.push_back(make_method(
      describe("obb-pn-vertex", published)
          .as("n/p-vertex test with the plane normal projected on the box axes")
          .from(am + "§3.1; " + lh + "Geometric Approach - Testing Boxes II")
          .claims(Claim::conservative, kDerivedTol)
          .on(kObbKind | kAabbKind)
          .touching(kTouchPn),
      planes,
      overload{[](const Frustum& f, const Aabb& b) { return obb_pn_vertex(f, to_obb(b)); },
               [](const Frustum& f, const Obb& b) { return obb_pn_vertex(f, b); }}));
}

// Pre-test stages in front of pn-vertex.
void register_pretest_methods(std::vector<Method>& out) {
  const std::string notes = lh + "Some Notes and Possible Optimizations, ";
  out.push_back(make_method(
      describe("box-sphere-then-pn-vertex", published)
          .as("box's bounding sphere first; when it straddles, the n/p-vertex test")
          .from(notes + "Spheres as Bounding Volumes for Boxes (case C: test the box)")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching(std::string("sphere stage: touching sphere falls through; then ") + kTouchPn),
      [](const CaseFrustum& f) { return PlanesAndNormalized{f.planes, f.planes.normalized()}; },
      [](const PlanesAndNormalized& p, const Aabb& b) {
        if (auto r = box_sphere_stage(p.normalized, b)) return *r;
        return pn_vertex(p.planes, b);
      }));
  out.push_back(make_method(
      describe("box-sphere-only", published)
          .as("box's bounding sphere only; a straddling sphere means intersecting")
          .from(notes + "Spheres as Bounding Volumes for Boxes (case C: consider that the box intersects)")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching("a touching sphere (hence box) is intersecting"),
      normalized, [](const Frustum& f, const Aabb& b) {
        if (auto r = box_sphere_stage(f, b)) return *r;
        return Visibility::intersecting;
      }));
  out.push_back(make_method(
      describe("frustum-sphere-then-pn-vertex", published)
          .as("frustum's bounding sphere vs box's sphere first, then n/p-vertex")
          .from(notes + "Spheres everywhere")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching(std::string("touching spheres fall through; then ") + kTouchPn),
      planes_and_bounds, [](const PlanesAndBounds& p, const Aabb& b) {
        if (auto r = frustum_sphere_stage(p.bounds, b)) return *r;
        return pn_vertex(p.planes, b);
      }));
  out.push_back(make_method(
      describe("frustum-aabb-then-pn-vertex", published)
          .as("frustum's AABB vs the box first, then n/p-vertex")
          .from(notes + "Axis-Aligned Boxes everywhere")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching(std::string("strict compares, a touching box falls through; then ") + kTouchPn),
      planes_and_bounds, [](const PlanesAndBounds& p, const Aabb& b) {
        if (auto r = frustum_aabb_stage(p.bounds, b)) return *r;
        return pn_vertex(p.planes, b);
      }));
}

// Frame coherence: per-object state kept across the frames of a camera path (object k is
// the k-th box classified in a frame, the harness's contract for stateful methods), in a store
// the method's copies share and reset() empties.
void register_coherent_methods(std::vector<Method>& out) {
  {
    auto caches = std::make_shared<ObjectStates<PlaneCoherencyCache>>();
    out.push_back(make_method(
                      describe("plane-coherency", published)
                          .as("n/p-vertex test starting at the plane that rejected the box last frame")
                          .from(am + "§3.2")
                          .claims(Claim::conservative, kDirectTol)
                          .on(kAabbKind)
                          .touching(kTouchPn)
                          .stateful(),
                      [caches](const CaseFrustum& f) {
                        caches->next = 0;
                        return PlanesAnd<PlaneCoherencyCache>{f.planes, caches};
                      },
                      [](PlanesAnd<PlaneCoherencyCache>& s, const Aabb& b) {
                        return plane_coherency_test(s.planes, b, s.store->next_state());
                      })
                      .on_reset([caches] { caches->clear(); }));
  }
  out.push_back(make_method(
      describe("octant", published)
          .as("octant test as published: three outer planes when d2 <= d1 (symmetric frusta only)")
          .from(am + "§3.3, fig. 5 and 6")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching(kTouchPn)
          .stateful(),
      octant_culler, [](const OctantCuller& c, const Aabb& b) { return c.classify(b); }));
  out.push_back(make_method(
      describe("octant-corrected", own)
          .as("octant test; inside only via the bounding sphere or the inner planes")
          .from(am + "§3.3, corrected inside rule")
          .claims(Claim::conservative, kDerivedTol)
          .on(kAabbKind)
          .touching(kTouchPn)
          .stateful(),
      octant_culler, [](const OctantCuller& c, const Aabb& b) { return c.classify_corrected(b); }));
  {
    // The frames carry no camera pose: translation coherency (A&M §3.5 (2)) only; rotation
    // coherency is tested over posed camera paths by the frame tests.
    struct Tr : ObjectStates<TrObjectState> {
      TrCoherencyCuller culler;
    };
    auto tr = std::make_shared<Tr>();
    out.push_back(make_method(
                      describe("tr-coherency", published)
                          .as("translation/rotation coherency; first frame is a full six-plane test")
                          .from(am + "§3.5, fig. 7")
                          .claims(Claim::conservative, kDerivedTol)
                          .on(kAabbKind)
                          .touching(kTouchPn)
                          .stateful(),
                      [tr](const CaseFrustum& f) {
                        tr->culler.begin_frame(f.planes);
                        tr->next = 0;
                        return tr;
                      },
                      [](std::shared_ptr<Tr>& s, const Aabb& b) { return s->culler.classify(b, s->next_state()); })
                      .on_reset([tr] {
                        tr->culler = TrCoherencyCuller();
                        tr->clear();
                      }));
  }
}

}  // namespace

// In the order `cullproof methods` lists them.
void register_cull_methods(std::vector<Method>& out) {
  register_point_methods(out);
  register_sphere_methods(out);
  register_aabb_methods(out);
  register_obb_methods(out);
  register_pretest_methods(out);
  register_coherent_methods(out);
}

}  // namespace cullproof::detail

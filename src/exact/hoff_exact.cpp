// Hoff's structure completed so that it is exact (in exact arithmetic; float rounding aside).
//
// Source: K. Hoff 1996, the procedure of hoff96.cpp, plus the classical
// characterisation of intersecting convex polyhedra: P and Q meet iff a vertex of one lies in
// the other, or an edge of one meets a face of the other.
// Claim: exact (float errors only within rounding distance of the boundary).
//
// What was added to hoff96, and why (each gap is a false reject of hoff96, found by the oracle;
// the cases are in the corpus under corpus/hoff96/ once the verification run has written them):
//  1. OBB edges against frustum faces. Hoff tests only frustum edges against OBB faces. A long
//     thin box crossing the frustum (a "rod") has no corner inside the frustum, and no frustum
//     edge touches it, yet it is visible: hoff96 rejects it.
//  2. Every frustum corner inside the OBB, instead of the centre of projection. If the frustum
//     lies inside the box, no edge crosses a face, and the test must find a frustum point in the
//     box. The COP is not a frustum point (it lies behind the near plane), so a box holding the
//     whole frustum but not the eye is rejected by hoff96. Any frustum vertex works.
//  3. Box geometry as given: faces, edges and the point-in-box test use the parallelepiped of the
//     float values (dual basis), not the assumption that the axes are orthonormal.
// Needs a bounded frustum with frustum topology (nullopt otherwise). Touching is intersecting
// (closed tests).
#include "cullproof/exact.hpp"

#include "hull.hpp"

#include <cmath>

namespace cullproof {

using namespace exact_detail;

namespace {

// Coordinates s with p = c + sum s_i u_i (dual basis); the box is |s_i| <= h_i.
struct LocalFrame {
  glm::vec3 c;
  glm::vec3 w[3];  // dual basis: w_i . u_j = delta_ij
  bool ok = false;
  explicit LocalFrame(const Obb& b) : c(b.center) {
    const glm::vec3 c12 = glm::cross(b.axes[1], b.axes[2]);
    const float det = glm::dot(b.axes[0], c12);
    if (det == 0.0f || !std::isfinite(det)) return;
    w[0] = c12 / det;
    w[1] = glm::cross(b.axes[2], b.axes[0]) / det;
    w[2] = glm::cross(b.axes[0], b.axes[1]) / det;
    ok = true;
  }
  glm::vec3 local(const glm::vec3& p) const {
    const glm::vec3 d = p - c;
    return {glm::dot(d, w[0]), glm::dot(d, w[1]), glm::dot(d, w[2])};
  }
};

bool in_box(const glm::vec3& s, const glm::vec3& h) {
  return std::abs(s.x) <= h.x && std::abs(s.y) <= h.y && std::abs(s.z) <= h.z;
}

// Closed segment [a, b] (local coordinates) against the face s_k = side * h_k of the box |s| <= h.
bool segment_hits_local_face(const glm::vec3& a, const glm::vec3& b, const glm::vec3& h, int k, float side) {
  const float da = a[k] - side * h[k], db = b[k] - side * h[k];
  if ((da > 0.0f && db > 0.0f) || (da < 0.0f && db < 0.0f)) return false;
  const int j = (k + 1) % 3, l = (k + 2) % 3;
  if (da == 0.0f && db == 0.0f) return clip_segment_to_rect(a[j], b[j] - a[j], h[j], a[l], b[l] - a[l], h[l]);
  const float t = da / (da - db);
  const glm::vec3 p = a + t * (b - a);
  return std::abs(p[j]) <= h[j] && std::abs(p[l]) <= h[l];
}

}  // namespace

std::optional<Visibility> hoff_exact(const Frustum& f, const Obb& b, HoffStage* stage) {
  const auto poly = frustum_polyhedron(f);
  if (!poly) return std::nullopt;
  // The corner triples must be the polytope's vertices (not so when nearly parallel planes
  // cross between near and far): otherwise the edge and face tests look at the wrong solid.
  const auto hull = frustum_hull(f);
  if (!hull || hull->empty) return hull && hull->empty ? std::optional<Visibility>(Visibility::outside) : std::nullopt;
  auto end = [&](HoffStage s, Visibility v) {
    if (stage) *stage = s;
    return v;
  };
  const auto v = obb_corners(b);
  if (const auto decided = hoff_trivial_stages(f, v, stage)) return *decided;

  const LocalFrame frame(b);
  if (!frame.ok) return std::nullopt;  // coplanar axes: not a box
  glm::vec3 local[8];
  for (std::size_t i = 0; i < 8; ++i) local[i] = frame.local(poly->corners[i]);
  // Frustum edges against box faces (Hoff's step 5), in the box's own coordinates.
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      if (i & bit) continue;
      for (int k = 0; k < 3; ++k)
        for (float s : {1.0f, -1.0f})
          if (segment_hits_local_face(local[i], local[i | bit], b.half, k, s))
            return end(HoffStage::edge_face, Visibility::intersecting);
    }
  // Added 1: box edges against frustum faces.
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      if (i & bit) continue;
      for (int face = 0; face < kPlaneCount; ++face)
        if (segment_hits_frustum_face(v[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(i | bit)], f, face))
          return end(HoffStage::box_edge_face, Visibility::intersecting);
    }
  // Added 2: any frustum vertex inside the box (the frustum inside the box).
  for (const glm::vec3& s : local)
    if (in_box(s, b.half)) return end(HoffStage::containment, Visibility::intersecting);
  return end(HoffStage::final_reject, Visibility::outside);
}

}  // namespace cullproof

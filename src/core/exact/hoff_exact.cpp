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
// The whole float range: where the case's magnitudes leave float's comfortable range
// (float_range_ok, hull_range_ok), the same operations run in double; in float, a box's corners
// near FLT_MAX and the frustum's vertices beyond it overflow, and the edge parameters of a scene
// of subnormal size are rounding noise.
#include "cullproof/core/exact.hpp"

#include "hull.hpp"

#include <cmath>
#include <type_traits>

namespace cullproof {

using namespace exact_detail;

namespace {

// Coordinates s with p = c + sum s_i u_i (dual basis); the box is |s_i| <= h_i.
template <class T>
struct LocalFrame {
  Vec3<T> c;
  Vec3<T> w[3];  // dual basis: w_i . u_j = delta_ij
  bool ok = false;
  explicit LocalFrame(const Obb& b) : c(vec_as<T>(b.center)) {
    const Vec3<T> u0 = vec_as<T>(b.axes[0]), u1 = vec_as<T>(b.axes[1]), u2 = vec_as<T>(b.axes[2]);
    const Vec3<T> c12 = glm::cross(u1, u2);
    const T det = glm::dot(u0, c12);
    if (det == T(0) || !std::isfinite(det)) return;
    w[0] = c12 / det;
    w[1] = glm::cross(u2, u0) / det;
    w[2] = glm::cross(u0, u1) / det;
    ok = true;
  }
  Vec3<T> local(const Vec3<T>& p) const {
    const Vec3<T> d = p - c;
    return {glm::dot(d, w[0]), glm::dot(d, w[1]), glm::dot(d, w[2])};
  }
};

template <class T>
bool in_box(const Vec3<T>& s, const Vec3<T>& h) {
  return std::abs(s.x) <= h.x && std::abs(s.y) <= h.y && std::abs(s.z) <= h.z;
}

// Closed segment [a, b] (local coordinates) against the face s_k = side * h_k of the box |s| <= h.
template <class T>
bool segment_hits_local_face(const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& h, int k, T side) {
  const T da = a[k] - side * h[k], db = b[k] - side * h[k];
  if ((da > T(0) && db > T(0)) || (da < T(0) && db < T(0))) return false;
  const int j = (k + 1) % 3, l = (k + 2) % 3;
  if (da == T(0) && db == T(0)) return clip_segment_to_rect_as<T>(a[j], b[j] - a[j], h[j], a[l], b[l] - a[l], h[l]);
  const T t = da / (da - db);
  const Vec3<T> p = a + t * (b - a);
  return std::abs(p[j]) <= h[j] && std::abs(p[l]) <= h[l];
}

// `redo` is set (and nothing decided) when the float run finds the frustum's vertices beyond its
// range.
template <class T>
std::optional<Visibility> hoff_exact_in(const Frustum& f, const Obb& b, HoffStage* stage, bool& redo) {
  // A bounded frustum whose corner triples are the polytope's vertices (not so when nearly
  // parallel planes cross between near and far): otherwise the edge and face tests look at the
  // wrong solid. The corners are those of frustum_corners (the same triples, in double).
  const auto hull = frustum_hull_as<T>(f);
  if (!hull || hull->empty || !hull->rays.empty() || hull->vertices.size() != 8) return std::nullopt;
  if (std::is_same_v<T, float> && !hull_range_ok(f, b, hull->magnitude)) {
    redo = true;
    return std::nullopt;
  }
  auto end = [&](HoffStage s, Visibility v) {
    if (stage) *stage = s;
    return v;
  };
  const auto v = obb_corners_as<T>(b);
  if (const auto decided = hoff_trivial_stages_as<T>(f, v, stage)) return *decided;

  const LocalFrame<T> frame(b);
  if (!frame.ok) return std::nullopt;  // coplanar axes: not a box
  const Vec3<T> half = vec_as<T>(b.half);
  Vec3<T> local[8];
  for (std::size_t i = 0; i < 8; ++i) local[i] = frame.local(hull->vertices[i]);
  // Frustum edges against box faces (Hoff's step 5), in the box's own coordinates.
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      if (i & bit) continue;
      for (int k = 0; k < 3; ++k)
        for (T s : {T(1), T(-1)})
          if (segment_hits_local_face<T>(local[i], local[i | bit], half, k, s))
            return end(HoffStage::edge_face, Visibility::intersecting);
    }
  // Added 1: box edges against frustum faces.
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4}) {
      if (i & bit) continue;
      for (int face = 0; face < kPlaneCount; ++face)
        if (segment_hits_frustum_face_as<T>(v[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(i | bit)], f, face))
          return end(HoffStage::box_edge_face, Visibility::intersecting);
    }
  // Added 2: any frustum vertex inside the box (the frustum inside the box).
  for (const Vec3<T>& s : local)
    if (in_box<T>(s, half)) return end(HoffStage::containment, Visibility::intersecting);
  return end(HoffStage::final_reject, Visibility::outside);
}

}  // namespace

std::optional<Visibility> hoff_exact(const Frustum& f, const Obb& b, HoffStage* stage) {
  bool redo = !float_range_ok(f, b);
  if (!redo) {
    const auto v = hoff_exact_in<float>(f, b, stage, redo);
    if (!redo) return v;
  }
  return hoff_exact_in<double>(f, b, stage, redo);
}

}  // namespace cullproof

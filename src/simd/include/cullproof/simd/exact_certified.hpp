// Exact culling at the cost of the fast test: certified-exact AABB, OBB and sphere tests whose
// verdict equals the exact truth (CONVENTIONS "Ground truth": outside, intersecting, inside on
// closed sets) for every valid float input, end to end from the matrix, with or without FMA
// contraction. The error band is zero.
//
// A cascade, each stage answering only what it can prove (src/simd/exact_certified.cpp
// derives every bound):
//  1. planes: the certified n/p-vertex (or projected-radius, or r |n|) test in double on the
//     exact planes, with a derived margin: clear outside, clear inside, and a box crossing planes
//     that share its p-vertex, proved inside each of them (intersecting);
//  2. axes: what remains is a small problem in the planes that do not surely hold the volume.
//     Witness points prepared once per frame (anchors: an interior point, face centres and
//     vertices pulled inwards, each certified inside every plane) that the volume holds; boxes:
//     a linear programme in the box's own coordinates t in [-1,1]^3, whose dual vertices are
//     SAT's separating axes as combinations of planes, proves separation by a Farkas combination
//     or overlap by a witness point inside every plane; spheres: the distance from the centre to
//     the frustum's faces, edges and corners (Gram matrices prepared once per frame) proves
//     separation by a combined plane farther than r, or overlap by a witness point;
//  3. exact: what lies inside every bound (touching, or within a few units in the last place of
//     touching) is decided in exact integer arithmetic (Boost.Multiprecision), no CGAL.
// The array forms (cullproof/simd/exact_certified_batch.hpp, library cullproof::simd) run the SIMD
// certified batch first and the cascade on what it leaves.
// Per-frame set-up (exact planes, scaled planes and margins, Gram matrices, anchors) happens
// once, in prepare_exact_certified.
#pragma once

#include "cullproof/core/certified.hpp"
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace cullproof {

/// The stage of the cascade that decided a volume.
enum class ExactStage : std::uint8_t {
  planes = 0,  ///< stage 1: the certified plane test
  axes = 1,    ///< stage 2: certified combined planes, witness points, distances
  exact = 2,   ///< stage 3: exact integer arithmetic
};
/// "planes", "axes", "exact".
std::string_view to_string(ExactStage s) noexcept;

/// The error model (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., §2.2,
/// §3.1): double arithmetic, unit roundoff u = 2^-53, fl(x op y) = (x op y)(1 + e) with |e| <= u.
/// Every value the stages compute is a sum of products of floats and doubles whose magnitude
/// lies in [2^-700, 2^400] or is zero, so nothing overflows or underflows (see the derivation).
/// Each margin below is a multiple of u times a magnitude bound; exact_certified.cpp derives the
/// multiple the computation needs, and the test re-derives it from u.
struct ExactMargins {
  static constexpr double u = 0x1p-53;
  /// Stage 1, AABBs and OBBs: T = kBox u max A' X (uniform over planes scaled to A' in [1, 2); X the
  /// volume's magnitude), delta = kBox u |d'| folded into the offsets.
  static constexpr double kBox = 16.0;
  /// Stage 1, spheres: T = kSphere u A' (M + r), delta = kSphereOffset u |d'|.
  static constexpr double kSphere = 16.0;
  static constexpr double kSphereOffset = 8.0;
  /// Stage 2, box rows in t: eps = kRow u (A' X + |d'|), X the volume's magnitude.
  static constexpr double kRow = 16.0;
  /// Stage 2, a plane at a double point x: kPoint u (A' |x|_max + |d'|).
  static constexpr double kPoint = 8.0;
  /// Stage 2, a squared distance sum((x_i - c_i)^2) in double: relative kDistance u.
  static constexpr double kDistance = 8.0;
  /// Stage 2, a Farkas combination of rows (boxes): kFarkasBox u sum lambda_j W_j.
  static constexpr double kFarkasBox = 32.0;
  /// Stage 2, a Farkas combination of planes at a sphere's centre: kFarkasCentre u sum lambda_j W_j
  /// for the value, kFarkasNormal u sum lambda_j A'_j for the normal.
  static constexpr double kFarkasCentre = 12.0;
  static constexpr double kFarkasNormal = 8.0;
  /// Stage 2 of AABBs, the frame's combinations of planes (C, D) = sum lambda_q (n'_q, d'_q) at a
  /// box: |computed - exact| <= kCombination u sum lambda_q (A'_q X + |d'_q|), plus what the
  /// multipliers themselves err by (kMultiplier u times the sum of the magnitudes of the two
  /// products each is the difference of, for three planes; u lambda_q for two).
  static constexpr double kCombination = 16.0;
  static constexpr double kMultiplier = 5.0;
  /// Added to each Farkas bound: covers the underflows of products of multipliers and
  /// coefficients (exact_certified.cpp, "Multipliers").
  static constexpr double kFarkasUnderflow = 0x1p-1000;
  /// Relative slack added to every computed bound before it is compared (covers the few
  /// roundings of the bound itself: each is at most u, and there are fewer than 2^10).
  static constexpr double kSlack = 0x1p-40;
};

/// The AABB array form's float pass (binary32, u = 2^-24; exact_certified.cpp, "The AABB array
/// form's float pass"): an item's threshold for a box of magnitude X is fl(t X + delta) with
/// t >= (e1 + kEval u A_f)(1 + kWiden) and delta >= (e0 + kEval u |Df|)(1 + kWiden) + kUnderflow;
/// tests/certified/test_exact_certified.cpp (FloatPassMargins.*) re-derives each from u.
struct FloatPassMargins {
  static constexpr double u = 0x1p-24;
  /// gamma_4 / u: a value fl(C.x + D), four terms, any order, fused or not.
  static constexpr double kEval = 4.0001;
  /// Relative room for the threshold's own roundings (at most two, each a factor 1 - u).
  static constexpr double kWiden = 0x1p-20;
  /// A coefficient rounded to a subnormal float errs by up to this much absolutely.
  static constexpr double kSubnormal = 0x1p-150;
  /// Every absolute underflow of the evaluation (three products) and of the threshold.
  static constexpr double kUnderflow = 0x1p-126;
  /// Boxes with (A_f + t) X + |Df| + delta above this are not decided (no partial sum overflows).
  static constexpr double kRoom = 0x1p120;
};

/// One active plane of the cascade, scaled by a power of two 2^-e (exact) so that its bound sum
/// A' = sum |n'_i| lies in [1, 2).
struct ExactCertifiedPlane {
  double nx = 0, ny = 0, nz = 0;  ///< n' = fl64(exact n) 2^-e: |n' - n 2^-e| <= u |n'| per component
  double d = 0;                   ///< d' = fl64(exact d) 2^-e
  double a = 0;                   ///< A' = |n'_x| + |n'_y| + |n'_z|, rounded up
  double ad = 0;                  ///< |d'|
  double norm = 0;                ///< fl(sqrt(fl(n'.n'))): |norm - |n 2^-e|| <= 3.6 u norm
  double d_out_box = 0, d_in_box = 0;        ///< d' + kBox u |d'| rounded up, d' - kBox u |d'| rounded down
  double d_out_sphere = 0, d_in_sphere = 0;  ///< the same with kSphereOffset
  int index = 0;                  ///< the plane's index in CONVENTIONS order
};

/// A frustum prepared for the exact-certified cascade (once per frame).
struct ExactCertifiedFrustum {
  /// The exact planes: coefficient i (n_x, n_y, n_z, d) of plane k is first[k][i] + second[k][i]
  /// exactly (second is 0 for planes given as planes; a matrix plane is a Gribb-Hartmann row sum
  /// r4 + rj or r4 - rj, or the row r3, of the float matrix entries: the end-to-end truth).
  std::array<std::array<float, 4>, 6> first{}, second{};
  /// The planes with a nonzero normal, in CONVENTIONS order; an all-space plane (n == 0, d >= 0)
  /// is left out, a plane holding nothing (n == 0, d < 0) sets `empty`.
  std::array<ExactCertifiedPlane, 6> plane{};
  int count = 0;
  /// The same planes by component, lane j for plane[j], zero past `count` (the plane stages of
  /// OBBs and spheres test every plane at once): lanes[kLaneNx][j] is plane[j].nx, and so on.
  enum Lane : int {
    kLaneNx, kLaneNy, kLaneNz, kLaneD, kLaneDOutBox, kLaneDInBox, kLaneDOutSphere, kLaneDInSphere,
    kLaneNorm, kLaneA, kLaneAd, kLaneCount
  };
  std::array<std::array<double, 8>, kLaneCount> lanes{};
  bool empty = false;
  double t_box = 0, t_sphere = 0;  ///< kBox u max A', kSphere u max A', rounded up
  /// For each set of planes (bit j: plane[j]), whether their normals agree in sign on every axis,
  /// so that a box's p-vertex is the same for all of them.
  std::array<bool, 64> same_p_vertex{};
  /// Gram matrices of the scaled normals: gram[i][j] = fl(n'_i . n'_j) (i, j in `plane` order).
  std::array<std::array<double, 6>, 6> gram{};
  /// A point strictly inside every plane (when one was found and certified), in double, and the
  /// scaled planes' values there (lower bounds, after the margin): the anchor of witness points.
  bool has_interior = false;
  std::array<double, 3> interior{};
  std::array<double, 6> interior_value{};
  /// Anchors: the interior point, the centres of the faces and the vertices of the frustum pulled
  /// towards it by 2^-12 of the way, each certified inside every plane (witness points for volumes
  /// holding part of a face or a corner), and their bounding box.
  /// Anchor k is (anchor_x[k], anchor_y[k], anchor_z[k]), k < anchor_count; the rest are NaN.
  static constexpr int kAnchors = 16;
  std::array<double, kAnchors> anchor_x{}, anchor_y{}, anchor_z{};
  int anchor_count = 0;
  std::array<double, 3> anchor_lo{}, anchor_hi{};  ///< the anchors' bounding box
  /// Stage 2 of AABBs: the separating axes of the box and the frustum other than the planes, as
  /// combinations of the planes, prepared once per frame (an AABB's axes are the coordinate axes,
  /// so they do not depend on the box): two planes whose normals differ in sign on an axis, with
  /// the multipliers that cancel it (an edge of the frustum against a box axis); three planes with
  /// those that cancel two axes (a corner of the frustum against a box face). Combination q is the
  /// plane (cx, cy, cz, d) = sum lambda (n', d'), and proves what it proves about a box of
  /// magnitude X beyond k1 X + k0.
  struct Combination {
    double cx = 0, cy = 0, cz = 0, d = 0;
    double k1 = 0, k0 = 0;
    std::uint32_t planes = 0;  ///< bit j: plane[j] is combined
  };
  static constexpr int kCombinations = 128;  ///< at least 15 pairs x 3 axes + 20 triples x 3
  std::array<Combination, kCombinations> comb{};
  int comb_count = 0;
  /// comb_in[J]: the combinations whose planes all lie in the set J (bit q % 64 of word q / 64).
  std::array<std::array<std::uint64_t, 2>, 64> comb_in{};
  /// Whether the combinations are every vertex of the dual programme with at most three planes
  /// (has_interior, and no multiplier of uncertain sign): then an AABB that every combination and
  /// every plane of J proves on its inner side meets the frustum.
  bool comb_complete = false;
  /// The AABB array form's float pass (exact_certified.cpp, "The AABB array form's float pass"):
  /// the planes (items 0 .. count - 1, in `plane` order) and the combinations (item count + q is
  /// comb[q]; float_count in all), each scaled
  /// by a power of two and rounded to float, with its threshold theta = fl(t X + delta) for a box
  /// of magnitude X <= float_x_safe: a value beyond -theta or theta at a vertex proves its sign.
  struct FloatItem {
    float cx = 0, cy = 0, cz = 0, d = 0;
    float t = 0, delta = 0;
    std::uint32_t planes = 0;            ///< bit j: plane[j] is in it
    std::array<std::uint8_t, 3> max{};   ///< 1 where c_i >= 0: the p-vertex takes max_i
    std::array<std::uint8_t, 3> member{};  ///< its planes (a pair repeats one), for combinations
  };
  std::array<FloatItem, 6 + kCombinations> float_item{};
  int float_planes = 0;  ///< count, or 0 when a plane does not fit a float (no float pass then)
  int float_count = 0;
  float float_x_safe = 0.0f;
  /// Bit J set where no combination lies within the set of planes J (comb_in[J] empty).
  std::uint64_t float_no_combination = 0;
  /// comb_complete, and every plane and combination has its item: the pass may prove `intersecting`.
  bool float_complete = false;
  /// The float certified frustum (src/core/certified/certified.cpp) for the SIMD batch's first stage.
  CertifiedFrustum certified;
};

/// Prepares a case frustum: planes as given, or the exact extraction of the matrix.
ExactCertifiedFrustum prepare_exact_certified(const CaseFrustum& f);

/// The exact verdict for an AABB. `stage`, when given, receives the stage that decided.
Visibility exact_certified_aabb(const ExactCertifiedFrustum& f, const Aabb& b, ExactStage* stage = nullptr);
/// The exact verdict for an OBB (the parallelepiped of its float values, CONVENTIONS "OBB").
Visibility exact_certified_obb(const ExactCertifiedFrustum& f, const Obb& b, ExactStage* stage = nullptr);
/// The exact verdict for a sphere (closed ball).
Visibility exact_certified_sphere(const ExactCertifiedFrustum& f, const Sphere& s, ExactStage* stage = nullptr);

}  // namespace cullproof

// cullproof::oracle — exact ground truth for frustum culling.
//
// Truth is docs/semantics.md "The truth": outside when B ∩ F is empty, inside when
// B ⊆ F, intersecting otherwise, for closed B and F, computed exactly from the float values.
// A matrix case is classified end to end: F is the Gribb–Hartmann extraction from the float
// matrix entries with rows added in exact arithmetic, never the float-rounded planes.
//
// Two layers, as in CGAL's filtered predicates:
//  1. an interval filter (CGAL::Interval_nt under Protect_FPU_rounding) that answers only
//     when its interval bounds prove the answer;
//  2. the exact route: every float converted losslessly to CGAL::Gmpzf / Gmpq, containment
//     by exact corner evaluation, B ∩ F ≠ ∅ as an exact LP in t ∈ [-1,1]^3 (boxes) or an
//     exact QP (spheres), both with CGAL's QP solver.
// Every answer carries a certificate that the oracle checks before answering (a point of
// B ∩ F, or a separating plane Σ λ_j plane_j with λ ≥ 0 that B lies strictly behind); a failed
// check throws OracleError, it never returns an answer.
//
// A second, independent exact method (classify_independent: vertex enumeration of B ∩ F in
// integer arithmetic, no CGAL solver) exists only to cross-check the first.
//
// This header does not include CGAL: the CLI and the harness link cullproof::oracle without
// compiling CGAL themselves.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cullproof::oracle {

/// Thrown when the oracle's own certificate fails its exact check (a bug, never an answer).
class OracleError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// What Result::distance measures, by truth (all lengths in the input's units, Euclidean):
///  - outside:      the Euclidean distance between B and F, min |b - q| over b ∈ B, q ∈ F
///                  (for a ball: dist(centre, F) - r). The squared distance is an exact QP
///                  optimum; the oracle checks the optimal pair is feasible, realises it, and is
///                  optimal (exact KKT multipliers give a plane proving the matching lower
///                  bound); then one square root in double. +infinity when F is empty.
///  - inside:       the clearance min_j min_{x∈B} (n_j·x + d_j)/|n_j| over planes with n ≠ 0:
///                  exactly the length of the shortest translation that makes B stop being
///                  inside (+infinity when every plane is "all space").
///  - intersecting: min(penetration, protrusion), where
///                  penetration = min_j max_{x∈B} (n_j·x + d_j)/|n_j|: the shortest translation
///                    along a frustum-plane normal after which B only touches F (any further
///                    and B is outside); an upper bound on the true penetration depth;
///                  protrusion = max_j max(0, -min_{x∈B} (n_j·x + d_j)/|n_j|): how far the
///                    farthest point of B lies beyond one plane; a lower bound on any
///                    translation that makes B inside.
///                  Both are also in the witness.
/// Every quantity is formed exactly and rounded once or twice at the end (a quotient and a
/// square root): relative error below 4 ulp of double. Degenerate planes (n == 0) take no part.
enum class DistanceKind : std::uint8_t { euclidean, margin, clearance, none };

/// An exact rational as the oracle writes it ("p/q", or "p" when an integer; GMP's canonical
/// form, lowest terms) with its nearest double.
struct Rational {
  std::string exact;
  double approx = 0.0;
};

/// The checked certificate of a verdict: what the oracle proved, in exact numbers.
struct Witness {
  enum class Kind : std::uint8_t {
    none,              ///< not requested (Options::witness false); the certificate was still checked
    point,             ///< inside or intersecting: an exact point of B ∩ F
    separating_plane,  ///< outside: a plane that holds F with B strictly behind it
  };
  Kind kind = Kind::none;
  /// Kind point: the point. "inside" itself is proved by evaluating every corner (or the ball's
  /// offset) exactly; the point shows B ∩ F is not empty.
  std::array<Rational, 3> point{};
  /// Intersecting: the index of a plane some point of B violates, and for boxes that corner.
  int violated_plane = -1;
  std::optional<std::array<Rational, 3>> outside_corner;
  /// Kind separating_plane: plane = Σ λ_j plane_j, λ ≥ 0, one multiplier per frustum plane.
  std::array<Rational, 4> plane{};
  std::array<Rational, 6> multipliers{};
  /// Intersecting, when the distance was measured: penetration and protrusion (DistanceKind).
  std::optional<double> penetration, protrusion;
};

/// The oracle's answer for one case.
struct Result {
  Visibility truth = Visibility::outside;  ///< exact truth (docs/semantics.md "The truth")
  double distance = 0.0;                   ///< see DistanceKind; NaN when not requested
  DistanceKind distance_kind = DistanceKind::none;  ///< what `distance` measures
  Witness witness;                          ///< kind none when Options::witness is false
  bool filtered = false;  ///< decided by the interval filter (no exact solver call)
};

/// Per-call switches. The truth and its certificate check are never skipped. Member order is
/// stable (callers use aggregate initialisation: Options{filter, distance, witness}).
struct Options {
  bool filter = true;    ///< try the interval filter before the exact route
  bool distance = true;  ///< compute Result::distance (an exact QP for outside volumes)
  bool witness = true;   ///< fill Result::witness (its exact numbers are formed as text)
  /// Closest points (an outside volume's distance, a ball's nearest point of F): first a pair found
  /// in double and solved exactly on the constraints active there, kept when its optimality
  /// conditions hold exactly (the same checks as the QP's answer); else the exact QP. False: the
  /// exact QP alone. The answer is the same exact optimum either way.
  bool closest_in_double = true;
};

/// Exact classification of v against f with checked certificate and distance. Thread-safe.
/// Throws ValidationError for invalid input, OracleError when a self-check fails.
Result classify(const CaseFrustum& f, const Volume& v);
/// As classify(f, v), with per-call options (e.g. truth only, or exact route only). Thread-safe.
Result classify(const CaseFrustum& f, const Volume& v, const Options& options);
/// Truth only: classify with the filter, no distance, no witness. Thread-safe.
Visibility truth(const CaseFrustum& f, const Volume& v);
/// classify(f, v).distance for a case whose truth the oracle has decided (by classify or truth),
/// without deciding it again: `truth` must be that answer. Throws as classify. Thread-safe.
double distance(const CaseFrustum& f, const Volume& v, Visibility truth);

/// {"truth": "...", "distance": x (null when infinite or not computed), "distance_kind": "...",
/// "filtered": bool, "witness": to_json(witness)}.
nlohmann::json to_json(const Result& r);
/// {} for kind none; {"kind": "point", "point": ["p/q" x3], "point_approx": [x3]} plus
/// "violated_plane", "outside_corner" (exact, boxes), "penetration", "protrusion" where known;
/// {"kind": "separating_plane", "plane": ["p/q" x4], "plane_approx": [x4], "multipliers":
/// ["p/q" x6]}. The corpus files carry this form.
nlohmann::json to_json(const Witness& w);
/// "none", "point", "separating_plane".
std::string_view to_string(Witness::Kind k) noexcept;
/// "euclidean", "margin", "clearance" or "none".
std::string_view to_string(DistanceKind k) noexcept;

/// How far a verdict lies from being the truth (docs/semantics.md "Forgiven means explained by
/// rounding"): the smallest change of the case that makes the verdict given the truth. With
/// s_j(x) = (n_j·x + d_j)/|n_j| the signed distance to plane j (planes with n != 0), the change
/// is a shift of every plane by the same length (outward or inward, as rounding perturbs plane
/// values); a shift of the volume never needs less (moving B by t changes each s_j by at most
/// |t|). By the verdict given and the truth:
///  - to_outside   (verdict outside; truth intersecting or inside): the depth
///                 max_{x∈B} min_j s_j(x), how far the planes must move in before B misses F;
///  - to_inside    (verdict inside; truth outside or intersecting): the protrusion
///                 max_j max_{x∈B} -s_j(x), how far B reaches beyond its farthest plane;
///  - to_meeting   (verdict intersecting; truth outside): minus the depth, how far the planes
///                 must move out before they reach B;
///  - to_leaving   (verdict intersecting; truth inside): the clearance min_j min_{x∈B} s_j(x),
///                 how far in they must move before B is not inside.
/// A verdict two classes away is thus measured across the whole volume, never by its nearness to
/// the boundary alone.
enum class VerdictShift : std::uint8_t { none, to_outside, to_inside, to_meeting, to_leaving };

/// A proven lower bound on that distance. Boxes, OBBs and points: the protrusion and clearance
/// are exact corner values over |n_j| in interval arithmetic; the depth is an exact LP over the
/// box with |n_j| rounded up (the LP's optimum moves toward zero, never away). Balls: the
/// protrusion and clearance likewise; the depth is certified by a point of the ball (a lower
/// bound on the depth) or by multipliers λ ≥ 0 (Σ λ_j s_j over the ball bounds it from above),
/// both evaluated in exact numbers and interval arithmetic. For boxes, OBBs and points the bound
/// lies within a relative 2^-50 of the exact distance. A ball's point is searched in double at the
/// ball's magnitude, so for a ball far larger than the frustum the bound may lie below the
/// distance by what double loses of |c| + r (a few units in its 50th bit), far less than any
/// rounding allowance of the case.
struct VerdictDistance {
  double distance = 0.0;  ///< 0 when the verdict is the truth; +infinity when no shift helps
  VerdictShift shift = VerdictShift::none;
  Visibility truth = Visibility::outside;
};

/// The distance from verdict `verdict` to the truth for v against f (see VerdictShift). Throws
/// ValidationError for invalid input. Thread-safe.
VerdictDistance distance_to_verdict(const CaseFrustum& f, const Volume& v, Visibility verdict);
/// "none", "depth" (to_outside), "protrusion" (to_inside), "gap" (to_meeting), "clearance" (to_leaving).
std::string_view to_string(VerdictShift s) noexcept;

/// The independent exact method, used only to cross-check classify: exact rationals/integers,
/// vertex enumeration of {t ∈ [-1,1]^3 : plane_j(c + Σ t_i e_i) ≥ 0} for boxes and points,
/// closest-point enumeration over faces of F for spheres. No CGAL solver, no filter. Thread-safe.
Visibility classify_independent(const CaseFrustum& f, const Volume& v);

/// Counters since start (or the last reset_stats), updated atomically by classify.
struct Stats {
  std::uint64_t calls = 0;      ///< classify calls with the filter enabled
  std::uint64_t filtered = 0;   ///< of those, decided by the interval filter
  std::uint64_t fallbacks = 0;  ///< of those, sent to the exact route
  std::uint64_t exact_lp = 0;   ///< exact LP solves (feasibility, certificate, distance QP)
  std::uint64_t closest_pairs = 0;  ///< closest pairs found in double and proven, no QP solved
  /// fallbacks / calls (0 when no calls).
  double fallback_fraction() const noexcept {
    return calls == 0 ? 0.0 : static_cast<double>(fallbacks) / static_cast<double>(calls);
  }
};
/// A snapshot of the counters (each read atomically; the set is not one atomic snapshot).
Stats stats() noexcept;
/// Sets every counter to zero.
void reset_stats() noexcept;

}  // namespace cullproof::oracle

// The side-by-side verification run (`cullproof verify`): every selected method and the exact
// oracle on the same generated cases; error classes, conservativeness, cost; mismatches shrunk
// and written to the corpus.
//
// Definitions used in the report (docs/semantics.md "Errors"):
//  - false-intersect rate  = false intersects / cases whose truth is outside (the invisible
//    volumes a method fails to cull), with a 95% Wilson score interval;
//  - under-inside rate     = under-insides / cases whose truth is inside;
//  - distance of a false intersect = the oracle's exact Euclidean distance between the volume
//    and the frustum, divided by the scene size (the diameter of the frustum's bounded part);
//  - a claim is refuted by an error its claim forbids (see `violates_claim`), beyond the method's
//    tolerance where the claim has one;
//  - cost: per frame, the method's prepare (set-up) is timed apart from its classify over the
//    frame's volumes (through its array form when it has one): cases are grouped into frames of
//    VerifyOptions::frame_size volumes against one frustum, as a culler runs in an engine.
#pragma once

#include "cullproof/gen/generators.hpp"
#include "cullproof/judge/judge.hpp"
#include "cullproof/methods/methods.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include <string_view>

namespace cullproof {
struct VerifyOptions {
  std::uint64_t cases = 100000;                ///< per distribution
  std::uint64_t seed = 1;
  std::vector<gen::Distribution> distributions = gen::generic_distributions();
  std::vector<std::string> methods;            ///< run_verify(options): built-in names; empty: all
  int threads = 0;                             ///< 0: all hardware threads
  std::optional<std::filesystem::path> corpus; ///< write new mismatches here
  int corpus_per_class = 1;                    ///< non-violating errors kept per (method, distribution, class)
  int shrink_budget = 400;                     ///< oracle calls per shrink
  std::optional<std::uint64_t> only_index;     ///< reproduce one case
  bool progress = true;                        ///< progress bar on stderr
  bool timing = true;                          ///< measure set-up per frame and ns/test
  std::size_t frame_size = 1024;               ///< volumes per frame when timing
  int timing_frames = 8;                       ///< frames per distribution when timing
  /// Where a case that makes a method fault is saved (see MethodFault); unset: `corpus`/faults.
  std::optional<std::filesystem::path> faults;
};

struct MethodStats {
  std::string method;
  Claim claim = Claim::none;
  Origin origin = Origin::user;
  bool three_way = true;
  unsigned volumes = 0;     ///< the volume kinds the method takes (VolumeKind bits)
  std::uint64_t cases = 0;  ///< cases the method applies to
  std::uint64_t truth_outside = 0, truth_intersecting = 0, truth_inside = 0;
  std::uint64_t false_reject = 0, false_inside = 0, false_intersect = 0, under_inside = 0;
  std::uint64_t claim_violations = 0;
  std::uint64_t float_exact_violations = 0;  ///< of claim_violations, on float-exact cases (no allowance)
  /// The smallest case index (of the distribution) at which the claim broke, if it did.
  std::optional<std::uint64_t> first_violation;
  std::vector<double> fi_distance;  ///< relative distances of false intersects
  double ns_per_test = 0.0;         ///< classify, per volume, in frames (NaN: not timed)
  double ns_setup_per_frame = 0.0;  ///< prepare, per frame (NaN: not timed)
  bool timed_batch = false;         ///< classify was timed through the method's array form
  /// What the method reported of itself over the same frames (a program's own clock around its
  /// classification, without the protocol's messages); NaN when it reports nothing.
  double ns_per_test_own = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> corpus_written;  ///< ids of corpus cases written by this run
  /// Ids of the corpus cases that record this run's claim violations (up to 4 per error class),
  /// written now or recorded already by an earlier run with the same seed. Empty without a corpus.
  std::vector<std::string> violation_ids;
  bool refuted() const noexcept { return claim_violations > 0; }
};

struct DistributionResult {
  gen::Distribution distribution{};
  std::uint64_t cases = 0;
  std::uint64_t oracle_calls = 0, oracle_fallbacks = 0;
  std::uint64_t float_exact_cases = 0;  ///< cases on which nothing rounds (gen::float_exact)
  std::vector<MethodStats> methods;
};

struct VerifyResult {
  VerifyOptions options;
  std::vector<DistributionResult> distributions;
  double wall_seconds = 0.0;
  /// A claim of one of cullproof's own methods or of a user's method broke (the run's exit
  /// status is non-zero). Refuted claims of published methods are findings, not failures.
  bool claim_broken() const noexcept;
};

/// Runs the campaign on `methods` (a user's, built-in ones, or both; names must be unique).
/// options.methods is ignored. Progress goes to stderr when options.progress is set. Throws
/// MethodFault when a method faults, std::invalid_argument for a duplicate name.
VerifyResult run_verify(const VerifyOptions& options, const std::vector<Method>& methods);
/// Runs the campaign on the built-in methods named by options.methods (all when empty).
VerifyResult run_verify(const VerifyOptions& options);
/// One table per distribution (the README format).
void print_tables(const VerifyResult& r, std::ostream& out);
/// The whole result for scripts (and for `cullproof report`).
nlohmann::json to_json(const VerifyResult& r);

/// The false-intersect distances (relative to the scene size) counted per decade:
/// {"first_decade": k0, "counts": [...], "below": n, "above": n}, where counts[i] holds the
/// distances in [10^(k0+i), 10^(k0+i+1)), "below" those under 10^k0 and "above" those of
/// 10^kFiHistogramLastDecade or more. Counts of several runs or distributions add up.
nlohmann::json fi_distance_histogram(const std::vector<double>& distances);
inline constexpr int kFiHistogramFirstDecade = -16;  ///< rounding of double at the scene's scale
inline constexpr int kFiHistogramLastDecade = 2;     ///< a hundred scene sizes away


}  // namespace cullproof

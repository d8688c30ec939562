// The side-by-side verification run (`cullproof verify`): every selected method and the exact
// oracle on the same generated cases; error classes, conservativeness, cost; mismatches shrunk
// and written to the corpus.
//
// Definitions used in the report (docs/semantics.md "Errors"):
//  - false-intersect rate  = false intersects / cases whose truth is outside (the invisible
//    volumes a method fails to cull), with a 95% Wilson score interval;
//  - under-inside rate     = under-insides / cases whose truth is inside, of the volume kinds the
//    method answers three-way;
//  - distance of a false intersect = the oracle's exact Euclidean distance between the volume
//    and the frustum, divided by the scene size (the diameter of the frustum's bounded part);
//  - a claim is refuted by an error its claim forbids (see `violates_claim`), beyond the method's
//    tolerance where the claim has one;
//  - a method faults when it breaks the method interface on a case (it throws, answers a value
//    that is not a verdict, or `inside` being two-way; behind the process protocol, it exits,
//    hangs or answers what the protocol does not allow): it is not asked again in that
//    distribution, its counts there are over the cases before the one it faulted on (the smallest
//    such index, whatever the threads), and the case is saved; the other methods run on;
//  - cost: per frame, the method's prepare (set-up) is timed apart from its classify over the
//    frame's volumes (through its array form when it has one): cases are grouped into frames of
//    VerifyOptions::frame_size volumes against one frustum, as a culler runs in an engine.
#pragma once

#include "cullproof/gen/generators.hpp"
#include "cullproof/judge/judge.hpp"
#include "cullproof/methods/methods.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>
#include <string_view>

namespace cullproof {

struct DistributionResult;

/// Shard `index` of `count` (index < count): one part of a run split over machines (`cullproof
/// verify --shard K/N`, merged by `cullproof merge`). Every distribution's cases are cut into
/// `count` consecutive ranges of whole frames (shard_cases); shard K runs range K.
struct Shard {
  std::uint64_t index = 0, count = 1;
};

/// The cases [first, first + n) of `shard` among `cases` of distribution `d`: the family's frames
/// (gen::cases_per_frame; a camera path's gen::kPathFrames x gen::kPathObjects cases for
/// camera-path) shared out in order, shard K taking frames [K F / N, (K + 1) F / N) of F. Every
/// case is in exactly one shard; a shard may have none.
std::pair<std::uint64_t, std::uint64_t> shard_cases(gen::Distribution d, std::uint64_t cases, const Shard& shard);

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
  std::optional<Shard> shard;                  ///< run only this shard's cases (not with only_index)
  bool progress = true;                        ///< progress bar on stderr
  bool timing = true;                          ///< measure set-up per frame and ns/test
  std::size_t frame_size = 1024;               ///< volumes per frame when timing
  int timing_frames = 8;                       ///< frames per distribution when timing
  /// Where a case that makes a method fault is saved (see MethodFault); unset: `corpus`/faults.
  std::optional<std::filesystem::path> faults;
  /// Set (by a signal handler, say) to stop the run: the cases judged so far are counted, recorded
  /// and reported, the distribution under way and the result marked interrupted, the others not
  /// run. Read without a lock; must outlive the run.
  const std::atomic<bool>* stop = nullptr;
  /// Called with each distribution's result as soon as it is complete (to print its table), on
  /// the thread that called run_verify, with the progress line cleared.
  std::function<void(const DistributionResult&)> on_distribution;
};

/// A method broke the method interface (see the definitions above): what it did, on which case,
/// and how to see it again.
struct MethodFault {
  std::string method;
  std::string problem;
  /// The distribution's case index it faulted on; unset for a fault while it was timed (on the
  /// timing frames, which are not the cases judged).
  std::optional<std::uint64_t> index;
  std::string reproduce;                        ///< the command that reruns the case (empty: timing)
  std::optional<std::filesystem::path> saved;   ///< the file the case was saved to, if it was
  std::string where;                            ///< "saved to FILE", or why it was not
  nlohmann::json failing_case;                  ///< the case format, with method, fault, index, reproduce
  /// The report's lines: the problem, the case, the reproduce command and where the case went.
  std::string message(gen::Distribution d, std::uint64_t seed) const;
};

/// One of a method's errors that a run records in its corpus, as a shard reports it for the merge
/// to choose among: a run records the first corpus_per_class errors of each class its claim allows
/// (by case index) and the 4 claim violations of each class farthest beyond their allowance (the
/// earlier case first among equals). A shard's are the ones it would record of its own cases, a
/// superset of the run's among them; merge_shards keeps what one run would record.
struct CorpusCandidate {
  std::uint64_t index = 0;   ///< the distribution's case index it was found on
  ErrorClass error{};
  bool violation = false;    ///< counted as a claim violation (chosen by rank) or not (by index)
  /// Of a violation: its judged distance over its allowance (infinity: unbounded, as on a
  /// float-exact case); 0 otherwise.
  double rank = 0.0;
  std::string id;            ///< the record's id
  std::string file;          ///< under the corpus folder: <method>/<distribution>/<class>-<hash>.json
  bool violates = false;     ///< the record's "violates_claim"
  std::string text;          ///< the record's file text
};

struct MethodStats {
  std::string method;
  std::string program;  ///< Method::program: the program behind it (empty: in process)
  Claim claim = Claim::none;
  Origin origin = Origin::user;
  bool three_way = true;
  unsigned two_way_kinds = 0;  ///< of a three-way method, the kinds it answers two-way (MethodInfo)
  unsigned volumes = 0;     ///< the volume kinds the method takes (VolumeKind bits)
  std::uint64_t cases = 0;  ///< cases the method applies to
  std::uint64_t truth_outside = 0, truth_intersecting = 0, truth_inside = 0;
  /// Of truth_inside, the volumes of the kinds it answers three-way: the under-inside rate's base.
  std::uint64_t truth_inside_three_way = 0;
  std::uint64_t false_reject = 0, false_inside = 0, false_intersect = 0, under_inside = 0;
  std::uint64_t claim_violations = 0;
  std::uint64_t float_exact_violations = 0;  ///< of claim_violations, on float-exact cases (no allowance)
  /// The smallest case index (of the distribution) at which the claim broke, if it did.
  std::optional<std::uint64_t> first_violation;
  std::string first_violation_reproduce;  ///< the command that reruns it (reproduce_command)
  std::vector<double> fi_distance;  ///< relative distances of false intersects
  double ns_per_test = std::numeric_limits<double>::quiet_NaN();         ///< classify, per volume, in frames (NaN: not timed)
  double ns_setup_per_frame = std::numeric_limits<double>::quiet_NaN();  ///< prepare, per frame (NaN: not timed)
  bool timed_batch = false;         ///< classify was timed through the method's array form
  /// What the method reported of itself over the same frames (a program's own clock around its
  /// classification, without the protocol's messages); NaN when it reports nothing.
  double ns_per_test_own = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::string> corpus_written;  ///< ids of corpus cases written by this run
  /// Ids of the corpus cases that record this run's claim violations (up to 4 per error class),
  /// written now or recorded already by an earlier run with the same seed. Empty without a corpus.
  std::vector<std::string> violation_ids;
  /// A shard's (VerifyOptions::shard, with a corpus): the records it would write, in the order it
  /// writes them; a merged run's: those one run writes, in its order (write_merged_corpus).
  std::vector<CorpusCandidate> corpus_candidates;
  /// Set when the method faulted in this distribution: its counts are over the cases before the
  /// fault's index (all of them when it faulted while being timed).
  std::optional<MethodFault> fault;
  bool refuted() const noexcept { return claim_violations > 0; }
};

struct DistributionResult {
  gen::Distribution distribution{};
  std::uint64_t first_case = 0;  ///< the index of the run's first case (a shard's or --index's)
  std::uint64_t cases = 0;  ///< cases judged by the oracle (fewer than asked when interrupted)
  std::uint64_t cases_asked = 0;
  bool interrupted = false;  ///< VerifyOptions::stop was set before the distribution was done
  std::uint64_t oracle_calls = 0, oracle_fallbacks = 0;
  std::uint64_t float_exact_cases = 0;  ///< cases on which nothing rounds (gen::float_exact)
  std::vector<MethodStats> methods;
};

struct VerifyResult {
  VerifyOptions options;
  std::vector<DistributionResult> distributions;
  double wall_seconds = 0.0;
  /// VerifyOptions::stop stopped the run: the last distribution is cut short (marked), the ones
  /// after it are missing.
  bool interrupted = false;
  /// A claim of one of cullproof's own methods or of a user's method was refuted. Refuted claims of
  /// published methods are findings, not failures.
  bool claim_broken() const noexcept;
  /// Faults, over every distribution.
  std::size_t faults() const noexcept;
  /// The run failed: a claim broke (claim_broken) or a method faulted. `cullproof verify` exits
  /// with 1 for a broken claim, 3 for a fault (the stronger), 128 + the signal when interrupted.
  bool failed() const noexcept { return claim_broken() || faults() > 0; }
};

/// Runs the campaign on `methods` (a user's, built-in ones, or both; names must be unique).
/// options.methods is ignored. Progress goes to stderr when options.progress is set. A method's
/// fault is reported in its MethodStats (the run goes on); throws std::invalid_argument for a
/// duplicate name.
VerifyResult run_verify(const VerifyOptions& options, const std::vector<Method>& methods);
/// Runs the campaign on the built-in methods named by options.methods (all when empty).
VerifyResult run_verify(const VerifyOptions& options);
/// One table per distribution (the README format), then what the columns mean.
void print_tables(const VerifyResult& r, std::ostream& out);
/// One distribution's table, with its faults under it.
void print_table(const DistributionResult& d, std::uint64_t seed, std::ostream& out);
/// What the tables' columns mean, and the run's wall time and state (interrupted).
void print_table_notes(const VerifyResult& r, std::ostream& out);
/// The whole result for scripts (and for `cullproof report`). A shard's (options.shard) carries
/// what a merge needs besides: "shard" (index, count), "run" (what identifies the run: version,
/// seed, cases, distributions, methods, shards, timing) and each method's false-intersect
/// distances in full ("fi_distances").
nlohmann::json to_json(const VerifyResult& r);

/// What identifies a run (the "run" of a shard's JSON): two shards merge only when theirs are
/// equal.
nlohmann::json run_identity(const VerifyResult& r);

/// A result read back from to_json's JSON (a shard's, with its distances in full; another run's
/// lacks them, and its distance medians are then unknown). Throws std::invalid_argument naming
/// `where` and the field that is missing or wrong.
VerifyResult from_json(const nlohmann::json& j, const std::string& where);

/// One shard's result for merge_shards: the file it came from, its JSON.
struct ShardFile {
  std::string file;
  nlohmann::json json;
};

/// The shards of one run merged (`cullproof merge`): counts summed exactly, each method's first
/// violation and fault the earliest (a method is not counted past its fault: the shards after it
/// are left out of its counts, as one run would not have asked it), the false-intersect distances
/// pooled, the costs the median of the shards' (each the fastest of its passes, on the same
/// timing frames), the wall time the sum. Throws std::invalid_argument naming the file: one not a
/// shard's result, of another run (and the field that differs), a shard given twice, a shard
/// interrupted, or missing shards (unless `partial`: then `missing` lists them).
struct MergedRun {
  VerifyResult result;
  std::vector<std::uint64_t> missing;  ///< shard indices absent (partial only)
  std::uint64_t shards = 0;            ///< of the run
  double longest_shard_seconds = 0.0;
};
MergedRun merge_shards(const std::vector<ShardFile>& shards, bool partial);
/// Writes the merged run's corpus into `dir`: each method's chosen records (corpus_candidates), in
/// the order one run writes them, each file written atomically and only where its name is free
/// (a name taken by the same case found twice, by this run or an earlier one, keeps its file, as
/// one run keeps it), and sets each method's corpus_written and violation_ids as one run sets them.
/// Into a folder holding no record of this run, the files one run writes, byte for byte. Throws
/// std::runtime_error naming the file, before anything is written, where a name holds another case
/// (its frustum or volume differ) or a file that is not a readable record; and naming a file that
/// cannot be written.
void write_merged_corpus(VerifyResult& merged, const std::filesystem::path& dir);

/// The false-intersect distances (relative to the scene size) counted per decade:
/// {"first_decade": k0, "counts": [...], "below": n, "above": n}, where counts[i] holds the
/// distances in [10^(k0+i), 10^(k0+i+1)), "below" those under 10^k0 and "above" those of
/// 10^kFiHistogramLastDecade or more. Counts of several runs or distributions add up.
nlohmann::json fi_distance_histogram(const std::vector<double>& distances);
inline constexpr int kFiHistogramFirstDecade = -16;  ///< rounding of double at the scene's scale
inline constexpr int kFiHistogramLastDecade = 2;     ///< a hundred scene sizes away


}  // namespace cullproof

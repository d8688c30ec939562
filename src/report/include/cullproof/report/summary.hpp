// What a verification run found, in a few lines: which claims broke (for which methods, on which
// families, with the corpus cases that show it) and which method is cheapest for each level of
// accuracy. Read from the run's JSON (`cullproof verify --json`, cullproof::to_json), so that
// the lines at the end of `cullproof verify` and the top of `cullproof report` are one thing.
//
// Definitions:
//  - overall false-intersect rate of a method: its false intersects over its truly outside
//    volumes, summed over the families of the run, with a 95% Wilson interval;
//  - overall cost: the median over the run's families of its ns/test (classify per volume with the
//    per-frame set-up hoisted out, as `cullproof verify` times it); families where it was not
//    timed take no part;
//  - cheapest for each level of accuracy: among the methods that make a claim and whose claim
//    held (see on_front), taking the same volume kinds (so that their rates are over the same
//    cases), the Pareto front of cost against false-intersect rate: each method on it is the
//    cheapest whose rate is at most its own.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace cullproof::report {

/// A verify result that lacks a field or holds one of the wrong type; what() names the field
/// by its JSON path (e.g. "distributions[2].methods[5].false_intersect").
class ResultError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One method over every family of the run.
struct MethodOverall {
  std::string method, claim, origin;
  std::vector<std::string> volumes;  ///< kinds it takes ("point", "sphere", "aabb", "obb")
  bool three_way = true;
  bool refuted = false;
  bool faulted = false;  ///< it faulted in some family (its counts there stop at the fault)
  std::uint64_t cases = 0, truth_outside = 0;
  std::uint64_t false_reject = 0, false_inside = 0, false_intersect = 0, under_inside = 0;
  std::uint64_t claim_violations = 0;
  double fi_rate = 0.0, fi_low = 0.0, fi_high = 0.0;  ///< false-intersect rate and its 95% interval
  std::optional<double> ns_per_test;                  ///< median over families (unset: never timed)
  std::optional<double> ns_per_test_own;              ///< the same of what a program reported itself
};

/// Where one method's claim broke in one family.
struct FamilyBreak {
  std::string family;
  std::uint64_t violations = 0, float_exact_violations = 0;
  std::optional<std::uint64_t> first_violation;  ///< case index, for --index
  std::vector<std::string> corpus_ids;           ///< corpus cases recording the violation
  std::string reproduce;                         ///< the command that reruns the first violation
};

/// A method's fault in one family.
struct FaultLine {
  std::string method, family, problem;
  std::optional<std::uint64_t> index;  ///< unset: while it was timed
  std::string reproduce;               ///< empty: while it was timed
};

struct BrokenClaim {
  std::string method, claim, origin;
  std::uint64_t violations = 0;
  std::vector<FamilyBreak> families;
};

/// One step of a Pareto front: the cheapest method with false-intersect rate at most `fi_rate`.
struct FrontStep {
  std::string method, claim;
  double ns_per_test = 0.0;
  double fi_rate = 0.0, fi_low = 0.0, fi_high = 0.0;
};

/// The methods that take exactly these volume kinds, and their front (cost increasing, rate
/// strictly decreasing).
struct VolumeGroup {
  std::vector<std::string> volumes;
  std::vector<FrontStep> front;
  std::size_t methods = 0;  ///< methods in the group whose claim held and that were timed
};

struct Summary {
  std::uint64_t seed = 0, cases_per_distribution = 0;
  std::vector<std::string> families;   ///< in the run's order
  std::vector<MethodOverall> methods;  ///< in the run's order
  std::vector<BrokenClaim> broken;     ///< refuted claims, in the run's order
  std::vector<VolumeGroup> cheapest;   ///< by volume kinds, in a fixed order (point first)
  std::vector<FaultLine> faults;       ///< in the run's order
  bool failed = false;                 ///< the run failed (VerifyResult::failed)
  bool interrupted = false;            ///< the run was stopped before it was done
  /// A claim of one of cullproof's own methods or of a user's method was refuted.
  bool own_claim_broken() const noexcept;
};

/// A point for pareto_front.
struct CostPoint {
  double ns_per_test = 0.0;
  double fi_rate = 0.0;
};
/// Indices of the Pareto front of `points` (lower cost and lower rate are better), by cost
/// increasing: a point is on it when no other is at most as costly and at most as wasteful and
/// better in one. Of equal points the first is kept.
std::vector<std::size_t> pareto_front(const std::vector<CostPoint>& points);

/// Whether a method takes part in the Pareto front: it makes a claim (not "none": a method that
/// promises nothing may cull what is visible), the claim held, it was timed and it met truly
/// outside volumes.
bool on_front(const MethodOverall& m);

/// Median of the finite values (unset when there are none); the mean of the middle two for an even count.
std::optional<double> median(std::vector<double> values);

/// Reads the run's JSON (see cullproof::to_json(const VerifyResult&)). Throws ResultError for a
/// missing or mistyped field.
Summary summarize(const nlohmann::json& verify);

/// The summary as the last lines of `cullproof verify`.
void print_summary(const Summary& s, std::ostream& out);

/// Required field `key` of object `j` at JSON path `where`; throws ResultError naming the path.
const nlohmann::json& field(const nlohmann::json& j, const char* key, const std::string& where);
/// The same for a count (a non-negative integer), a string, and a number or null (not measured).
std::uint64_t count_field(const nlohmann::json& j, const char* key, const std::string& where);
std::string text_field(const nlohmann::json& j, const char* key, const std::string& where);
std::optional<double> measure_field(const nlohmann::json& j, const char* key, const std::string& where);

}  // namespace cullproof::report

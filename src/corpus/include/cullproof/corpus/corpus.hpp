// The mismatch corpus (corpus/): one case per file, corpus/<method>/<distribution>/<class>-<hash>.json,
// in the case format of docs/semantics.md plus the mismatch record (method, verdict, class, truth,
// witness, distance, seed, reproduce command, every method's verdict on the case).
#pragma once

#include "cullproof/gen/generators.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/judge/judge.hpp"
#include "cullproof/methods/methods.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof {

/// One corpus file and the mismatch it records.
struct CorpusEntry {
  std::filesystem::path file;
  Case c;
  std::string method;        ///< the method whose error this case records
  Visibility verdict{};      ///< its recorded verdict
  ErrorClass error{};        ///< recorded class
  std::string distribution;  ///< where the campaign found it
  /// For a stateful method's error on a camera path: the path it needs (field "path"); the
  /// case's frustum and volume are its last frame and its object. Stateful methods are replayed
  /// over it, the others on the case alone.
  std::optional<PathCase> path;
};

/// 12 hex digits identifying the geometry (FNV-1a of the canonical frustum and volume text).
std::string geometry_hash(const CaseFrustum& f, const Volume& v);
/// The mismatch case files under `dir` (every *.json, sorted by path), leaving out the scene
/// directories corpus/scenes/ and corpus/scenes-*/ and the fault records under corpus/faults/.
/// The temporary file a writer killed mid-write may leave (".<name>.tmp-<pid>-<n>", see
/// write_file_atomic) does not end in ".json" and is not listed.
std::vector<std::filesystem::path> corpus_case_files(const std::filesystem::path& dir);
/// Reads every case file under `dir` (corpus_case_files). Throws CaseError for a malformed file and
/// std::runtime_error for a file that lacks the mismatch record (naming the file and field).
std::vector<CorpusEntry> load_corpus(const std::filesystem::path& dir);
/// The mismatch record of a case read from `file`: its truth, method, verdict, class and
/// distribution, and its camera path if it has one. Throws std::runtime_error naming the file and
/// the field that is missing or wrong.
CorpusEntry corpus_entry(Case c, const std::filesystem::path& file);
/// A corpus file's text as load_corpus reads it (parse_case, then corpus_entry). Throws CaseError
/// or std::runtime_error naming `file`.
CorpusEntry parse_corpus_entry(std::string_view text, const std::filesystem::path& file);

/// Outcome of replaying one corpus entry.
struct ReplayResult {
  const CorpusEntry* entry = nullptr;
  Visibility truth_now{};
  bool truth_changed = false;            ///< the oracle disagrees with the recorded truth
  std::optional<Visibility> verdict_now; ///< the method's verdict now (nullopt: method gone)
  bool reproduces = false;               ///< the recorded verdict is given again
  bool fixed = false;                    ///< the method now agrees with the truth
  std::vector<std::string> regressed;    ///< methods that were correct in the record and now are not
  std::vector<std::string> changed;      ///< methods whose verdict differs from the record
};
/// Re-runs the oracle and every recorded built-in method on the entry.
ReplayResult replay(const CorpusEntry& e);
/// The same with `methods` (a user's corpus records the user's methods).
ReplayResult replay(const CorpusEntry& e, const std::vector<Method>& methods);

/// One record whose "verdicts" entry for a method was taken again.
struct Rerecorded {
  std::filesystem::path file;
  std::string before, after;  ///< the recorded verdict and the one now ("" when it does not apply)
};
/// After a deliberate change to method `m`: takes its verdict again in the "verdicts" of every
/// record under `dir` that lists it, and rewrites (atomically) the records where it changed.
/// Records of m's own errors are left alone: evidence that no longer reproduces is moved out of the
/// corpus by hand. Returns the records rewritten.
std::vector<Rerecorded> rerecord_verdicts(const std::filesystem::path& dir, const Method& m);

/// One record judged again by the judge as it is now.
struct Rejudged {
  std::filesystem::path file;
  std::string id;
  bool violated_before = false, violates_now = false;  ///< its "violates_claim", recorded and now
  double distance = 0.0;    ///< error_distance now
  double allowance = 0.0;   ///< the distance within which the claim forgives it (0: none)
};
/// After a change to the judge (error_distance, violates_claim): judges every record under `dir`
/// of a method among `methods` again, with its claim and tolerance, and rewrites (atomically) each
/// record whose judgement fields ("violates_claim", "float_exact", "verdict_distance", its kind,
/// "tolerance", "allowance") differ from what the judge says now. Records whose truth changed are left to
/// `replay`. Returns the records rewritten.
std::vector<Rejudged> rejudge(const std::filesystem::path& dir, const std::vector<Method>& methods);

// ---- Writing the records (corpus_write.cpp), as the campaign finds errors

namespace detail {

/// The command (or, for a user's method, the test environment) that reruns one case.
std::string reproduce_command(std::uint64_t seed, gen::Distribution d, std::uint64_t index, const Method& m);

/// What write_corpus_case recorded: the case's id, whether this run wrote it (false: the same
/// geometry was recorded already, by an earlier run or meanwhile by another thread), and whether
/// the record breaks the method's claim (its "violates_claim"); its file under the corpus folder
/// (<method>/<distribution>/<class>-<hash>.json) and the text this case's record has there (what
/// was written, or would have been had the name been free; a held record's text as read).
struct CorpusRecord {
  std::string id;
  bool written = false;
  bool violates = false;
  std::string file;
  std::string text;
};

/// The judgement fields of a record of method m's error: "float_exact", "verdict_distance" (error_distance; null
/// when no shift helps), "verdict_distance_kind" (oracle::to_string(VerdictShift)), "tolerance"
/// and "allowance" (the distance within which the claim forgives the error: tolerance x scale, 0
/// on a float-exact case where the claim allows only rounding; null for a claim without one).
/// Removes the older "backward_distance".
void set_judgement(nlohmann::json& record, const oracle::VerdictDistance& vd, const Method& m, double scale, bool float_exact);

/// Writes one corpus case unless the same geometry is already recorded.
/// `path`: the camera path a stateful method's error needs to reproduce, recorded with the case
/// (the other stateful methods' verdicts are taken over it too).
CorpusRecord write_corpus_case(const std::filesystem::path& dir, const gen::GenCase& g, const Method& m, Visibility verdict,
                               gen::Distribution d, std::uint64_t seed, std::uint64_t index,
                               const std::vector<Method>& all, const PathCase* path = nullptr);

/// The records of one method's errors on one distribution (dir/<method>/<distribution>/), found by
/// the case each was shrunk from: its "seed", "index" and "class". The campaign asks it before
/// shrinking an error, so that an error the corpus records already is not shrunk again on every
/// run. A file that cannot be read as a record is no source of any error here (the campaign then
/// shrinks and writes as if it were absent; `cullproof corpus` reports such a file).
class CorpusSources {
 public:
  CorpusSources(const std::filesystem::path& dir, const std::string& method, gen::Distribution d);
  /// The record of m's error of class `cls` on case `index` drawn from `seed`, if one is held
  /// whose truth the oracle still gives and on whose case (or camera path) m still gives the
  /// recorded verdict; its id, written = false and, with `judge`, whether it breaks m's claim as
  /// judged now (without, `violates` is false: the distance is not measured).
  std::optional<CorpusRecord> held(const Method& m, std::uint64_t seed, std::uint64_t index, ErrorClass cls,
                                   bool judge = true) const;
  /// How many records were read.
  std::size_t size() const noexcept { return entries_.size(); }

 private:
  std::vector<CorpusEntry> entries_;
};

}  // namespace detail

}  // namespace cullproof

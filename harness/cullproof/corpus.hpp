// The mismatch corpus (corpus/): one case per file, corpus/<method>/<distribution>/<class>-<hash>.json,
// in the case format of docs/semantics.md plus the mismatch record (method, verdict, class, truth,
// witness, distance, seed, reproduce command, every method's verdict on the case).
#pragma once

#include "cullproof/campaign.hpp"
#include "cullproof/case_io.hpp"

#include <filesystem>
#include <optional>
#include <string>
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
/// directories corpus/scenes/ and corpus/scenes-*/.
std::vector<std::filesystem::path> corpus_case_files(const std::filesystem::path& dir);
/// Reads every case file under `dir` (corpus_case_files). Throws CaseError for a malformed file and
/// std::runtime_error for a file that lacks the mismatch record (naming the file and field).
std::vector<CorpusEntry> load_corpus(const std::filesystem::path& dir);

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

}  // namespace cullproof

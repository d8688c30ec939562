// Case files (docs/semantics.md "Case files"): one JSON object per case; the corpus stores
// one case per file, batches are JSON Lines. Numbers are JSON numbers or C99 hex-float strings,
// each rounded once, to the nearest float, from its text (never through double). Writers emit
// the shortest decimal that reads back to the same float. Malformed input is rejected with a
// CaseError naming the file, the line and the field; so is input past the readers' limits below.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof {

// ---- Limits -----------------------------------------------------------------------------------
// A case file may come from anywhere. Every reader here refuses input past these limits with a
// CaseError naming the file, the line and the limit, before the input costs more than a small
// multiple of the limit in memory or time (nothing is truncated or skipped). They are far above
// what real cases need.

/// Arrays and objects nested in one case. A case nests 5 deep (volume.obb.axes[i]), a corpus
/// record with its camera path 6; the limit leaves the free fields room. Refused as soon as the
/// parser opens the first array or object past it.
inline constexpr int kMaxCaseDepth = 64;
/// Bytes of one case: a line of a JSON Lines file, or the whole of a one-case file (so no line of
/// a case file is longer). The largest committed corpus case is under 3 KB.
inline constexpr std::size_t kMaxCaseBytes = std::size_t(1) << 20;  // 1 MiB
/// Bytes of a JSON Lines file: about a million cases of the usual 300 bytes. A regular file is
/// refused by its size before it is read; a pipe when its input passes the limit.
inline constexpr std::uintmax_t kMaxCaseFileBytes = std::uintmax_t(256) << 20;  // 256 MiB

/// One case. Fields the reader does not know are kept, untouched, in `extra`.
struct Case {
  std::string id;
  CaseFrustum frustum;
  Volume volume;
  std::optional<Visibility> truth;
  std::string note;
  nlohmann::json extra = nlohmann::json::object();  ///< verdicts, witness, distance, seed, ...
  /// The line the case starts on in the text it was read from (1 for a one-case file; 0 for a case
  /// that was not read), for messages about the case after reading. Not written by format_case.
  int line = 0;
};

/// Error in a case file: where (file, 1-based line; 0 when it is about the file as a whole, as its
/// size) and which field (e.g. "volume.obb.half[1]").
class CaseError : public std::runtime_error {
 public:
  CaseError(std::string file, int line, std::string field, const std::string& problem);
  const std::string& file() const noexcept { return file_; }
  int line() const noexcept { return line_; }
  const std::string& field() const noexcept { return field_; }

 private:
  std::string file_;
  int line_;
  std::string field_;
};

/// Parses one case from JSON text. `source` names the file in errors; `first_line` is the line
/// the text starts on (for JSON Lines). Throws CaseError, also for text longer than kMaxCaseBytes
/// or nested deeper than kMaxCaseDepth.
Case parse_case(std::string_view text, std::string_view source = "<input>", int first_line = 1);
/// Reads a file holding one case (any layout), of at most kMaxCaseBytes. Throws CaseError (or
/// std::system_error when the file cannot be read).
Case read_case_file(const std::filesystem::path& file);
/// Parses JSON Lines text: one case per non-blank line, each of at most kMaxCaseBytes, the whole of
/// at most kMaxCaseFileBytes. `source` names the file in errors. Throws CaseError at the first bad
/// line (no case of the text is returned then).
std::vector<Case> parse_cases_jsonl(std::string_view text, std::string_view source = "<input>");
/// Reads JSON Lines (parse_cases_jsonl) from a file of at most kMaxCaseFileBytes. Throws
/// CaseError at the first bad line (or std::system_error when the file cannot be read).
std::vector<Case> read_cases_jsonl(const std::filesystem::path& file);
/// ".jsonl" files as JSON Lines, anything else as one case.
std::vector<Case> read_cases(const std::filesystem::path& file);

/// Parses a number as the case format allows: JSON number text or a C99 hex-float string
/// ("0x1.8p+3", optional sign), rounded to the nearest float. Rejects NaN, infinity and values
/// that overflow float. Throws std::invalid_argument describing the problem.
float parse_case_float(std::string_view text, bool is_string);
/// Shortest decimal text that reads back to exactly `x` (std::to_chars); -0 keeps its sign.
std::string format_float(float x);
/// C99 hex-float text of `x` (exact, for counterexample printing), e.g. "0x1.8p+3".
std::string format_hex_float(float x);

/// Serialises a case. `pretty` gives the multi-line corpus layout; otherwise one line (JSONL).
std::string format_case(const Case& c, bool pretty = false);
/// Writes one case to `file` atomically (write_file_atomic).
void write_case_file(const std::filesystem::path& file, const Case& c, bool overwrite = true);

/// The volume as the case-format JSON object ({"aabb": ...} etc.), numbers as shortest decimals.
std::string format_volume(const Volume& v);
/// The frustum as the case-format JSON object.
std::string format_frustum(const CaseFrustum& f);

}  // namespace cullproof

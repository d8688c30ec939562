// Case files (shared/CONVENTIONS.md "Case format"): one JSON object per case; the corpus stores
// one case per file, batches are JSON Lines. Numbers are JSON numbers or C99 hex-float strings,
// each rounded once, to the nearest float, from its text (never through double). Writers emit
// the shortest decimal that reads back to the same float. Malformed input is rejected with a
// CaseError naming the file, the line and the field.
#pragma once

#include "cullproof/frustum_build.hpp"
#include "cullproof/geometry.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cullproof {

/// One case. Fields the reader does not know are kept, untouched, in `extra`.
struct Case {
  std::string id;
  CaseFrustum frustum;
  Volume volume;
  std::optional<Visibility> truth;
  std::string note;
  nlohmann::json extra = nlohmann::json::object();  ///< verdicts, witness, distance, seed, ...
};

/// Error in a case file: where (file, 1-based line) and which field (e.g. "volume.obb.half[1]").
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
/// the text starts on (for JSON Lines). Throws CaseError.
Case parse_case(std::string_view text, std::string_view source = "<input>", int first_line = 1);
/// Reads a file holding one case (any layout). Throws CaseError (or std::runtime_error when the
/// file cannot be read).
Case read_case_file(const std::filesystem::path& file);
/// Reads JSON Lines: one case per non-blank line. Throws CaseError at the first bad line.
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
/// Writes one case to `file` atomically: a temporary file in the same directory, flushed and
/// renamed over the target, so a reader (or a crash) never sees a partial file. With
/// `overwrite == false`, an existing file is left untouched and std::runtime_error is thrown.
void write_case_file(const std::filesystem::path& file, const Case& c, bool overwrite = true);
/// Writes arbitrary text atomically (same guarantees as write_case_file).
void write_file_atomic(const std::filesystem::path& file, std::string_view text, bool overwrite = true);

/// The volume as the case-format JSON object ({"aabb": ...} etc.), numbers as shortest decimals.
std::string format_volume(const Volume& v);
/// The frustum as the case-format JSON object.
std::string format_frustum(const CaseFrustum& f);

}  // namespace cullproof

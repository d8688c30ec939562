// Bounded reading, for every reader of JSON from outside (case files, scene files, the process
// protocol's messages, a run's result): each reader names its own limits and turns
// InputLimitError into its own error.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

namespace cullproof {

/// Input past a limit of its reader. what() says which limit was passed and by how much; line()
/// is where: 1-based, or 0 when it is about the input as a whole (a file's size).
class InputLimitError : public std::runtime_error {
 public:
  InputLimitError(int line, const std::string& problem) : std::runtime_error(problem), line_(line) {}
  int line() const noexcept { return line_; }

 private:
  int line_;
};

/// `text` as an error message may quote it: control characters (a NUL would end the message
/// where it stands) written as JSON escapes ("\n", "\u0000"), everything else as it is.
std::string printable_text(std::string_view text);
/// "1048576 bytes (1 MiB)": a byte count as the limits' messages give it.
std::string byte_count_text(std::uintmax_t n);
/// The whole of `file`, at most `max_bytes` of it. A regular file larger than that is refused by
/// its size before anything is read (line 0); any other file (a pipe) when its input passes the
/// limit (the line where it does). `what` names the kind of file in the message ("a scene file").
/// Throws InputLimitError, or std::system_error when the file cannot be opened or read.
std::string read_file_limited(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what);
/// Throws InputLimitError for the first line of `text` longer than `max_bytes` (without its '\n');
/// `what` names what the line belongs to ("a scene file").
void check_line_lengths(std::string_view text, std::size_t max_bytes, std::string_view what);
/// Parses JSON text into a document, refusing nesting of arrays and objects deeper than
/// `max_depth` as soon as the parser opens the first container past it (nlohmann's parser
/// callback), before the document grows. Throws InputLimitError (with the line) for that and for
/// a number past the range of a double ("1e999"), and nlohmann::json::parse_error for text that is
/// not JSON.
nlohmann::json parse_json_limited(std::string_view text, int max_depth, std::string_view what);

}  // namespace cullproof

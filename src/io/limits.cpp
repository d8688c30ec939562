// Bounded reading of JSON from outside (cullproof/io/limits.hpp).
#include "cullproof/io/limits.hpp"

#include "line_counting.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <string>
#include <system_error>

namespace cullproof {

using nlohmann::json;
using io_detail::CountingIterator;
using io_detail::LineState;

std::string printable_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto u = static_cast<unsigned char>(ch);
    if (u >= 0x20 && u != 0x7f) {
      out += ch;
      continue;
    }
    switch (ch) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default: {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", u);
        out += buf;
      }
    }
  }
  return out;
}

// The message quotes the field and the problem through printable_text: both may hold text of the
// input (a key, a string value), and a NUL in it would cut the message short.

std::string byte_count_text(std::uintmax_t n) {
  std::string s = std::to_string(n) + " bytes";
  if (n >= (1u << 20) && n % (1u << 20) == 0) return s + " (" + std::to_string(n >> 20) + " MiB)";
  if (n >= (1u << 10) && n % (1u << 10) == 0) return s + " (" + std::to_string(n >> 10) + " KiB)";
  return s;
}

std::string read_file_limited(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw std::system_error(errno, std::generic_category(), file.string() + ": cannot open for reading");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st{};
  if (::fstat(fd, &st) != 0) throw std::system_error(errno, std::generic_category(), file.string() + ": read error");
  const bool regular = S_ISREG(st.st_mode);
  if (regular && std::uintmax_t(st.st_size) > max_bytes)
    throw InputLimitError(0, "a file of " + std::to_string(st.st_size) + " bytes, over the limit of " +
                                 byte_count_text(max_bytes) + " for " + std::string(what));
  std::string text;
  if (regular) text.reserve(std::size_t(st.st_size));
  char buf[1 << 16];
  for (;;) {
    // At most one byte past the limit: enough to tell that the input goes on.
    const std::size_t want = std::size_t(std::min<std::uintmax_t>(sizeof buf, max_bytes + 1 - text.size()));
    const ssize_t n = ::read(fd, buf, want);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::system_error(errno, std::generic_category(), file.string() + ": read error");
    }
    if (n == 0) return text;
    text.append(buf, std::size_t(n));
    if (text.size() > max_bytes) {
      const int line = 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(max_bytes), '\n'));
      throw InputLimitError(line, "the input goes on past the limit of " + byte_count_text(max_bytes) + " for " +
                                      std::string(what) + " (passed on this line)");
    }
  }
}

void check_line_lengths(std::string_view text, std::size_t max_bytes, std::string_view what) {
  int line = 1;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    if (end - pos > max_bytes)
      throw InputLimitError(line, "a line of " + std::to_string(end - pos) + " bytes, over the limit of " +
                                      byte_count_text(max_bytes) + " for a line of " + std::string(what));
    pos = end + 1;
    ++line;
  }
}

json parse_json_limited(std::string_view text, int max_depth, std::string_view what) {
  LineState st;
  CountingIterator b{text.data(), &st}, e{text.data() + text.size(), &st};
  // `depth` is the number of containers already open when one starts.
  const json::parser_callback_t within = [&](int depth, json::parse_event_t event, json&) {
    if ((event == json::parse_event_t::object_start || event == json::parse_event_t::array_start) && depth >= max_depth)
      throw InputLimitError(st.token_line, "arrays and objects nested deeper than " + std::to_string(max_depth) +
                                               ", the limit for " + std::string(what));
    return true;
  };
  try {
    return json::parse(b, e, within);
  } catch (const json::out_of_range& ex) {
    // The one error of nlohmann's parser that is not a parse_error: a number past the range of a
    // double ("1e999"), which it cannot hold. Reported like a limit, at the number's line.
    std::string msg = ex.what();
    const auto pos = msg.find("] ");
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    throw InputLimitError(st.token_line, "a number beyond the range of a double (" + msg + ")");
  }
}

}  // namespace cullproof

// Range checks for the numeric options of cullproof's command line (the subcommands,
// commands.hpp). The program's own: it needs CLI11, which the libraries do not.
//
// CLI11 (2.1) reads "-5" into an unsigned option as 2^64 - 5 and a number past 2^64 - 1 as
// 2^64 - 1, without a word, and CLI::Range of an unsigned type compares what it read. Unsigned
// options take UnsignedRange instead, which reads decimal digits only; signed ones take CLI::Range.
#pragma once

#include <CLI/CLI.hpp>

#include <charconv>
#include <cstdint>
#include <string>
#include <system_error>

namespace cullproof::cli {

/// A whole number in [lo, hi], written in decimal digits (no sign): the same message as
/// CLI::Range ("Value -5 not in range 1 to 10000000").
class UnsignedRange : public CLI::Validator {
 public:
  UnsignedRange(std::uint64_t lo, std::uint64_t hi) {
    description("UINT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
    func_ = [lo, hi](std::string& input) {
      std::uint64_t v = 0;
      const char* end = input.data() + input.size();
      const auto r = std::from_chars(input.data(), end, v);
      if (input.empty() || r.ec != std::errc() || r.ptr != end || v < lo || v > hi)
        return "Value " + input + " not in range " + std::to_string(lo) + " to " + std::to_string(hi);
      return std::string();
    };
  }
};

}  // namespace cullproof::cli

// Numbers and lists as every part of the report writes them (the summary, the charts, the page),
// so that the same figure reads the same everywhere.
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>
#include <vector>

namespace cullproof::report::show {

/// A fraction as a percentage: "0%" for zero, three significant digits, scientific below 1e-6.
inline std::string percent(double fraction) {
  if (fraction == 0.0) return "0%";
  if (fraction < 1e-6) return fmt::format("{:.2e}%", fraction * 100);
  return fmt::format("{:.3g}%", fraction * 100);
}

/// Nanoseconds with the digits that matter: two decimals below 10, one below 100, none above.
inline std::string nanoseconds(double x) {
  return x < 10 ? fmt::format("{:.2f}", x) : x < 100 ? fmt::format("{:.1f}", x) : fmt::format("{:.0f}", x);
}

inline std::string join(const std::vector<std::string>& v, const char* sep) { return fmt::format("{}", fmt::join(v, sep)); }

}  // namespace cullproof::report::show

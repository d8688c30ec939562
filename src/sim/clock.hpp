// The simulator's clock (not installed): the steady clock in nanoseconds, as a double.
#pragma once

#include <chrono>

namespace cullproof::sim {

/// The steady clock's time in nanoseconds (for differences only).
inline double now_ns() {
  return static_cast<double>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch()).count());
}

}  // namespace cullproof::sim

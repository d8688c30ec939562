// Portable random numbers: splitmix64 (S. Vigna, "Further scramblings of Marsaglia's xorshift
// generators", 2014; the seeding generator of xoshiro) is fixed and portable, where the standard
// library's distributions differ between implementations: the same seed gives the same scenes,
// worlds, camera paths and samples everywhere.
#pragma once

#include <cstdint>

namespace cullproof {

/// One step of splitmix64 on `x`: a bijective mix of 64 bits, the stream's output for state x.
constexpr std::uint64_t splitmix64(std::uint64_t x) noexcept {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() noexcept {
    const std::uint64_t z = splitmix64(state);
    state += 0x9E3779B97F4A7C15ull;
    return z;
  }
  /// Uniform in [0, 1), 53 random bits.
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1p-53; }
  /// Uniform in [lo, hi].
  int range(int lo, int hi) noexcept { return lo + static_cast<int>(uniform() * (hi - lo + 1)); }
};

}  // namespace cullproof

// Internal to sim/: the simulator's random numbers. splitmix64 (S. Vigna, "Further scramblings of
// Marsaglia's xorshift generators", 2014; the seeding generator of xoshiro) is fixed and portable,
// where the standard library's distributions differ between implementations: the same scene and
// seed give the same world, camera path and samples everywhere.
#pragma once

#include <cstdint>

namespace cullproof::sim {

struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1), 53 random bits.
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1p-53; }
  /// Uniform in [lo, hi].
  int range(int lo, int hi) noexcept { return lo + static_cast<int>(uniform() * (hi - lo + 1)); }
};

}  // namespace cullproof::sim

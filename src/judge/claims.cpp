// What a claim forbids and how far an error lies from being right: error classes, the claim rule,
// the distance it is judged on (see cullproof/judge/judge.hpp), and the Wilson interval of a rate.
#include "cullproof/judge/judge.hpp"

#include "cullproof/oracle/oracle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace cullproof {

ErrorClass error_class(Visibility verdict, Visibility truth, bool three_way) noexcept {
  if (verdict == truth) return ErrorClass::correct;
  if (!three_way && verdict == Visibility::intersecting && truth == Visibility::inside) return ErrorClass::correct;
  if (verdict == Visibility::outside) return ErrorClass::false_reject;
  if (verdict == Visibility::inside) return ErrorClass::false_inside;
  return truth == Visibility::outside ? ErrorClass::false_intersect : ErrorClass::under_inside;
}

bool violates_claim(Claim claim, ErrorClass e, double distance, double tolerance, double scale, bool float_exact) noexcept {
  if (e == ErrorClass::correct) return false;
  const bool hard = e == ErrorClass::false_reject || e == ErrorClass::false_inside;
  // A certified band, or the rounding allowance; a zero tolerance forgives nothing, not even an
  // error at distance 0 (a volume touching the boundary).
  const bool within = tolerance > 0.0 && distance <= tolerance * scale;
  const bool allowed = within && !float_exact;         // the rounding allowance: only where things round
  switch (claim) {
    case Claim::certified_conservative: return hard;
    case Claim::certified_exact: return hard || !within;
    case Claim::conservative: return hard && !allowed;
    case Claim::exact: return !allowed;
    case Claim::none: return false;
  }
  return false;
}

double error_distance(const CaseFrustum& f, const Volume& v, Visibility verdict) {
  return oracle::distance_to_verdict(f, v, verdict).distance;
}

bool needs_distance(Claim claim, ErrorClass e, bool float_exact) noexcept {
  if (e == ErrorClass::correct) return false;
  const bool hard = e == ErrorClass::false_reject || e == ErrorClass::false_inside;
  switch (claim) {
    case Claim::certified_exact: return !hard;  // the proven band, float-exact or not
    case Claim::exact: return !float_exact;
    case Claim::conservative: return hard && !float_exact;
    default: return false;
  }
}


std::pair<double, double> wilson95(std::uint64_t k, std::uint64_t n) noexcept {
  if (n == 0) return {0.0, 0.0};
  const double z = 1.959963984540054, p = double(k) / double(n), nn = double(n);
  const double denom = 1 + z * z / nn, centre = (p + z * z / (2 * nn)) / denom;
  const double half = z * std::sqrt(p * (1 - p) / nn + z * z / (4 * nn * nn)) / denom;
  // With no success (no failure) the bound is exactly 0 (1); centre - half would leave a rounding
  // residue such as 1e-19 there.
  return {k == 0 ? 0.0 : std::max(0.0, centre - half), k == n ? 1.0 : std::min(1.0, centre + half)};
}

std::string percent_ci95(std::uint64_t k, std::uint64_t n) {
  if (n == 0) return "-";
  const auto [lo, hi] = wilson95(k, n);
  return fmt::format("{:.2f} [{:.2f}, {:.2f}]", 100.0 * double(k) / double(n), 100.0 * lo, 100.0 * hi);
}

}  // namespace cullproof

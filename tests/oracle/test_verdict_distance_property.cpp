// The judge's distance (oracle::distance_to_verdict) against the oracle's truth, on generated
// cases: move every plane of the frustum by a little less than the distance (in the direction
// that helps the verdict) and the verdict is still wrong; by a little more and it is the truth.
// That is the definition of the distance, checked with the exact truth of the moved frustum, for
// every wrong verdict of every case. Plane cases only (a moved matrix frustum is not a matrix),
// and only where moving a plane in float rounds far less than the margin tested.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <variant>
#include <string>

namespace cullproof::oracle::test {
namespace {

constexpr double kMargin = 1e-3;  // relative: the bound is tighter than this by far

// F with every plane moved out (sign +1) or in (-1) by `shift` in distance units, or nothing when
// moving it in float would round by more than a thousandth of the margin.
std::optional<CaseFrustum> moved(const CaseFrustum& f, double shift, int sign) {
  Frustum out = f.planes;
  for (int k = 0; k < kPlaneCount; ++k) {
    Plane& p = out[k];
    const double len = glm::length(glm::dvec3(p.n));
    if (len == 0.0) continue;
    const double d = double(p.d) + sign * shift * len;
    const float df = float(d);
    if (!std::isfinite(df)) return std::nullopt;
    const double want = shift * len;
    if (std::abs((d - double(p.d)) - sign * want) > 1e-3 * kMargin * want) return std::nullopt;  // lost in double
    if (std::abs(double(df) - d) > 1e-3 * kMargin * want) return std::nullopt;                    // lost in float
    p.d = df;
  }
  return frustum_spec(out);
}

// Whether `verdict` is right for v against g: inside and outside exactly; intersecting where the
// volume is neither inside nor outside any more.
bool right(const CaseFrustum& g, const Volume& v, Visibility verdict, VerdictShift shift) {
  const Visibility t = truth(g, v);
  if (shift == VerdictShift::to_meeting) return t != Visibility::outside;
  if (shift == VerdictShift::to_leaving) return t != Visibility::inside;
  return t == verdict;
}

// A ball's depth is searched in double at the ball's own magnitude (oracle.hpp: a certified lower
// bound, not within 2^-50 as a box's is): for a ball far larger than the frustum the values meet
// the frustum as differences of numbers near |c| + r, and the search keeps what double keeps of
// those (units in the 50th bit or so of |c| + r). Tightness is asserted only where that is far
// below the margin tested; the lower bound always.
bool tight_enough(const Volume& v, double distance) {
  const auto* s = std::get_if<Sphere>(&v);
  if (!s) return true;
  const double magnitude = std::max({std::abs(double(s->center.x)), std::abs(double(s->center.y)),
                                     std::abs(double(s->center.z))}) + double(s->radius);
  return magnitude * 0x1p-45 < kMargin * distance;
}

void check(const gen::GenCase& c) {
  if (c.frustum.matrix) return;
  for (Visibility verdict : {Visibility::outside, Visibility::intersecting, Visibility::inside}) {
    const VerdictDistance d = distance_to_verdict(c.frustum, c.volume, verdict);
    if (d.shift == VerdictShift::none || !std::isfinite(d.distance) || !(d.distance > 0.0)) continue;
    // Outward for inside and for meeting from outside; inward for outside and for leaving.
    const int sign = d.shift == VerdictShift::to_inside || d.shift == VerdictShift::to_meeting ? +1 : -1;
    const auto less = moved(c.frustum, d.distance * (1 - kMargin), sign);
    const auto more = moved(c.frustum, d.distance * (1 + kMargin), sign);
    if (!less || !more) continue;
    RC_TAG(std::string(to_string(d.shift)));
    RC_ASSERT(!right(*less, c.volume, verdict, d.shift));  // a lower bound: not right before it
    if (tight_enough(c.volume, d.distance)) RC_ASSERT(right(*more, c.volume, verdict, d.shift));  // and tight
  }
}

RC_GTEST_PROP(VerdictDistanceProperty, IsTheShiftThatMakesTheVerdictRight, (const gen::GenCase& c)) { check(c); }

RC_GTEST_PROP(VerdictDistanceProperty, HoldsOnTheHardFamilies, (gen::Distribution d)) {
  check(*gen::case_of(d));
}

}  // namespace
}  // namespace cullproof::oracle::test

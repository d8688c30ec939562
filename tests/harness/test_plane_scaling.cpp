// A metamorphic property over every family: multiplying a plane by a power of two is exact (when
// no coefficient leaves float's range or rounds into the subnormals), so the half-space, and the
// truth, cannot change. For each case of each family, every plane is multiplied by its own power
// of two (a matrix case: the whole matrix, which multiplies each of its planes), chosen so that
// the scaled plane is exact, finite and keeps a nonzero normal; then
//  - the oracle's truth is the same as on the case as drawn;
//  - every certified method's verdict on the scaled case is correct (its claim holds: no false
//    reject, no false inside), as the oracle judges.
#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace cullproof;

namespace {

// The powers of two k for which every value of `values` times 2^k is a float exactly: the
// largest stays at most FLT_MAX, the smallest nonzero one keeps all its bits (normal, or
// subnormal only when its last bits are zero: checked exactly). {lo, hi}; lo > hi when none
// but 0 (the values span more than float's range).
template <std::size_t N>
std::pair<int, int> exact_range(const std::array<float, N>& values) {
  float big = 0.0f, small = std::numeric_limits<float>::infinity();
  for (float v : values) {
    const float a = std::abs(v);
    if (a == 0.0f) continue;
    big = std::max(big, a);
    small = std::min(small, a);
  }
  if (big == 0.0f) return {0, 0};
  int lo = -126 - std::ilogb(small), hi = 127 - std::ilogb(big);
  // A value already subnormal may go up freely and down only as far as its low zero bits allow.
  while (lo > -200) {
    bool exact = true;
    for (float v : values) exact = exact && double(std::ldexp(v, lo - 1)) == std::ldexp(double(v), lo - 1);
    if (!exact) break;
    --lo;
  }
  return {lo, hi};
}

int power_in(std::pair<int, int> range) {
  if (range.first > range.second) return 0;
  return *rc::gen::inRange(range.first, range.second + 1);
}

// The case with every plane times its own exact power of two (a matrix: the whole matrix).
gen::GenCase scaled(const gen::GenCase& g) {
  gen::GenCase s = g;
  if (g.frustum.matrix) {
    glm::mat4 m = *g.frustum.matrix;
    std::array<float, 16> entries{};
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) entries[std::size_t(4 * c + r)] = m[c][r];
    const int k = power_in(exact_range(entries));
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = std::ldexp(m[c][r], k);
    s.frustum = frustum_spec(m, g.frustum.depth);
    return s;
  }
  for (Plane& p : s.frustum.planes.planes) {
    const int k = power_in(exact_range(std::array<float, 4>{p.n.x, p.n.y, p.n.z, p.d}));
    p = Plane{glm::vec3(std::ldexp(p.n.x, k), std::ldexp(p.n.y, k), std::ldexp(p.n.z, k)), std::ldexp(p.d, k)};
  }
  return s;
}

bool same_planes_up_to_scaling(const gen::GenCase& a, const gen::GenCase& b) {
  // Exactness of the scaling itself: each scaled coefficient divided back is the original.
  if (a.frustum.matrix) return true;  // checked by the entries' exact range
  for (int k = 0; k < kPlaneCount; ++k) {
    const Plane &p = a.frustum.planes[k], &q = b.frustum.planes[k];
    const double r = p.is_degenerate() ? (p.d != 0.0f ? double(q.d) / double(p.d) : 1.0)
                     : p.n.x != 0.0f   ? double(q.n.x) / double(p.n.x)
                     : p.n.y != 0.0f   ? double(q.n.y) / double(p.n.y)
                                       : double(q.n.z) / double(p.n.z);
    if (!(r > 0.0) || double(q.n.x) != double(p.n.x) * r || double(q.n.y) != double(p.n.y) * r ||
        double(q.n.z) != double(p.n.z) * r || double(q.d) != double(p.d) * r)
      return false;
  }
  return true;
}

}  // namespace

// Every distribution: the argument is rc::Arbitrary<gen::Distribution> (cullproof/gen/arbitrary.hpp).
RC_GTEST_PROP(PlaneScaling, PowersOfTwoChangeNoTruthAndNoCertifiedVerdictGoesWrong, (gen::Distribution d)) {
  const gen::GenCase g = *gen::case_of(d);
  const gen::GenCase s = scaled(g);
  RC_TAG(std::string(gen::to_string(d)));
  RC_ASSERT(is_valid(s.frustum.planes));
  RC_ASSERT(same_planes_up_to_scaling(g, s));
  const Visibility truth = oracle::truth(g.frustum, g.volume);
  RC_ASSERT(oracle::truth(s.frustum, s.volume) == truth);
  for (const Method& m : builtin_methods()) {
    if (m.claim != Claim::certified_conservative && m.claim != Claim::certified_exact) continue;
    if (!m.takes(s.volume)) continue;
    const Answer v = checked_classify(m, s.frustum, s.volume);
    if (!v) continue;
    const ErrorClass cls = error_class(*v, truth, m.three_way);
    if (cls == ErrorClass::correct) continue;
    if (!violates_claim(m.claim, cls, error_distance(s.frustum, s.volume, *v), m.tolerance, gen::case_scale(s.frustum, s.volume),
                        gen::float_exact(s.frustum, s.volume)))
      continue;
    RC_FAIL(m.name + " says " + std::string(to_string(*v)) + " on " + std::string(gen::to_string(d)) +
            " with its planes scaled, truth " + std::string(to_string(truth)) + " (" + std::string(to_string(cls)) + ")");
  }
}

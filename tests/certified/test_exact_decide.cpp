// The certified-exact cascade's exact stage (src/simd/exact_decide.hpp, not installed): its two
// integer widths give the same answers.
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/simd/exact_certified.hpp"
#include "exact_decide.hpp"

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>

namespace {

using namespace cullproof;

// The exact stage decides on 512-bit integers and, where a value outgrows them, again at arbitrary
// precision. Both routes give the same answers: on boxes and balls of a quarter grid about frusta
// whose plane coefficients are exact sums of floats up to 2^140 apart (a clip matrix's rows),
// everything scaled by powers of two from 2^-149 to 2^100; and the inputs include some on which
// the 512-bit route alone overflows, so that the second route is exercised.
TEST(ExactCertified, TheExactStagesTwoIntegerWidthsAgree) {
  using exact_detail::Width;
  std::mt19937 rng(7);
  auto pick = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  int overflowed = 0, compared = 0;
  for (int round = 0; round < 400; ++round) {
    // A pyramid or box frustum from a matrix whose rows' sums are exact dyadic values far apart.
    const float wide = std::ldexp(1.0f, -pick(0, 140));
    glm::mat4 m(0.0f);
    auto set_row = [&](int r, glm::vec4 v) {
      for (int c = 0; c < 4; ++c) m[c][r] = v[c];
    };
    set_row(0, {1, 0, 0, float(pick(-2, 2))});
    set_row(1, {0, 1, 0, float(pick(-2, 2))});
    set_row(2, {0, 0, wide, float(pick(-2, 2))});
    set_row(3, {wide, wide, 1, float(pick(0, 2))});
    const CaseFrustum cf = frustum_spec(m, {DepthRange::negative_one_to_one, false});
    const ExactCertifiedFrustum f = prepare_exact_certified(cf);
    const int scale = pick(-149, 100);
    auto coord = [&] { return std::ldexp(float(pick(-8, 8)) / 4.0f, scale); };
    auto compare = [&](auto&& decide) {
      const bool unbounded = decide(Width::unbounded);
      EXPECT_EQ(decide(Width::bounded_first), unbounded) << "round " << round;
      try {
        EXPECT_EQ(decide(Width::bounded), unbounded) << "round " << round;
      } catch (const std::overflow_error&) {
        ++overflowed;
      }
      ++compared;
    };
    Aabb b{{coord(), coord(), coord()}, {coord(), coord(), coord()}};
    b = Aabb{glm::min(b.min, b.max), glm::max(b.min, b.max)};
    const Obb o = to_obb(b);
    const Sphere sp{{coord(), coord(), coord()}, std::abs(coord())};
    const int all[6] = {0, 1, 2, 3, 4, 5};
    for (const exact_detail::BoxRef ref : {exact_detail::BoxRef{&b, nullptr}, exact_detail::BoxRef{nullptr, &o}}) {
      for (int k = 0; k < 6; ++k) compare([&](Width w) { return exact_detail::box_in_plane(f, k, ref, w); });
      compare([&](Width w) { return exact_detail::box_meets_planes(f, all, 6, ref, w); });
    }
    for (int k = 0; k < 6; ++k) compare([&](Width w) { return exact_detail::sphere_in_plane(f, k, sp, w); });
    compare([&](Width w) { return exact_detail::sphere_meets_planes(f, all, 6, sp, w); });
  }
  EXPECT_GT(overflowed, 0) << "no input outgrew 512 bits: the second route went untested";
  EXPECT_LT(overflowed, compared / 2) << "most inputs should fit 512 bits";
  std::printf("%d of %d decisions overflowed 512 bits\n", overflowed, compared);
}

}  // namespace

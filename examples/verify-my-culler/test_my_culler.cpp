// Verifying my culler: the method is described once, then one line per claim to check.
#include "my_culler.hpp"

#include <cullproof/gtest/gtest.hpp>

#include <iostream>

namespace {

cullproof::Visibility to_verdict(my::Result r) {
  return r == my::Result::outside ? cullproof::Visibility::outside
         : r == my::Result::inside ? cullproof::Visibility::inside
                                   : cullproof::Visibility::intersecting;
}

// My culler as a cullproof method: my own plane extraction from the case's matrix (so that it is
// under test end to end), or the case's planes when it gives planes.
cullproof::Method my_method(bool bug) {
  cullproof::MethodInfo info;
  info.name = bug ? "my-culler-with-a-bug" : "my-culler";
  info.description = "n/p-vertex AABB test on planes extracted by my engine";
  info.claim = cullproof::Claim::conservative;
  info.tolerance = 1e-5;  // my plane extraction rounds: errors allowed within 1e-5 of the scale
  return cullproof::make_method(
      info,
      [](const cullproof::CaseFrustum& f) {  // once per frame
        // Reversed-Z swaps which of the two depth planes is near; the set of planes is the same.
        if (f.matrix) return my::planes_from_matrix(*f.matrix, f.depth.range == cullproof::DepthRange::zero_to_one);
        my::Planes p;
        for (int i = 0; i < 6; ++i) p[i] = my::Plane{f.planes[i].n, f.planes[i].d};
        return p;
      },
      [bug](const my::Planes& planes, const cullproof::Aabb& b) {  // per box
        return to_verdict(my::classify_box(planes, b.min, b.max, bug));
      });
}

// The helper's default distributions (every family but `huge`, 2,000 cases each), shrunk failures
// written under corpus/.
cullproof::testing::ClaimOptions options() {
  cullproof::testing::ClaimOptions o;
  o.corpus = "corpus";
  return o;
}

TEST(MyCuller, HoldsItsClaim) { EXPECT_TRUE(cullproof::testing::claim_holds(my_method(false), options())); }

// What a failure looks like: the planted bug is refuted, and the message shows the shrunk case
// (also written to corpus/my-culler-with-a-bug/...). Asserted here so that the example's own
// test suite passes; in your tests, EXPECT_TRUE(claim_holds(...)) prints this and fails.
TEST(MyCullerWithABug, IsCaught) {
  const ::testing::AssertionResult r = cullproof::testing::claim_holds(my_method(true), options());
  EXPECT_FALSE(r);
  std::cout << r.message() << "\n";
}

}  // namespace

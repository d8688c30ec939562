// The registered fast cullers: names, claims, kinds; each method on hand-made cases of every
// volume kind it takes; methods that do not apply return std::nullopt.
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/methods/methods.hpp"

#include <set>

namespace cullproof {
namespace {

using V = Visibility;

const std::vector<std::string> kNames = {
    "point-plane", "radar-point", "sphere-plane", "radar-sphere", "radar-sphere-as-published",
    "sphere-batch-simd", "eight-corner", "pn-vertex", "pn-vertex-index", "p-vertex-post", "pn-vertex-lut",
    "pn-vertex-batch-simd", "perspective-transform-as-published", "perspective-transform", "obb-pn-vertex",
    "box-sphere-then-pn-vertex", "box-sphere-only", "frustum-sphere-then-pn-vertex",
    "frustum-aabb-then-pn-vertex", "plane-coherency", "octant", "octant-corrected", "tr-coherency"};

TEST(CullRegistry, EveryMethodIsRegisteredWithItsMetadata) {
  for (const auto& n : kNames) {
    const Method* m = find_builtin(n);
    ASSERT_NE(m, nullptr) << n;
    EXPECT_FALSE(m->source.empty()) << n;
    EXPECT_FALSE(m->touching.empty()) << n;
    EXPECT_NE(m->volumes, 0u) << n;
    for (char c : m->name) EXPECT_TRUE((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-') << n;
  }
  for (const char* s : {"plane-coherency", "octant", "octant-corrected", "tr-coherency"})
    EXPECT_TRUE(find_builtin(s)->stateful) << s;
  EXPECT_EQ(find_builtin("radar-sphere-as-published")->claim, Claim::none);
  EXPECT_EQ(find_builtin("perspective-transform-as-published")->claim, Claim::none);
  EXPECT_EQ(find_builtin("point-plane")->claim, Claim::exact);
  // cullproof's own variants are not "published methods under test".
  for (const char* s : {"radar-sphere", "perspective-transform", "octant-corrected", "pn-vertex-index",
                        "pn-vertex-batch-simd", "sphere-batch-simd"})
    EXPECT_NE(find_builtin(s)->origin, Origin::published) << s;
  for (const char* s : {"pn-vertex", "octant", "radar-sphere-as-published", "perspective-transform-as-published",
                        "eight-corner", "p-vertex-post", "tr-coherency"})
    EXPECT_EQ(find_builtin(s)->origin, Origin::published) << s;
}

struct Case {
  const char* what;
  CaseFrustum frustum;
  Volume volume;
  Visibility expected;
};

std::vector<Case> cases() {
  using namespace test;
  const CaseFrustum sym = frustum_spec(sym90());
  const CaseFrustum symm = frustum_spec(sym90_matrix(), {});
  const CaseFrustum inf = frustum_spec(sym90_infinite());
  const CaseFrustum ort = frustum_spec(ortho());
  return {
      {"point inside", sym, Point{0, 0, -5}, V::inside},
      {"point behind the camera", sym, Point{0, 0, 3}, V::outside},
      {"point far away, infinite far plane", inf, Point{0, 0, -1e5f}, V::inside},
      {"sphere inside", sym, Sphere{{0, 0, -5}, 1}, V::inside},
      {"sphere outside", sym, Sphere{{30, 0, -5}, 1}, V::outside},
      {"sphere straddling near", sym, Sphere{{0, 0, -1}, 0.5f}, V::intersecting},
      {"sphere behind the camera", sym, Sphere{{0, 0, 5}, 1}, V::outside},
      {"box inside", sym, inside_box(), V::inside},
      {"box inside, matrix case", symm, inside_box(), V::inside},
      {"box outside", sym, outside_box(), V::outside},
      {"box outside, matrix case", symm, outside_box(), V::outside},
      {"box straddling right", sym, straddle_right_box(), V::intersecting},
      {"box behind the camera", sym, behind_box(), V::outside},
      {"box touching near from outside", sym, touch_near_outside_box(), V::intersecting},
      {"box beyond far, infinite far plane: inside", inf, far_beyond_box(), V::inside},
      {"orthographic: box touching x = 1 from outside", ort, test::box({1, -0.5f, -4}, {2, 0.5f, -3}),
       V::intersecting},
      {"orthographic: box inside", ort, inside_box(), V::inside},
  };
}

bool two_way(const std::string& name) { return name == "p-vertex-post" || name == "box-sphere-only"; }

TEST(CullRegistry, EveryMethodOnHandCasesOfItsKinds) {
  for (const auto& n : kNames) {
    const Method& m = *find_builtin(n);
    int run = 0;
    for (const Case& c : cases()) {
      if (!m.takes(c.volume)) continue;
      const auto v = m.classify(c.frustum, c.volume);
      if (!v) continue;  // does not apply (e.g. radar on an orthographic frustum)
      ++run;
      if (m.claim == Claim::none) continue;  // published methods under test: measured, not asserted
      // The matrix of a planes-only case is derived (clip_matrix_from_frustum) and rounded, so
      // a box touching a plane exactly is within this method's rounding tolerance.
      if (n == "perspective-transform" && std::string(c.what).find("touching") != std::string::npos &&
          !c.frustum.matrix)
        continue;
      if (two_way(n) || n == "box-sphere-only") {
        if (c.expected == V::outside) EXPECT_EQ(*v, V::outside) << n << ": " << c.what;
        else EXPECT_NE(*v, V::outside) << n << ": " << c.what;
      } else {
        EXPECT_EQ(*v, c.expected) << n << ": " << c.what;
      }
    }
    EXPECT_GT(run, 0) << n << " ran on no case";
  }
}

TEST(CullRegistry, MethodsThatNeedASymmetricFrustumDoNotApplyToAnAsymmetricOne) {
  const CaseFrustum f = frustum_spec(test::off_axis());
  for (const char* n : {"octant", "octant-corrected"})
    EXPECT_FALSE(find_builtin(n)->classify(f, test::inside_box()).has_value()) << n;
  EXPECT_FALSE(find_builtin("radar-point")->classify(f, Point{0, 0, -5}).has_value());
  EXPECT_FALSE(find_builtin("radar-sphere")->classify(f, Sphere{{0, 0, -5}, 1}).has_value());
  // Everything else applies.
  EXPECT_TRUE(find_builtin("tr-coherency")->classify(f, test::inside_box()).has_value());
  EXPECT_TRUE(find_builtin("perspective-transform")->classify(f, test::inside_box()).has_value());
}

}  // namespace
}  // namespace cullproof

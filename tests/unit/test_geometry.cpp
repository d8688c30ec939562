// Geometry core: names, normalisation, validation messages.
#include "cullproof/core/geometry.hpp"

#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

using namespace cullproof;

namespace {

template <class T>
std::string validation_message(const T& x) {
  try {
    validate(x);
  } catch (const ValidationError& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(Visibility, NamesRoundTrip) {
  for (Visibility v : {Visibility::outside, Visibility::intersecting, Visibility::inside})
    EXPECT_EQ(visibility_from_string(to_string(v)), v);
  EXPECT_THROW(visibility_from_string("visible"), std::invalid_argument);
}

TEST(Plane, PointOnPlaneIsInside) {
  const Plane p{{0.0f, 0.0f, 1.0f}, -2.0f};
  EXPECT_EQ(p.eval({5.0f, -3.0f, 2.0f}), 0.0f);  // closed half-space: 0 counts as inside
  EXPECT_GT(p.eval({0.0f, 0.0f, 3.0f}), 0.0f);
  EXPECT_LT(p.eval({0.0f, 0.0f, 1.0f}), 0.0f);
}

TEST(Plane, NormalizeKeepsInfiniteFarPlaneWithoutNaN) {
  const Plane all{{0.0f, 0.0f, 0.0f}, 2.0f};
  const Plane n = all.normalized();
  EXPECT_TRUE(n.is_degenerate());
  EXPECT_EQ(n.d, 2.0f);
}

TEST(Plane, NormalizeHugeCoefficientsDoesNotOverflow) {
  const Plane p{{3e37f, 4e37f, 0.0f}, 5e37f};  // squares overflow float
  const Plane n = p.normalized();
  EXPECT_FLOAT_EQ(n.n.x, 0.6f);
  EXPECT_FLOAT_EQ(n.n.y, 0.8f);
  EXPECT_FLOAT_EQ(n.d, 1.0f);
}

TEST(Validation, AcceptsFlatAndPointBoxes) {
  EXPECT_NO_THROW(validate(Aabb{{1, 2, 3}, {1, 2, 3}}));
  EXPECT_NO_THROW(validate(Aabb{{0, 0, 0}, {1, 0, 1}}));
  EXPECT_NO_THROW(validate(Sphere{{0, 0, 0}, 0.0f}));
  EXPECT_NO_THROW(validate(Obb{{0, 0, 0}, glm::mat3(1.0f), {0, 0, 0}}));
}

TEST(Validation, RejectsMinGreaterThanMaxNamingTheComponent) {
  const std::string m = validation_message(Aabb{{0, 2, 0}, {1, 1, 1}});
  EXPECT_NE(m.find("min[1]"), std::string::npos) << m;
}

TEST(Validation, RejectsNaNAndInfinityNamingTheField) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_NE(validation_message(Aabb{{0, nan, 0}, {1, 1, 1}}).find("aabb.min[1]: is NaN"), std::string::npos);
  EXPECT_NE(validation_message(Sphere{{0, 0, -inf}, 1}).find("sphere.center[2]: is -infinity"), std::string::npos);
  Frustum f;
  f[kTop].d = inf;
  EXPECT_NE(validation_message(f).find("frustum.top.d: is +infinity"), std::string::npos);
}

TEST(Validation, RejectsNegativeExtentsRadiusAndZeroAxis) {
  EXPECT_NE(validation_message(Sphere{{0, 0, 0}, -1}).find("radius: is negative"), std::string::npos);
  EXPECT_NE(validation_message(Obb{{0, 0, 0}, glm::mat3(1.0f), {1, -0.5f, 1}}).find("half[1]: is negative"),
            std::string::npos);
  glm::mat3 axes(1.0f);
  axes[2] = glm::vec3(0.0f);
  EXPECT_NE(validation_message(Obb{{0, 0, 0}, axes, {1, 1, 1}}).find("axes[2]: is a zero-length axis"),
            std::string::npos);
}

TEST(Volume, KindsAndToObb) {
  EXPECT_EQ(volume_kind(Volume{Point{0, 0, 0}}), kPointKind);
  EXPECT_EQ(volume_kind(Volume{Obb{}}), kObbKind);
  EXPECT_EQ(volume_kind_name(kSphereKind), "sphere");
  const Obb o = to_obb(Aabb{{0, 2, 4}, {2, 6, 4}});
  EXPECT_EQ(o.center, glm::vec3(1, 4, 4));
  EXPECT_EQ(o.half, glm::vec3(1, 2, 0));
}

// A float as an exact integer multiple of 2^-172 (a subnormal is m 2^(e-24) with e >= -148).
boost::multiprecision::cpp_int fixed(float x) {
  if (x == 0.0f) return 0;
  int ex = 0;
  const auto mant = static_cast<std::int32_t>(std::ldexp(std::frexp(x, &ex), 24));  // x = mant 2^(ex - 24)
  return boost::multiprecision::cpp_int(mant) << static_cast<unsigned>(ex - 24 + 172);
}

// Exact containment: c - h <= lo and hi <= c + h on every axis.
bool encloses(const Obb& o, const Aabb& b) {
  for (int i = 0; i < 3; ++i) {
    const auto c = fixed(o.center[i]), h = fixed(o.half[i]);
    if (c - h > fixed(b.min[i]) || c + h < fixed(b.max[i])) return false;
  }
  return o.axes == glm::mat3(1.0f);
}

TEST(Geometry, TheEnclosingObbHoldsTheWholeBox) {
  const float big = std::numeric_limits<float>::max(), sub = std::numeric_limits<float>::denorm_min();
  // A subnormal box whose float centre rounds by half an ulp: to_obb loses a sliver of it.
  const Aabb sliver{{1.61e-43f, 3.85e-43f, 7.54e-43f}, {1.63e-43f, 3.87e-43f, 7.55e-43f}};
  EXPECT_FALSE(encloses(to_obb(sliver), sliver));
  EXPECT_TRUE(encloses(enclosing_obb(sliver), sliver));
  // Far-apart exponents, where the double difference itself rounds; the whole float range.
  for (const Aabb& b : {sliver, Aabb{{1e-30f, 3, -big}, {1e30f, 3.0000002f, big}}, Aabb{{-big, -big, -big}, {big, big, big}},
                        Aabb{{sub, -sub, 0}, {2 * sub, sub, 1e-38f}}, Aabb{{-1e38f, 1.5f, -7}, {3e38f, 1.5f, 1e-45f}}}) {
    const Obb o = enclosing_obb(b);
    EXPECT_TRUE(encloses(o, b));
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(std::isfinite(o.half[i]));
  }
  // Where to_obb is exact, so is the enclosing box.
  const Aabb exact{{0, 2, 4}, {2, 6, 4}};
  EXPECT_EQ(enclosing_obb(exact).half, to_obb(exact).half);
}

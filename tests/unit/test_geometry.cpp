// Geometry core: names, normalisation, validation messages.
#include "cullproof/geometry.hpp"

#include <gtest/gtest.h>

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

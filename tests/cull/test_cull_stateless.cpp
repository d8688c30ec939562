// Unit tests of the stateless fast cullers (cullproof/core/cull.hpp): hand-made cases named by what
// they check. Frusta and boxes: cull_fixtures.hpp.
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/core/cull.hpp"

#include <glm/ext/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <functional>

namespace cullproof {
namespace {

using test::box;
using V = Visibility;
using AabbFn = std::function<Visibility(const Frustum&, const Aabb&)>;

// The AABB cullers that answer three-way, each under test with the same table.
struct NamedAabbFn {
  const char* name;
  AabbFn fn;
};

std::vector<NamedAabbFn> three_way_aabb_methods() {
  return {
      {"eight-corner", aabb_eight_corner},
      {"pn-vertex", pn_vertex},
      {"pn-vertex-index", pn_vertex_index},
      {"pn-vertex-lut", [](const Frustum& f, const Aabb& b) { return pn_vertex_lut(make_pn_lut(f), b); }},
      {"obb-pn-vertex", [](const Frustum& f, const Aabb& b) { return obb_pn_vertex(f, to_obb(b)); }},
      {"box-sphere-then-pn-vertex",
       [](const Frustum& f, const Aabb& b) {
         if (auto r = box_sphere_stage(f.normalized(), b)) return *r;
         return pn_vertex(f, b);
       }},
      {"frustum-sphere-then-pn-vertex",
       [](const Frustum& f, const Aabb& b) {
         if (auto r = frustum_sphere_stage(frustum_bounds(f), b)) return *r;
         return pn_vertex(f, b);
       }},
      {"frustum-aabb-then-pn-vertex",
       [](const Frustum& f, const Aabb& b) {
         if (auto r = frustum_aabb_stage(frustum_bounds(f), b)) return *r;
         return pn_vertex(f, b);
       }},
  };
}

struct AabbCase {
  const char* what;
  Frustum frustum;
  Aabb box;
  Visibility expected;
};

std::vector<AabbCase> aabb_cases() {
  using namespace test;
  return {
      {"box inside the symmetric frustum", sym90(), inside_box(), V::inside},
      {"box far outside to the right", sym90(), outside_box(), V::outside},
      {"box straddling the right plane only", sym90(), straddle_right_box(), V::intersecting},
      {"box touches the near plane from outside (shares the face z = -1)", sym90(), touch_near_outside_box(),
       V::intersecting},
      {"box touches the near plane from inside", sym90(), touch_near_inside_box(), V::inside},
      {"box behind the camera", sym90(), behind_box(), V::outside},
      {"box beyond the far plane", sym90(), far_beyond_box(), V::outside},
      {"infinite far plane: box at z = -30 is inside", sym90_infinite(), far_beyond_box(), V::inside},
      {"infinite far plane: box to the right is outside", sym90_infinite(), outside_box(), V::outside},
      {"orthographic: box inside", ortho(), inside_box(), V::inside},
      {"orthographic: box straddles x = 1", ortho(), box({0.5f, -0.5f, -4}, {1.5f, 0.5f, -3}), V::intersecting},
      {"orthographic: box touches x = 1 from outside", ortho(), box({1, -0.5f, -4}, {2, 0.5f, -3}), V::intersecting},
      {"orthographic: box touches x = 1 from inside", ortho(), box({0, -0.5f, -4}, {1, 0.5f, -3}), V::inside},
      {"orthographic: box just outside x = 1", ortho(), box({1.0625f, -0.5f, -4}, {2, 0.5f, -3}), V::outside},
      {"asymmetric frustum: box inside", off_axis(), box({0, -0.2f, -4}, {1, 0.2f, -3}), V::inside},
      {"asymmetric frustum: box left of the narrow side", off_axis(), box({-2, -0.2f, -4}, {-1.5f, 0.2f, -3}),
       V::outside},
      {"flat box (min == max) on the right plane", sym90(), box({3, 0, -3}, {3, 0, -3}), V::inside},
  };
}

TEST(CullAabb, EveryThreeWayMethodAgreesWithTheHandTable) {
  for (const auto& m : three_way_aabb_methods())
    for (const auto& c : aabb_cases())
      EXPECT_EQ(m.fn(c.frustum, c.box), c.expected) << m.name << ": " << c.what;
}

TEST(CullAabb, PVertexPostIsTwoWayAndRejectsTheSameBoxes) {
  for (const auto& c : aabb_cases()) {
    const Visibility v = p_vertex_post(c.frustum, c.box);
    EXPECT_EQ(v, c.expected == V::outside ? V::outside : V::intersecting) << c.what;
  }
}

TEST(CullAabb, EightCornerReportsTheOrangeBoxIntersecting) {
  // Outside the frustum beyond its right-far edge but not outside any single plane (A&M fig. 2,
  // Lighthouse3D's orange box): the per-plane tests are conservative.
  const Aabb orange = box({10.5f, -0.5f, -11}, {12, 0.5f, -9});
  // Part with z >= -10 has x >= 10.5 > -z (<= 10): outside right there; part with z < -10 is
  // beyond far. No single plane has all corners out.
  EXPECT_EQ(aabb_eight_corner(test::sym90(), orange), V::intersecting);
  EXPECT_EQ(pn_vertex(test::sym90(), orange), V::intersecting);
}

TEST(CullAabb, LutBitfieldsFollowTheNormalSigns) {
  const PnLut lut = make_pn_lut(test::sym90());
  EXPECT_EQ(lut.p_bits[kLeft], 1u);    // n = (1, 0, -1): max x
  EXPECT_EQ(lut.p_bits[kRight], 0u);   // n = (-1, 0, -1)
  EXPECT_EQ(lut.p_bits[kBottom], 2u);  // n = (0, 1, -1): max y
  EXPECT_EQ(lut.p_bits[kFar], 4u);     // n = (0, 0, 1): max z
}

// ---- points

TEST(CullPoint, PlaneTestHandCases) {
  const Frustum f = test::sym90();
  EXPECT_EQ(point_plane_test(f, {0, 0, -5}), V::inside) << "point inside";
  EXPECT_EQ(point_plane_test(f, {5, 0, -5}), V::inside) << "point on the right plane is inside";
  EXPECT_EQ(point_plane_test(f, {5.0001f, 0, -5}), V::outside) << "point just right of the right plane";
  EXPECT_EQ(point_plane_test(f, {0, 0, 1}), V::outside) << "point behind the camera";
  EXPECT_EQ(point_plane_test(test::sym90_infinite(), {0, 0, -1e6f}), V::inside) << "infinite far plane";
  EXPECT_EQ(point_plane_test(test::ortho(), {1, 1, -1}), V::inside) << "orthographic corner";
}

TEST(CullPoint, RadarDerivesTheCameraOfASymmetricFrustum) {
  const auto cam = radar_camera_from_frustum(test::sym90());
  ASSERT_TRUE(cam.has_value());
  EXPECT_NEAR(cam->tang, 1.0f, 1e-6f);
  EXPECT_NEAR(cam->ratio, 1.0f, 1e-6f);
  EXPECT_NEAR(cam->near_dist, 1.0f, 1e-6f);
  EXPECT_NEAR(cam->far_dist, 10.0f, 1e-5f);
  EXPECT_NEAR(glm::length(cam->eye), 0.0f, 1e-6f);
  EXPECT_NEAR(cam->z_axis.z, -1.0f, 1e-6f);
}

TEST(CullPoint, RadarRefusesAsymmetricAndOrthographicFrusta) {
  EXPECT_FALSE(radar_camera_from_frustum(test::off_axis()).has_value()) << "asymmetric refused";
  EXPECT_FALSE(radar_camera_from_frustum(test::ortho()).has_value()) << "orthographic refused";
}

TEST(CullPoint, RadarHandCases) {
  const RadarCamera cam = *radar_camera_from_frustum(test::sym90());
  EXPECT_EQ(radar_point(cam, {0, 0, -5}), V::inside) << "inside";
  EXPECT_EQ(radar_point(cam, {0, 0, -0.5f}), V::outside) << "between the eye and the near plane";
  EXPECT_EQ(radar_point(cam, {0, 0, 5}), V::outside) << "behind the camera";
  EXPECT_EQ(radar_point(cam, {0, 0, -11}), V::outside) << "beyond far";
  EXPECT_EQ(radar_point(cam, {0, 6, -5}), V::outside) << "above the top plane";
  EXPECT_EQ(radar_point(cam, {4, 4, -5}), V::inside) << "inside near the corner";
  EXPECT_EQ(radar_point(cam, {0, 0, -1}), V::inside) << "on the near plane";
  const RadarCamera inf = *radar_camera_from_frustum(test::sym90_infinite());
  EXPECT_TRUE(std::isinf(inf.far_dist)) << "infinite far plane gives far = inf";
  EXPECT_EQ(radar_point(inf, {0, 0, -1e6f}), V::inside) << "infinite far plane";
}

TEST(CullPoint, RadarFromCameraMatchesThePlaneTest) {
  PerspectiveCamera c;
  c.fovy_degrees = 60;
  c.aspect = 1.5f;
  c.near_dist = 0.5f;
  c.far_dist = 50;
  c.eye = {1, 2, 3};
  c.target = {0, 0, -10};
  const RadarCamera cam = radar_camera(c);
  const Frustum f = frustum_from_camera(c);
  int checked = 0;
  for (int i = -10; i <= 10; ++i)
    for (int j = -10; j <= 10; ++j)
      for (int k = 0; k <= 20; ++k) {
        const glm::vec3 p(1 + 1.37f * i, 2 + 0.91f * j, 3 - 2.43f * k);
        const float margin = 1e-3f;
        bool clear = true;
        for (int q = 0; q < 6; ++q) clear = clear && std::abs(f[q].normalized().eval(p)) > margin;
        if (!clear) continue;
        ++checked;
        EXPECT_EQ(radar_point(cam, p), point_plane_test(f, p)) << p.x << " " << p.y << " " << p.z;
      }
  EXPECT_GT(checked, 1000);
}

// ---- spheres

TEST(CullSphere, PlaneTestHandCases) {
  const Frustum f = test::sym90().normalized();
  EXPECT_EQ(sphere_plane_test(f, Sphere{{0, 0, -5}, 1}), V::inside) << "inside";
  EXPECT_EQ(sphere_plane_test(f, Sphere{{20, 0, -5}, 1}), V::outside) << "outside";
  EXPECT_EQ(sphere_plane_test(f, Sphere{{0, 0, 0}, 1}), V::intersecting) << "touches near from outside";
  EXPECT_EQ(sphere_plane_test(f, Sphere{{0, 0, -11}, 1}), V::intersecting) << "touches far from outside";
  EXPECT_EQ(sphere_plane_test(f, Sphere{{0, 0, -9}, 1}), V::inside) << "touches far from inside";
  EXPECT_EQ(sphere_plane_test(f, Sphere{{0, 0, 5}, 1}), V::outside) << "behind the camera";
  EXPECT_EQ(sphere_plane_test(test::sym90_infinite().normalized(), Sphere{{0, 0, -1000}, 100}), V::inside)
      << "infinite far plane is skipped";
  EXPECT_EQ(sphere_plane_test(test::ortho().normalized(), Sphere{{1.5f, 0, -5}, 0.5f}), V::intersecting)
      << "orthographic: touches x = 1 from outside";
  Frustum empty = test::sym90().normalized();
  empty[kFar] = Plane{{0, 0, 0}, -1};
  EXPECT_EQ(sphere_plane_test(empty, Sphere{{0, 0, -5}, 1}), V::outside) << "n == 0, d < 0 contains nothing";
}

TEST(CullSphere, RadarCorrectedAgreesWithPlaneTestAwayFromTheBoundary) {
  const RadarCamera cam = *radar_camera_from_frustum(test::sym90());
  const Frustum f = test::sym90().normalized();
  for (float x : {-12.f, -6.f, -3.f, 0.f, 2.f, 4.5f, 7.f})
    for (float z : {2.f, -0.5f, -2.f, -5.f, -9.f, -12.f})
      for (float r : {0.1f, 0.7f, 2.f}) {
        const Sphere s{{x, 0.3f * x, z}, r};
        EXPECT_EQ(radar_sphere(cam, s), sphere_plane_test(f, s)) << x << " " << z << " " << r;
      }
}

TEST(CullSphere, RadarAsPublishedUsesTheFullAngleAndAcceptsAnOutsideSphere) {
  PerspectiveCamera c;
  c.fovy_degrees = 60;
  c.aspect = 1;
  c.near_dist = 1;
  c.far_dist = 100;
  c.eye = {0, 0, 0};
  c.target = {0, 0, -1};
  const RadarCamera good = radar_camera(c), pub = radar_camera_as_published(c);
  EXPECT_NEAR(good.tang, std::tan(glm::radians(30.0f)), 1e-6f);
  EXPECT_NEAR(pub.tang, std::tan(glm::radians(60.0f)), 1e-5f);
  // Centre at 45 degrees above the axis, radius 1: outside the 60-degree frustum by far.
  const Sphere s{{0, 10, -10}, 1};
  EXPECT_EQ(radar_sphere(good, s), V::outside);
  EXPECT_EQ(radar_sphere(pub, s), V::inside) << "as published: a false inside";
  EXPECT_EQ(sphere_plane_test(frustum_from_camera(c).normalized(), s), V::outside);
}

// ---- OBB

TEST(CullObb, RotatedBoxHandCases) {
  const Frustum f = test::sym90();
  Obb b;
  b.axes = glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(45.0f), glm::vec3(0, 0, 1)));
  b.half = {0.5f, 0.5f, 0.5f};
  b.center = {0, 0, -5};
  EXPECT_EQ(obb_pn_vertex(f, b), V::inside) << "inside";
  b.center = {20, 0, -5};
  EXPECT_EQ(obb_pn_vertex(f, b), V::outside) << "outside";
  b.center = {5, 0, -5};
  EXPECT_EQ(obb_pn_vertex(f, b), V::intersecting) << "straddling the right plane";
  b.center = {0, 0, 3};
  EXPECT_EQ(obb_pn_vertex(f, b), V::outside) << "behind the camera";
  b.center = {0, 0, -500};
  EXPECT_EQ(obb_pn_vertex(test::sym90_infinite(), b), V::inside) << "infinite far plane";
}

// ---- perspective transform (DirectModel)

TEST(CullPerspectiveTransform, HandCases) {
  const glm::mat4 m = test::sym90_matrix();
  const DepthConvention gl{};
  for (auto fn : {perspective_transform, perspective_transform_as_published}) {
    EXPECT_EQ(fn(m, gl, test::inside_box()), V::inside) << "inside";
    EXPECT_EQ(fn(m, gl, test::outside_box()), V::outside) << "outside";
    EXPECT_EQ(fn(m, gl, test::straddle_right_box()), V::intersecting) << "straddling";
    EXPECT_EQ(fn(m, gl, test::far_beyond_box()), V::outside) << "beyond far";
  }
  // Behind the camera: every corner has w < 0. As published the division mirrors the box
  // through the eye; corrected, the outcodes reject it on the near plane.
  EXPECT_EQ(perspective_transform(m, gl, test::behind_box()), V::outside) << "behind the camera";
}

TEST(CullPerspectiveTransform, BoxStraddlingTheEyePlaneIsNotRejected) {
  const glm::mat4 m = test::sym90_matrix();
  // Visible: the point (0, 0, -2) is inside; corners at z = 1 are behind the eye (w = -1).
  const Aabb b = box({-0.5f, -0.5f, -5}, {0.5f, 0.5f, 1});
  EXPECT_EQ(perspective_transform(m, {}, b), V::intersecting);
}

TEST(CullPerspectiveTransform, CorrectedNeverRejectsVisibleBoxesWithACornerAtOrBehindTheEye) {
  // A corner exactly at the eye has w == 0: x / w = inf or NaN. Box from the eye to z = -5,
  // entirely on x >= 0: the NDC box x range becomes [.., inf] or garbage. Check a few such
  // boxes for a published false reject, and check the corrected test never rejects them.
  const glm::mat4 m = test::sym90_matrix();
  int published_rejects = 0;
  for (float x0 : {0.0f, 0.25f})
    for (float x1 : {0.5f, 1.0f, 3.0f})
      for (float z1 : {0.0f, 0.5f, 2.0f}) {
        const Aabb b = box({x0, -0.25f, -5}, {x1, 0.25f, z1});
        // The point (x0 + 0.01, 0, -4) is inside the frustum and the box: visible.
        EXPECT_NE(perspective_transform(m, {}, b), V::outside) << x0 << " " << x1 << " " << z1;
        published_rejects += perspective_transform_as_published(m, {}, b) == V::outside;
      }
  RecordProperty("published_false_rejects", published_rejects);
  std::printf("perspective-transform as published: %d of 18 visible boxes with a corner at or behind the eye rejected\n",
              published_rejects);
}

TEST(CullPerspectiveTransform, AsPublishedRejectsAVisibleBoxFromBehindTheEyeToBeyondFar) {
  // A long box around the view axis from z = 1 (behind the eye, w = -1) to z = -20 (beyond
  // far): visible, it contains (0, 0, -5). Behind the eye, ndc z = clip.z / w > 1 (the division
  // by a negative w mirrors the point past the far plane); beyond far, ndc z > 1 too, so the
  // NDC box lies entirely above z = 1 and the published test rejects it: a false reject.
  const glm::mat4 m = test::sym90_matrix();
  const Aabb corridor = box({-0.5f, -0.5f, -20}, {0.5f, 0.5f, 1});
  EXPECT_EQ(perspective_transform_as_published(m, {}, corridor), V::outside) << "as published: false reject";
  EXPECT_EQ(perspective_transform(m, {}, corridor), V::intersecting) << "corrected";
  EXPECT_EQ(pn_vertex(test::sym90(), corridor), V::intersecting);
  // The camera inside a big box: the same.
  const Aabb room = box({-5, -5, -20}, {5, 5, 1});
  EXPECT_EQ(perspective_transform_as_published(m, {}, room), V::outside) << "as published: false reject";
  EXPECT_EQ(perspective_transform(m, {}, room), V::intersecting);
}

TEST(CullPerspectiveTransform, ClipMatrixFromPlanesReproducesThePlanes) {
  for (const Frustum& f : {test::sym90(), test::ortho(), test::off_axis(), test::sym90_infinite()}) {
    const auto m = clip_matrix_from_frustum(f);
    ASSERT_TRUE(m.has_value());
    const Frustum g = frustum_from_matrix(*m).normalized();
    const Frustum fn = f.normalized();
    for (int i = 0; i < 6; ++i) {
      if (fn[i].is_degenerate()) {  // infinite far plane: must stay "all space"
        EXPECT_TRUE(g[i].is_degenerate()) << plane_name(i);
        EXPECT_GT(g[i].d, 0.0f) << plane_name(i);
        continue;
      }
      EXPECT_NEAR(glm::length(g[i].n - fn[i].n), 0.0f, 1e-5f) << plane_name(i);
      EXPECT_NEAR(g[i].d, fn[i].d, 1e-4f) << plane_name(i);
    }
  }
  Frustum junk = test::sym90();
  junk[kFar] = Plane{{0.3f, 0.2f, 1}, 10};  // not parallel to near: no clip cube maps to it
  EXPECT_FALSE(clip_matrix_from_frustum(junk).has_value());
}

// ---- pre-test stages

TEST(CullPretest, StagesAnswerOnlyWhenSure) {
  const Frustum f = test::sym90();
  const Frustum fn = f.normalized();
  const FrustumBounds fb = frustum_bounds(f);
  ASSERT_TRUE(fb.bounded);
  EXPECT_EQ(box_sphere_stage(fn, test::inside_box()), V::inside);
  EXPECT_EQ(box_sphere_stage(fn, test::outside_box()), V::outside);
  EXPECT_FALSE(box_sphere_stage(fn, test::straddle_right_box()).has_value()) << "straddling falls through";
  EXPECT_EQ(frustum_sphere_stage(fb, test::outside_box()), V::outside);
  EXPECT_FALSE(frustum_sphere_stage(fb, test::inside_box()).has_value());
  EXPECT_EQ(frustum_aabb_stage(fb, test::behind_box()), V::outside) << "behind the camera";
  EXPECT_FALSE(frustum_aabb_stage(fb, test::inside_box()).has_value()) << "text's INSIDE falls through";
  // Touching the frustum's AABB from outside (z = -1 face) falls through (strict compares).
  EXPECT_FALSE(frustum_aabb_stage(fb, box({-0.5f, -0.5f, -1}, {0.5f, 0.5f, 0})).has_value());
  const FrustumBounds inf = frustum_bounds(test::sym90_infinite());
  EXPECT_FALSE(inf.bounded) << "infinite far plane: no bounds";
  EXPECT_FALSE(frustum_aabb_stage(inf, test::outside_box()).has_value());
  EXPECT_FALSE(frustum_sphere_stage(inf, test::outside_box()).has_value());
}

TEST(CullPretest, FrustumSphereContainsTheCorners) {
  const Frustum f = test::off_axis();
  const FrustumBounds fb = frustum_bounds(f);
  for (const auto& c : frustum_corners(f)) {
    EXPECT_LE(glm::length(c - glm::dvec3(fb.sphere_center)), double(fb.sphere_radius));
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(double(fb.box.min[k]), c[k]);
      EXPECT_GE(double(fb.box.max[k]), c[k]);
    }
  }
}

}  // namespace
}  // namespace cullproof

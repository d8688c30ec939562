// Unit tests of the frame-coherent cullers (cullproof/core/cull_coherence.hpp).
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/core/cull_coherence.hpp"

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <random>
#include <string>

namespace cullproof {
namespace {

using test::box;
using V = Visibility;

std::vector<Aabb> dyadic_boxes(std::uint32_t seed, int n) {
  // Coordinates on a 1/16 grid: plane values of sym90 (integer coefficients) are exact.
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> c(-16 * 12, 16 * 12), e(0, 16 * 3);
  std::vector<Aabb> out;
  for (int i = 0; i < n; ++i) {
    glm::vec3 lo(c(rng) / 16.0f, c(rng) / 16.0f, (c(rng) - 16 * 4) / 16.0f);
    glm::vec3 hi = lo + glm::vec3(e(rng), e(rng), e(rng)) / 16.0f;
    out.push_back(Aabb{lo, hi});
  }
  return out;
}

// ---- plane coherency

TEST(CullPlaneCoherency, VerdictsEqualPnVertexForAnyCache) {
  for (const Frustum& f : {test::sym90(), test::ortho(), test::off_axis(), test::sym90_infinite()})
    for (const Aabb& b : dyadic_boxes(1, 500))
      for (int cached = -1; cached < 6; ++cached) {
        PlaneCoherencyCache cache{static_cast<std::int8_t>(cached)};
        EXPECT_EQ(plane_coherency_test(f, b, cache), pn_vertex(f, b));
      }
}

TEST(CullPlaneCoherency, CachesTheRejectingPlaneAndStartsThereNextFrame) {
  PlaneCoherencyCache cache;
  std::uint64_t tests = 0;
  // Outside the far plane only: the A&M order left, right, near, far reaches far 4th.
  EXPECT_EQ(plane_coherency_test(test::sym90(), test::far_beyond_box(), cache, &tests), V::outside);
  EXPECT_EQ(cache.last_outside_plane, kFar);
  EXPECT_EQ(tests, 4u);
  tests = 0;
  EXPECT_EQ(plane_coherency_test(test::sym90(), test::far_beyond_box(), cache, &tests), V::outside);
  EXPECT_EQ(tests, 1u) << "second frame: one plane test";
}

// ---- octant

TEST(CullOctant, RefusesAsymmetricFrustumWithAClearError) {
  try {
    OctantCuller c(test::off_axis());
    FAIL() << "asymmetric frustum accepted";
  } catch (const CullerPreconditionError& e) {
    EXPECT_NE(std::string(e.what()).find("octant: frustum is not symmetric"), std::string::npos) << e.what();
  }
}

TEST(CullOctant, RefusesInfiniteFarPlane) {
  EXPECT_THROW(OctantCuller c(test::sym90_infinite()), CullerPreconditionError);
}

TEST(CullOctant, HandCasesOnASymmetricFrustum) {
  const OctantCuller c(test::sym90());
  EXPECT_NEAR(c.centre_distance(), 5.5 / std::sqrt(2.0), 1e-5);
  for (auto fn : {&OctantCuller::classify, &OctantCuller::classify_corrected}) {
    EXPECT_EQ((c.*fn)(test::inside_box()), V::inside) << "inside";
    EXPECT_EQ((c.*fn)(test::outside_box()), V::outside) << "outside";
    EXPECT_EQ((c.*fn)(test::straddle_right_box()), V::intersecting) << "straddling right";
    EXPECT_EQ((c.*fn)(test::behind_box()), V::outside) << "behind the camera";
    EXPECT_EQ((c.*fn)(test::touch_near_outside_box()), V::intersecting) << "touching near from outside";
    // d2 > d1: the fig. 6 precondition fails, full test.
    EXPECT_EQ((c.*fn)(box({-20, -20, -30}, {20, 20, 5})), V::intersecting) << "huge box";
  }
  // Orthographic boxes are symmetric too.
  const OctantCuller o(test::ortho());
  EXPECT_EQ(o.classify(test::inside_box()), V::inside);
  EXPECT_EQ(o.classify(box({1, -0.5f, -4}, {2, 0.5f, -3})), V::intersecting) << "orthographic touching";
}

// Smallest normalised plane value at the n-vertex: < 0 means a corner is outside that plane.
double min_n_vertex_margin(const Frustum& f, const Aabb& b) {
  double m = 1e300;
  for (int i = 0; i < 6; ++i) {
    const glm::dvec3 n(f[i].n);
    const glm::dvec3 v(n.x > 0 ? b.min.x : b.max.x, n.y > 0 ? b.min.y : b.max.y, n.z > 0 ? b.min.z : b.max.z);
    m = std::min(m, (glm::dot(n, v) + f[i].d) / glm::length(n));
  }
  return m;
}

TEST(CullOctant, NeverRejectsWhatPnVertexAcceptsAndCorrectedNeverFalseInside) {
  // A symmetric frustum whose axes are not the world axes, so that an AABB's extents along
  // mirrored plane normals differ (in an axis-aligned symmetric frustum they are equal).
  PerspectiveCamera cam;
  cam.fovy_degrees = 90;
  cam.aspect = 1.3f;
  cam.near_dist = 1;
  cam.far_dist = 12;
  cam.eye = {0, 0, 0};
  cam.target = {0.55f, 0.3f, -1};
  const Frustum f = frustum_from_camera(cam);
  ASSERT_TRUE(is_symmetric(f, 1e-5));
  const OctantCuller c(f);
  const glm::dvec3 centre = frustum_center(f);
  int published_false_inside = 0;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int i = 0; i < 300000; ++i) {
    const float s = static_cast<float>(c.centre_distance());
    const glm::vec3 ctr = glm::vec3(centre) + glm::vec3(u(rng), u(rng), u(rng)) * (2.5f * s);
    // Thin boxes (one small extent) with d2 <= d1 mostly.
    glm::vec3 half(std::abs(u(rng)), std::abs(u(rng)), std::abs(u(rng)));
    half[i % 3] *= 0.05f;
    half *= s * 0.6f;
    const Aabb b{ctr - half, ctr + half};
    const V ref = pn_vertex(f, b);
    const V pub = c.classify(b), cor = c.classify_corrected(b);
    if (ref != V::outside) {
      EXPECT_NE(pub, V::outside);
      EXPECT_NE(cor, V::outside);
    }
    if (min_n_vertex_margin(f, b) < -1e-4 * s) {  // a corner clearly outside: not inside
      published_false_inside += pub == V::inside;
      EXPECT_NE(cor, V::inside);
    }
  }
  // The published test's flaw (the next test pins one case) shows on these thin boxes; were it
  // to vanish, the boxes would no longer reach the precondition's blind spot and the assertions
  // on the corrected test above would test nothing there.
  RecordProperty("octant_published_false_inside", published_false_inside);
  EXPECT_GT(published_false_inside, 0) << "no thin box of 300000 caught the published octant test's false inside";
}

TEST(CullOctant, AsPublishedReportsAThinBoxInsideWhileACornerIsOutside) {
  // Found by the random search above: A&M's fig. 6 precondition holds (d2 = 3.9 <= d1 = 4.6),
  // the box is inside the three outer planes of its octant, but it crosses an inner plane by 0.47.
  PerspectiveCamera cam;
  cam.fovy_degrees = 90;
  cam.aspect = 1.3f;
  cam.near_dist = 1;
  cam.far_dist = 12;
  cam.eye = {0, 0, 0};
  cam.target = {0.55f, 0.3f, -1};
  const Frustum f = frustum_from_camera(cam);
  const OctantCuller c(f);
  const Aabb b{{0x1.50baaep+0f, -0x1.daba8p+0f, -0x1.05a1dp+1f}, {0x1.0786a8p+2f, 0x1.ccb464p+1f, -0x1.d6c746p+0f}};
  const glm::vec3 h = b.half_extent();
  EXPECT_LE(glm::length(h), c.centre_distance()) << "fig. 6 precondition holds";
  EXPECT_LT(min_n_vertex_margin(f, b), -0.4) << "a corner is outside a plane by 0.4";
  EXPECT_EQ(c.classify(b), V::inside) << "as published: false inside";
  EXPECT_EQ(c.classify_corrected(b), V::intersecting);
  EXPECT_EQ(pn_vertex(f, b), V::intersecting);
}

// ---- TR coherency

TEST(CullTrCoherency, PureTranslationUpdatesDistancesExactly) {
  const std::vector<Aabb> boxes = dyadic_boxes(3, 300);
  std::vector<TrObjectState> st(boxes.size());
  TrCoherencyCuller c;
  Frustum f = test::sym90();
  glm::vec3 t(0);
  for (int frame = 0; frame < 6; ++frame) {
    // Translate the frustum by t: plane (n, d) -> (n, d - n.t) (exact on this grid).
    Frustum g = f;
    for (int i = 0; i < 6; ++i) g[i].d = f[i].d - dot(f[i].n, t);
    c.begin_frame(g);
    if (frame > 0) {
      EXPECT_EQ(c.motion(), TrCoherencyCuller::Motion::translation);
    }
    for (std::size_t k = 0; k < boxes.size(); ++k) EXPECT_EQ(c.classify(boxes[k], st[k]), pn_vertex(g, boxes[k]));
    t += glm::vec3(0.5f, -0.25f, -0.75f);
  }
  EXPECT_EQ(c.stats.full_tests, boxes.size());
  EXPECT_EQ(c.stats.translation_updates, 5 * boxes.size());
}

TEST(CullTrCoherency, MovedObjectGetsAFullTest) {
  TrCoherencyCuller c;
  TrObjectState st;
  c.begin_frame(test::sym90());
  EXPECT_EQ(c.classify(test::inside_box(), st), V::inside);
  c.begin_frame(test::sym90());
  EXPECT_EQ(c.motion(), TrCoherencyCuller::Motion::still);
  EXPECT_EQ(c.classify(test::outside_box(), st), V::outside) << "the object moved: full test";
  EXPECT_EQ(c.stats.full_tests, 2u);
  EXPECT_EQ(c.stats.translation_updates, 0u);
}

PerspectiveCamera cam_at_yaw(double yaw_deg) {
  PerspectiveCamera c;
  c.fovy_degrees = 90;
  c.aspect = 1;
  c.near_dist = 1;
  c.far_dist = 100;
  c.eye = {0, 0, 0};
  const double a = glm::radians(yaw_deg);
  c.target = glm::vec3(float(-std::sin(a)), 0.0f, float(-std::cos(a)));  // yaw > 0 turns left
  return c;
}

TEST(CullTrCoherency, RotationKeepsBoxesRightOfTheFrustumOutsideUntilTheLimit) {
  TrCoherencyCuller c;
  TrObjectState st;
  const Aabb right = box({10, -0.5f, -2}, {11, 0.5f, -1});  // far right of the view
  std::uint64_t last_rejects = 0;
  for (int frame = 0; frame <= 4; ++frame) {
    const PerspectiveCamera cam = cam_at_yaw(30.0 * frame);
    const Frustum f = frustum_from_camera(cam);
    c.begin_frame(f, camera_pose(cam));
    const V v = c.classify(right, st);
    EXPECT_NE(pn_vertex(f, right), V::inside);
    EXPECT_EQ(v, V::outside) << "frame " << frame;
    if (frame >= 1) {
      EXPECT_EQ(c.motion(), TrCoherencyCuller::Motion::rotation_y);
      EXPECT_NEAR(c.rotation_limit(), glm::radians(90.0), 1e-4) << "180 - 90 degree opening";
    }
    const bool quick = c.stats.rotation_rejects > last_rejects;
    last_rejects = c.stats.rotation_rejects;
    // Accumulated 30, 60 degrees: quick; 90 degrees reaches the limit: full test.
    if (frame == 1 || frame == 2) {
      EXPECT_TRUE(quick) << "frame " << frame;
    }
    if (frame == 3) {
      EXPECT_FALSE(quick) << "accumulated rotation reached the limit";
    }
  }
}

TEST(CullTrCoherency, RotationTheOtherWayDoesNotReuseTheRightPlane) {
  TrCoherencyCuller c;
  TrObjectState st;
  const Aabb right = box({10, -0.5f, -2}, {11, 0.5f, -1});
  for (int frame = 0; frame <= 1; ++frame) {
    const PerspectiveCamera cam = cam_at_yaw(-20.0 * frame);  // turning right, towards the box
    c.begin_frame(frustum_from_camera(cam), camera_pose(cam));
    c.classify(right, st);
  }
  EXPECT_EQ(c.stats.rotation_rejects, 0u);
  EXPECT_EQ(c.stats.full_tests, 2u);
}

TEST(CullTrCoherency, RefusesAFrustumThatIsNotThePosesPerspectiveFrustum) {
  TrCoherencyCuller c;
  const PerspectiveCamera cam = cam_at_yaw(0);
  try {
    c.begin_frame(test::ortho(), camera_pose(cam));
    FAIL() << "orthographic frustum accepted with a pose";
  } catch (const CullerPreconditionError& e) {
    EXPECT_NE(std::string(e.what()).find("tr-coherency:"), std::string::npos) << e.what();
  }
  CameraPose moved = camera_pose(cam);
  moved.eye = {1, 0, 0};
  EXPECT_THROW(c.begin_frame(frustum_from_camera(cam), moved), CullerPreconditionError);
  // Without a pose, any frustum is fine (translation coherency only).
  EXPECT_NO_THROW(c.begin_frame(test::ortho()));
  EXPECT_NO_THROW(c.begin_frame(test::off_axis()));
}

TEST(CullTrCoherency, RollKeepsBoxesBehindTheNearPlaneOutside) {
  TrCoherencyCuller c;
  TrObjectState st;
  for (int frame = 0; frame <= 3; ++frame) {
    PerspectiveCamera cam = cam_at_yaw(0);
    const double a = glm::radians(50.0 * frame);
    cam.up = glm::vec3(float(-std::sin(a)), float(std::cos(a)), 0.0f);
    c.begin_frame(frustum_from_camera(cam), camera_pose(cam));
    EXPECT_EQ(c.classify(test::behind_box(), st), V::outside);
  }
  EXPECT_EQ(c.motion(), TrCoherencyCuller::Motion::rotation_z);
  EXPECT_EQ(c.stats.rotation_rejects, 3u);
}

}  // namespace
}  // namespace cullproof

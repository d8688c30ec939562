// Frustum construction against hand-computed planes. Every expectation below is worked out in
// the comment beside it from the matrix entries (all exactly representable).
#include "cullproof/core/frustum_build.hpp"

#include <gtest/gtest.h>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>

#include <cmath>
#include <random>

using namespace cullproof;

namespace {

void expect_plane(const Plane& p, float a, float b, float c, float d, const char* what) {
  EXPECT_EQ(p.n.x, a) << what;
  EXPECT_EQ(p.n.y, b) << what;
  EXPECT_EQ(p.n.z, c) << what;
  EXPECT_EQ(p.d, d) << what;
}

bool inside(const Frustum& f, glm::vec3 x) {
  for (const Plane& p : f.planes)
    if (p.eval(x) < 0.0f) return false;
  return true;
}

}  // namespace

// glm::frustum(-1, 1, -1, 1, 1, 3), OpenGL: rows r1 = (1,0,0,0), r2 = (0,1,0,0),
// r3 = (0,0,-(f+n)/(f-n), -2fn/(f-n)) = (0,0,-2,-3), r4 = (0,0,-1,0).
TEST(GribbHartmann, OpenGLPerspectiveRowsByHand) {
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3));
  expect_plane(f[kLeft], 1, 0, -1, 0, "left = r4 + r1");
  expect_plane(f[kRight], -1, 0, -1, 0, "right = r4 - r1");
  expect_plane(f[kBottom], 0, 1, -1, 0, "bottom = r4 + r2");
  expect_plane(f[kTop], 0, -1, -1, 0, "top = r4 - r2");
  expect_plane(f[kNear], 0, 0, -3, -3, "near = r4 + r3: z <= -1");
  expect_plane(f[kFar], 0, 0, 1, 3, "far = r4 - r3: z >= -3");
}

// glm::frustumRH_ZO(-1, 1, -1, 1, 1, 3): r3 = (0,0,f/(n-f), -fn/(f-n)) = (0,0,-1.5,-1.5).
TEST(GribbHartmann, ZeroToOneNearIsRow3) {
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3, {DepthRange::zero_to_one, false}),
                                        {DepthRange::zero_to_one, false});
  expect_plane(f[kNear], 0, 0, -1.5f, -1.5f, "near = r3: z <= -1");
  expect_plane(f[kFar], 0, 0, 0.5f, 1.5f, "far = r4 - r3: z >= -3");
}

// Reversed-Z [0,1]: z' = w - z, so r3' = r4 - r3 = (0,0,0.5,1.5). near = r4 - r3' = r3 and
// far = r3': the same half-spaces as the forward matrix.
TEST(GribbHartmann, ReversedZeroToOneSwapsRoles) {
  const DepthConvention rev{DepthRange::zero_to_one, true};
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3, rev), rev);
  expect_plane(f[kNear], 0, 0, -1.5f, -1.5f, "near");
  expect_plane(f[kFar], 0, 0, 0.5f, 1.5f, "far");
}

// Reversed-Z [-1,1]: z' = -z; near is z' <= w (r4 - r3'), far is z' >= -w (r4 + r3').
TEST(GribbHartmann, ReversedNegativeOneToOne) {
  const DepthConvention rev{DepthRange::negative_one_to_one, true};
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3, rev), rev);
  expect_plane(f[kNear], 0, 0, -3, -3, "near");
  expect_plane(f[kFar], 0, 0, 1, 3, "far");
}

// glm::infinitePerspective: r3 = (0,0,-1,-2n), r4 = (0,0,-1,0), so far = r4 - r3 = (0,0,0,2n):
// exactly "contains all space", even after a view matrix (both rows see the same products).
TEST(GribbHartmann, InfiniteFarContainsAllSpaceWithoutNaN) {
  const glm::mat4 view = glm::lookAtRH(glm::vec3(3, -2, 7), glm::vec3(0.3f, 1.1f, -5), glm::vec3(0, 1, 0));
  const Frustum f = frustum_from_matrix(glm::infinitePerspective(1.0f, 1.5f, 0.25f) * view);
  EXPECT_TRUE(f[kFar].is_degenerate());
  EXPECT_GT(f[kFar].d, 0.0f);
  EXPECT_EQ(f[kFar].d, 0.5f);
  const Frustum nf = f.normalized();
  for (const Plane& p : nf.planes) {
    EXPECT_FALSE(std::isnan(p.d));
    EXPECT_FALSE(std::isnan(p.n.x) || std::isnan(p.n.y) || std::isnan(p.n.z));
  }
  EXPECT_FALSE(is_bounded(f));
  EXPECT_THROW(frustum_corners(f), std::domain_error);
}

// Reversed infinite [0,1]: proj rows r3 = (0,0,-1,-n), r4 = (0,0,-1,0); reversed r3' = (0,0,0,n):
// far = r3' contains all space, near = r4 - r3' = r3 (z <= -n).
TEST(GribbHartmann, ReversedInfiniteZeroToOne) {
  PerspectiveCamera cam;
  cam.far_dist = std::numeric_limits<float>::infinity();
  cam.near_dist = 0.5f;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  const DepthConvention rev{DepthRange::zero_to_one, true};
  const Frustum f = frustum_from_matrix(view_projection(cam, rev), rev);
  EXPECT_TRUE(f[kFar].is_degenerate());
  EXPECT_EQ(f[kFar].d, 0.5f);
  expect_plane(f[kNear], 0, 0, -1, -0.5f, "near");
  EXPECT_TRUE(inside(f, {0, 0, -1e30f}));
  EXPECT_FALSE(inside(f, {0, 0, -0.25f}));
}

// glm::orthoRH_NO(-2, 2, -1, 1, 1, 5): r1 = (0.5,0,0,0), r2 = (0,1,0,0), r3 = (0,0,-0.5,-1.5),
// r4 = (0,0,0,1).
TEST(GribbHartmann, OrthographicByHand) {
  const Frustum f = frustum_from_matrix(orthographic_projection(-2, 2, -1, 1, 1, 5));
  expect_plane(f[kLeft], 0.5f, 0, 0, 1, "x >= -2");
  expect_plane(f[kRight], -0.5f, 0, 0, 1, "x <= 2");
  expect_plane(f[kBottom], 0, 1, 0, 1, "y >= -1");
  expect_plane(f[kTop], 0, -1, 0, 1, "y <= 1");
  expect_plane(f[kNear], 0, 0, -0.5f, -0.5f, "z <= -1");
  expect_plane(f[kFar], 0, 0, 0.5f, 2.5f, "z >= -5");
  EXPECT_TRUE(is_symmetric(f));
}

// glm::frustum(-1, 3, -1, 1, 1, 10): r1 = (2n/(r-l), 0, (r+l)/(r-l), 0) = (0.5, 0, 0.5, 0).
TEST(GribbHartmann, OffAxisByHand) {
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 3, -1, 1, 1, 10));
  expect_plane(f[kLeft], 0.5f, 0, -0.5f, 0, "x >= z: x >= -1 at z = -1");
  expect_plane(f[kRight], -0.5f, 0, -1.5f, 0, "x <= -3z: x <= 3 at z = -1");
  EXPECT_FALSE(is_symmetric(f));
}

TEST(Corners, SymmetricFrustumByHand) {
  const Frustum f = frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3));
  const auto c = frustum_corners(f);
  EXPECT_EQ(c[0], glm::dvec3(-1, -1, -1));  // left bottom near
  EXPECT_EQ(c[3], glm::dvec3(1, 1, -1));    // right top near
  EXPECT_EQ(c[4], glm::dvec3(-3, -3, -3));  // left bottom far
  EXPECT_EQ(c[7], glm::dvec3(3, 3, -3));    // right top far
  EXPECT_TRUE(is_symmetric(f));
  EXPECT_EQ(frustum_center(f), glm::dvec3(0, 0, -2));
}

TEST(Corners, RotatedSymmetricFrustumStaysSymmetric) {
  PerspectiveCamera cam;
  cam.eye = {10, -4, 3};
  cam.target = {-2, 7, 1};
  cam.up = {0.3f, 0.2f, 1.0f};
  cam.fovy_degrees = 70;
  cam.aspect = 1.7f;
  EXPECT_TRUE(is_symmetric(frustum_from_camera(cam)));
  EXPECT_TRUE(is_symmetric(frustum_from_matrix(view_projection(cam))));
}

// The geometric construction (Lighthouse3D, double internally, rounded once to float) and the
// Gribb–Hartmann route (float matrix products, then normalised) describe the same camera; they
// differ by float rounding only. Tolerance: normals within 1e-4 (a few hundred ulps of the float
// matrix pipeline: lookAt, perspective and the product each round), offsets within
// 1e-4 * (|eye| + far), the scale of the numbers the offset is computed from.
TEST(GeometricConstruction, AgreesWithMatrixRouteWithinFloatTolerance) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> pos(-100, 100), fov(10, 150), asp(0.3f, 3), nr(0.05f, 2);
  for (int i = 0; i < 2000; ++i) {
    PerspectiveCamera cam;
    cam.eye = {pos(rng), pos(rng), pos(rng)};
    cam.target = cam.eye + glm::vec3(pos(rng), pos(rng), pos(rng));
    cam.up = glm::vec3(pos(rng), pos(rng), pos(rng));
    if (glm::length(glm::cross(glm::normalize(cam.target - cam.eye), glm::normalize(cam.up))) < 0.1f) continue;
    cam.fovy_degrees = fov(rng);
    cam.aspect = asp(rng);
    cam.near_dist = nr(rng);
    cam.far_dist = cam.near_dist * 50;
    const Frustum g = frustum_from_camera(cam);
    const Frustum m = frustum_from_matrix(view_projection(cam)).normalized();
    const float scale = glm::length(cam.eye) + cam.far_dist;
    for (int k = 0; k < 6; ++k) {
      EXPECT_LT(glm::length(g[k].n - m[k].n), 1e-4f) << "camera " << i << " plane " << plane_name(k);
      EXPECT_LT(std::abs(g[k].d - m[k].d), 1e-4f * scale) << "camera " << i << " plane " << plane_name(k);
    }
  }
}

TEST(GeometricConstruction, InfiniteFarAndInvalidCameras) {
  PerspectiveCamera cam;
  cam.far_dist = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(frustum_from_camera(cam)[kFar].is_degenerate());
  PerspectiveCamera bad = cam;
  bad.fovy_degrees = 180;
  EXPECT_THROW(frustum_from_camera(bad), ValidationError);
  bad = cam;
  bad.up = {0, 0, -1};  // parallel to the view direction
  try {
    frustum_from_camera(bad);
    FAIL() << "expected a ValidationError";
  } catch (const ValidationError& e) {
    EXPECT_NE(std::string(e.what()).find("camera.up"), std::string::npos) << e.what();
  }
}

// Hoff camera, COP (0.5, 0, 2), window [-1,1]^2 on z = 0. Left plane through the COP and the
// edge x = -1: n = (cz, 0, wl - cx) = (2, 0, -1.5), |n| = 2.5 -> (0.8, 0, -0.6), d = -n.cop/2.5
// = -(1 - 3)/2.5 = 0.8.
TEST(HoffCamera, OffAxisCopByHand) {
  HoffCamera c;
  c.cop = {0.5f, 0.0f, 2.0f};
  c.window_left = -1;
  c.window_right = 1;
  c.window_bottom = -1;
  c.window_top = 1;
  c.near_z = 1.0f;
  c.far_z = -10.0f;
  const Frustum f = frustum_from_hoff_camera(c);
  EXPECT_FLOAT_EQ(f[kLeft].n.x, 0.8f);
  EXPECT_FLOAT_EQ(f[kLeft].n.z, -0.6f);
  EXPECT_FLOAT_EQ(f[kLeft].d, 0.8f);
  EXPECT_NEAR(f[kLeft].eval({-1, 0.3f, 0}), 0.0f, 1e-6f);  // the window edge lies on it
  EXPECT_NEAR(f[kRight].eval({1, -0.7f, 0}), 0.0f, 1e-6f);
  EXPECT_NEAR(f[kNear].eval({0, 0, 1}), 0.0f, 1e-6f);
  EXPECT_FALSE(is_symmetric(f));
  c.cop.x = 0.0f;
  EXPECT_TRUE(is_symmetric(frustum_from_hoff_camera(c)));
}

TEST(HoffCamera, WorldPlacementMovesPlanes) {
  HoffCamera c;
  c.origin = {10, 0, 0};
  c.horizon = {0, 0, -1};  // camera rotated 90 degrees about y
  c.view_up = {0, 1, 0};
  c.vpn = {1, 0, 0};
  const Frustum f = frustum_from_hoff_camera(c);
  // The camera looks along -vpn = -x from x = 10: a point at x = 5 on the axis is inside.
  EXPECT_TRUE(inside(f, {5, 0, 0}));
  EXPECT_FALSE(inside(f, {15, 0, 0}));
  EXPECT_EQ(hoff_cop_world(c), glm::vec3(11, 0, 0));
}

TEST(Stereo, EyesAreMirroredOffAxisFrustaMeetingAtConvergence) {
  StereoRig rig;
  rig.center.eye = {0, 0, 0};
  rig.center.target = {0, 0, -1};
  rig.center.near_dist = 0.5f;
  rig.center.far_dist = 50;
  rig.eye_separation = 0.2f;
  rig.convergence = 4.0f;
  const auto m = stereo_view_projections(rig);
  const Frustum l = frustum_from_matrix(m[0]).normalized(), r = frustum_from_matrix(m[1]).normalized();
  EXPECT_FALSE(is_symmetric(l));
  EXPECT_FALSE(is_symmetric(r));
  // x where a side plane crosses the line y = 0, z = -convergence: both eyes agree there.
  auto x_at = [](const Plane& p, float z) { return -(p.n.z * z + p.d) / p.n.x; };
  EXPECT_NEAR(x_at(l[kLeft], -4), x_at(r[kLeft], -4), 1e-5f);
  EXPECT_NEAR(x_at(l[kRight], -4), x_at(r[kRight], -4), 1e-5f);
  // Mirror images: left eye's left edge at the near plane mirrors the right eye's right edge.
  EXPECT_NEAR(x_at(l[kLeft], -0.5f), -x_at(r[kRight], -0.5f), 1e-5f);
}

// The p-vertex post: planes from M V P evaluated at a local point equal the world planes at the
// transformed point, so boxes can be tested in their own space.
TEST(LocalFrustum, PlanesInObjectSpace) {
  const glm::mat4 vp = off_axis_projection(-1, 1, -1, 1, 1, 3);
  const glm::mat4 model = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f, 0.0f, -2.0f));
  const Frustum world = frustum_from_matrix(vp), local = local_frustum(vp, model);
  const glm::vec3 p_local(0.25f, 0.5f, 0.0f), p_world = glm::vec3(model * glm::vec4(p_local, 1.0f));
  for (int k = 0; k < 6; ++k) EXPECT_FLOAT_EQ(local[k].eval(p_local), world[k].eval(p_world)) << plane_name(k);
}

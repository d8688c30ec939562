// Certified conservative cullers on hand-made cases, and the SIMD batch against the scalar
// functions bit for bit. The oracle-backed guarantees are in tests/harness (every family) and
// test_certified_fma (with FMA contraction).
#include "cullproof/certified.hpp"
#include "cullproof/certified_batch.hpp"
#include "cullproof/cull.hpp"
#include "cullproof/frustum_build.hpp"
#include "cullproof/methods.hpp"

#include <gtest/gtest.h>
#include <glm/ext/matrix_transform.hpp>

#include <limits>
#include <random>

using namespace cullproof;
using V = Visibility;

namespace {

// glm::frustum(-1, 1, -1, 1, 1, 3): |x|, |y| <= -z, z in [-3, -1]; exact integer planes.
Frustum F() { return frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 3)); }

}  // namespace

TEST(Certified, ClearCasesAreDecided) {
  const CertifiedFrustum f = certify_planes(F());
  EXPECT_EQ(certified_pn_vertex(f, Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}}), V::inside);
  EXPECT_EQ(certified_pn_vertex(f, Aabb{{-0.5f, -0.5f, -10}, {0.5f, 0.5f, -5}}), V::outside);
  EXPECT_EQ(certified_pn_vertex(f, Aabb{{-0.5f, -0.5f, -2.5f}, {5, 0.5f, -1.5f}}), V::intersecting);
  EXPECT_EQ(certified_point(f, Point{0, 0, -2}), V::inside);
  EXPECT_EQ(certified_point(f, Point{0, 0, 2}), V::outside);
  EXPECT_EQ(certified_sphere(f, Sphere{{0, 0, -2}, 0.25f}), V::inside);
  EXPECT_EQ(certified_sphere(f, Sphere{{0, 0, 5}, 1}), V::outside);
  EXPECT_EQ(certified_obb_pn_vertex(f, to_obb(Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}})), V::inside);
  EXPECT_EQ(certified_sat(f, to_obb(Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}})), V::inside);
}

// Touching exactly: the truth is intersecting (from outside) or inside (from inside); a
// certified test may not say outside, and says intersecting when the margin cannot separate.
TEST(Certified, TouchingIsNeverRejected) {
  const CertifiedFrustum f = certify_planes(F());
  const Aabb near_face{{-0.5f, -0.5f, -1}, {0.5f, 0.5f, 0}};       // shares the face z = -1
  const Aabb far_corner{{3, 3, -4}, {4, 4, -3}};                    // shares the corner (3, 3, -3)
  const Aabb inside_touch{{-0.5f, -0.5f, -2}, {0.5f, 0.5f, -1}};    // inside, touching near
  EXPECT_EQ(certified_pn_vertex(f, near_face), V::intersecting);
  EXPECT_EQ(certified_pn_vertex(f, far_corner), V::intersecting);
  EXPECT_EQ(certified_pn_vertex(f, inside_touch), V::intersecting);  // under-inside: allowed
  EXPECT_EQ(certified_point(f, Point{0.5f, 0, -1}), V::intersecting);  // on the near plane
  EXPECT_EQ(certified_sphere(f, Sphere{{0, 0, -0.5f}, 0.5f}), V::intersecting);
  EXPECT_EQ(certified_sat(f, to_obb(far_corner)), V::intersecting);
}

// The float culler rejects this: the box's near face sits one ulp inside the true near plane,
// but the extracted float plane, rounded from a matrix, puts it outside. End to end, the
// certified test bounds the extraction error and does not reject. Here the near plane is
// z <= -n with n = 0.1 (not representable), from a [0, 1] projection where the near plane is a
// single matrix row (exact) and the far plane the difference r4 - r3 (rounded).
TEST(Certified, EndToEndBoundsTheExtractionError) {
  const glm::mat4 m = off_axis_projection(-0.1f, 0.1f, -0.1f, 0.1f, 0.1f, 1000.0f, {DepthRange::zero_to_one, false});
  const CertifiedFrustum e2e = certify_matrix(m, {DepthRange::zero_to_one, false});
  const CertifiedFrustum as_planes = certify_planes(frustum_from_matrix(m, {DepthRange::zero_to_one, false}));
  // The far plane's float coefficients carry a rounding error; its bound is larger than |plane|.
  EXPECT_GT(e2e.bound[kFar].w, std::abs(e2e.planes[kFar].d) * 0.99f);
  EXPECT_GE(e2e.bound_sum[kFar], as_planes.bound_sum[kFar]);
  // A box straddling nothing far from every plane is decided the same either way.
  const Aabb mid{{-1, -1, -500}, {1, 1, -400}};
  EXPECT_EQ(certified_pn_vertex(e2e, mid), certified_pn_vertex(as_planes, mid));
}

TEST(Certified, DegeneratePlanesAreDecidedExactly) {
  Frustum f = F();
  f[kFar] = Plane{glm::vec3(0.0f), 1.0f};  // all space
  EXPECT_EQ(certified_pn_vertex(certify_planes(f), Aabb{{-1, -1, -1e30f}, {1, 1, -1e29f}}), V::inside);
  EXPECT_EQ(certified_point(certify_planes(f), Point{0, 0, -1e6f}), V::inside);
  f[kFar] = Plane{glm::vec3(0.0f), -1.0f};  // nothing
  EXPECT_EQ(certified_pn_vertex(certify_planes(f), Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}}), V::outside);
}

TEST(Certified, HugeCoordinatesNeverOverflowIntoAVerdict) {
  const float big = std::numeric_limits<float>::max();
  const CertifiedFrustum f = certify_planes(F());
  // Products overflow to infinity: the guarded path answers intersecting, never a false verdict.
  EXPECT_EQ(certified_pn_vertex(f, Aabb{{-big, -big, -big}, {big, big, big}}), V::intersecting);
  EXPECT_EQ(certified_sphere(f, Sphere{{0, 0, -2}, big}), V::intersecting);
  // With an infinite far plane the point (0, 0, -max) is inside, but the near plane's value
  // -3 z - 3 overflows: that plane is left undecided rather than trusted.
  Frustum open = F();
  open[kFar] = Plane{glm::vec3(0.0f), 1.0f};
  EXPECT_EQ(certified_point(certify_planes(open), Point{0, 0, -big}), V::intersecting);
  // (max, 0, -max) lies beyond the far plane z >= -3, which evaluates without overflow: outside.
  EXPECT_EQ(certified_point(f, Point{big, 0, -big}), V::outside);
  EXPECT_GT(f.m_safe, 1e30f);
}

TEST(CertifiedBatch, SameVerdictsAsScalarBitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-6, 6), size(0.0f, 1.5f), logm(-3, 38);
  PerspectiveCamera cam;
  cam.eye = {1, 2, 3};
  cam.target = {0, 0, -2};
  const glm::mat4 vp = view_projection(cam, {DepthRange::zero_to_one, true});
  for (const CertifiedFrustum& f : {certify_planes(F()), certify_matrix(vp, {DepthRange::zero_to_one, true})}) {
    const std::size_t n = 64 * 37 + 23;  // full words and a tail
    std::vector<float> a[6], s[4];
    for (auto& v : a) v.resize(n);
    for (auto& v : s) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      // Every 50th volume is astronomically large (the unsafe path).
      const float scale = i % 50 == 0 ? std::pow(10.0f, logm(rng)) : 1.0f;
      const float centre[3] = {pos(rng) / 2, pos(rng) / 2, -2.0f + pos(rng) / 5};
      for (int k = 0; k < 3; ++k) {
        const float c = centre[k] * scale, h = size(rng) * scale * 0.3f;
        a[k][i] = c - h;
        a[3 + k][i] = c + h;
        s[k][i] = c;
      }
      s[3][i] = size(rng) * scale;
      if (i % 7 == 3) {  // within the margin of the near plane z <= -1: the margin decides
        a[2][i] = -1.0f + float(int(i % 5) - 2) * 0x1p-23f;
        a[5][i] = a[2][i] + 0.5f;
        s[2][i] = a[2][i] + s[3][i];
      }
    }
    const AabbSoa boxes{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), n};
    const SphereSoa spheres{s[0].data(), s[1].data(), s[2].data(), s[3].data(), n};
    std::vector<std::uint64_t> vis(bitset_words(n)), ins(bitset_words(n)), svis(bitset_words(n)), sins(bitset_words(n));
    certified_cull_aabbs_bitset(f, boxes, vis.data(), ins.data());
    certified_cull_spheres_bitset(f, spheres, svis.data(), sins.data());
    int outside = 0, inside = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const V v = certified_pn_vertex(f, Aabb{{a[0][i], a[1][i], a[2][i]}, {a[3][i], a[4][i], a[5][i]}});
      const bool bv = (vis[i / 64] >> (i % 64)) & 1u, bi = (ins[i / 64] >> (i % 64)) & 1u;
      ASSERT_EQ(bv, v != V::outside) << "box " << i;
      ASSERT_EQ(bi, v == V::inside) << "box " << i;
      outside += v == V::outside;
      inside += v == V::inside;
      const V w = certified_sphere(f, Sphere{{s[0][i], s[1][i], s[2][i]}, s[3][i]});
      ASSERT_EQ(bool((svis[i / 64] >> (i % 64)) & 1u), w != V::outside) << "sphere " << i;
      ASSERT_EQ(bool((sins[i / 64] >> (i % 64)) & 1u), w == V::inside) << "sphere " << i;
    }
    EXPECT_GT(outside, 50);  // the data exercises every verdict
    EXPECT_GT(inside, 10);
  }
}

TEST(Certified, RegisteredWithTheCertifiedClaim) {
  for (const char* name : {"point-certified", "sphere-certified", "pn-vertex-certified", "obb-pn-vertex-certified",
                           "pn-vertex-batch-certified", "sphere-batch-certified", "sat-certified"}) {
    const Method* m = find_method(name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->claim, Claim::certified_conservative) << name;
    EXPECT_FALSE(m->published) << name;
  }
}

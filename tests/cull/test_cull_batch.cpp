// Unit tests of the SIMD batch cullers (cullproof/simd/cull_batch.hpp): bit-for-bit the scalar
// verdicts on random input, including boxes and spheres touching planes exactly.
#include <gtest/gtest.h>

#include "cull_fixtures.hpp"
#include "cullproof/simd/cull_batch.hpp"

#include <random>

namespace cullproof {
namespace {

using V = Visibility;

struct SoaBoxes {
  std::vector<float> a[6];
  AabbSoa view() const {
    return AabbSoa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), a[0].size()};
  }
  Aabb at(std::size_t i) const {
    return Aabb{{a[0][i], a[1][i], a[2][i]}, {a[3][i], a[4][i], a[5][i]}};
  }
  void push(const Aabb& b) {
    for (int k = 0; k < 3; ++k) {
      a[k].push_back(b.min[k]);
      a[3 + k].push_back(b.max[k]);
    }
  }
};

SoaBoxes random_boxes(std::uint32_t seed, std::size_t n) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> c(-15, 15), e(0, 4);
  std::uniform_int_distribution<int> g(-12 * 8, 12 * 8), kind(0, 3);
  SoaBoxes s;
  for (std::size_t i = 0; i < n; ++i) {
    if (kind(rng) == 0) {  // on a 1/8 grid: many boxes touch sym90's planes exactly
      const glm::vec3 lo(g(rng) / 8.0f, g(rng) / 8.0f, g(rng) / 8.0f);
      s.push(Aabb{lo, lo + glm::vec3(float(g(rng) & 15) / 8.0f, float(g(rng) & 15) / 8.0f, float(g(rng) & 15) / 8.0f)});
    } else {
      const glm::vec3 lo(c(rng), c(rng), c(rng) - 5);
      s.push(Aabb{lo, lo + glm::vec3(e(rng), e(rng), e(rng))});
    }
  }
  return s;
}

std::vector<Frustum> frusta() {
  std::vector<Frustum> out = {test::sym90(), test::sym90_infinite(), test::ortho(), test::off_axis()};
  Frustum empty = test::sym90();
  empty[kFar] = Plane{{0, 0, 0}, -1};  // contains nothing
  out.push_back(empty);
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> u(-1, 1);
  for (int r = 0; r < 5; ++r) {  // arbitrary planes, zero components included
    Frustum f;
    for (int i = 0; i < 6; ++i) f[i] = Plane{{u(rng), (r & 1) ? 0.0f : u(rng), u(rng)}, 10 * u(rng)};
    out.push_back(f);
  }
  return out;
}

TEST(CullBatch, AabbBitsetEqualsScalarPnVertexBitForBit) {
  for (std::size_t n : {0u, 1u, 63u, 64u, 65u, 1000u, 4099u}) {
    const SoaBoxes s = random_boxes(static_cast<std::uint32_t>(n), n);
    for (const Frustum& f : frusta()) {
      std::vector<std::uint64_t> vis(bitset_words(n) + 1, ~0ull), ins(bitset_words(n) + 1, ~0ull),
          only(bitset_words(n) + 1, ~0ull), scalar(bitset_words(n) + 1, ~0ull);
      classify_aabbs_bitset(f, s.view(), vis.data(), ins.data());
      cull_aabbs_bitset(f, s.view(), only.data());
      cull_aabbs_bitset_scalar(f, s.view(), scalar.data());
      std::size_t mismatches = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const V ref = pn_vertex(f, s.at(i));
        const bool v = (vis[i / 64] >> (i % 64)) & 1u, in = (ins[i / 64] >> (i % 64)) & 1u;
        const bool o = (only[i / 64] >> (i % 64)) & 1u, sc = (scalar[i / 64] >> (i % 64)) & 1u;
        mismatches += v != (ref != V::outside) || in != (ref == V::inside) || o != v || sc != v;
      }
      EXPECT_EQ(mismatches, 0u) << "n = " << n;
      if (n % 64) {
        EXPECT_EQ(vis[n / 64] >> (n % 64), 0u) << "bits past count are zero";
      }
      std::vector<std::uint32_t> idx(n + 1);
      const std::size_t k = cull_aabbs_indices(f, s.view(), idx.data());
      std::size_t expect = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (pn_vertex(f, s.at(i)) != V::outside) {
          ASSERT_LT(expect, k);
          EXPECT_EQ(idx[expect++], i);
        }
      EXPECT_EQ(k, expect);
    }
  }
}

TEST(CullBatch, SphereBitsetEqualsScalarSpherePlaneBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> c(-15, 15), r(0, 3);
  std::uniform_int_distribution<int> g(-12 * 8, 12 * 8);
  for (std::size_t n : {0u, 5u, 64u, 130u, 3001u}) {
    std::vector<float> x(n), y(n), z(n), rad(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (i % 4 == 0) {  // grid: exact touching against the orthographic box
        x[i] = g(rng) / 8.0f; y[i] = g(rng) / 8.0f; z[i] = g(rng) / 8.0f; rad[i] = float(g(rng) & 15) / 8.0f;
      } else {
        x[i] = c(rng); y[i] = c(rng); z[i] = c(rng) - 5; rad[i] = r(rng);
      }
    }
    const SphereSoa s{x.data(), y.data(), z.data(), rad.data(), n};
    for (const Frustum& raw : frusta()) {
      const Frustum f = raw.normalized();
      std::vector<std::uint64_t> vis(bitset_words(n) + 1), ins(bitset_words(n) + 1), only(bitset_words(n) + 1);
      classify_spheres_bitset(f, s, vis.data(), ins.data());
      cull_spheres_bitset(f, s, only.data());
      std::size_t mismatches = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const V ref = sphere_plane_test(f, Sphere{{x[i], y[i], z[i]}, rad[i]});
        const bool v = (vis[i / 64] >> (i % 64)) & 1u, in = (ins[i / 64] >> (i % 64)) & 1u;
        const bool o = (only[i / 64] >> (i % 64)) & 1u;
        mismatches += v != (ref != V::outside) || in != (ref == V::inside) || o != v;
      }
      EXPECT_EQ(mismatches, 0u) << "n = " << n;
      std::vector<std::uint32_t> idx(n + 1);
      std::size_t expect = 0;
      for (std::size_t i = 0; i < n; ++i) expect += sphere_plane_test(f, Sphere{{x[i], y[i], z[i]}, rad[i]}) != V::outside;
      EXPECT_EQ(cull_spheres_indices(f, s, idx.data()), expect);
    }
  }
}

TEST(CullBatch, TouchingBoxAndSphereAreVisible) {
  SoaBoxes s;
  for (int i = 0; i < 64; ++i) s.push(test::touch_near_outside_box());
  std::uint64_t vis = 0, ins = 0;
  classify_aabbs_bitset(test::sym90(), s.view(), &vis, &ins);
  EXPECT_EQ(vis, ~0ull) << "box touching near from outside is intersecting";
  EXPECT_EQ(ins, 0ull);
}

TEST(CullBatch, ReportsTheDispatchedTarget) {
  const char* t = batch_simd_target();
  ASSERT_NE(t, nullptr);
  EXPECT_GT(std::string(t).size(), 0u);
  std::printf("batch SIMD target: %s\n", t);
}

}  // namespace
}  // namespace cullproof

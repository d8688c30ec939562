// Certified conservative cullers on hand-made cases, and the SIMD batch against the scalar
// functions bit for bit. The oracle-backed guarantees are in tests/harness (every family) and
// test_certified_fma (with FMA contraction).
#include "cullproof/core/certified.hpp"
#include "cullproof/simd/certified_batch.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/methods/methods.hpp"

#include <gtest/gtest.h>
#include <hwy/targets.h>
#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

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
  EXPECT_GT(e2e.data().bound[kFar].w, std::abs(e2e.data().planes[kFar].d) * 0.99f);
  EXPECT_GE(e2e.data().bound_sum[kFar], as_planes.data().bound_sum[kFar]);
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
  EXPECT_GT(f.data().m_safe, 1e30f);
}

// A scalar model of the SIMD kernels' operations (src/simd/batch_certified.cpp): the fast
// path's scaled planes, M, T = fl(t M) and plane values as three fused multiply-adds (the batch
// fuses them on every target: in SIMD where the target has FMA, volume by volume otherwise).
float mul_add(float a, float b, float c) { return std::fma(a, b, c); }
float plane3(const CertifiedPlane& p, float d, float x, float y, float z) {
  return mul_add(p.nz, z, mul_add(p.ny, y, mul_add(p.nx, x, d)));
}

V model_box(const CertifiedFrustum& frustum, const Aabb& b) {
  const CertifiedFrustum::Data& f = frustum.data();
  if (f.empty) return V::outside;
  const float m = std::max({std::abs(b.min.x), std::abs(b.min.y), std::abs(b.min.z), std::abs(b.max.x),
                            std::abs(b.max.y), std::abs(b.max.z)});
  if (!(m <= f.m_safe)) return certified_pn_vertex(frustum, b);  // the kernel hands these lanes over
  const float t = f.t_box * m;
  bool outside = false, inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_box[std::size_t(i)];
    const glm::vec3 pv(p.nx >= 0 ? b.max.x : b.min.x, p.ny >= 0 ? b.max.y : b.min.y, p.nz >= 0 ? b.max.z : b.min.z);
    const glm::vec3 nv(p.nx >= 0 ? b.min.x : b.max.x, p.ny >= 0 ? b.min.y : b.max.y, p.nz >= 0 ? b.min.z : b.max.z);
    outside = outside || plane3(p, p.d_out, pv.x, pv.y, pv.z) < -t;
    inside = inside && plane3(p, p.d_in, nv.x, nv.y, nv.z) >= t;
  }
  return outside ? V::outside : inside ? V::inside : V::intersecting;
}

V model_sphere(const CertifiedFrustum& frustum, const Sphere& s) {
  const CertifiedFrustum::Data& f = frustum.data();
  if (f.empty) return V::outside;
  const glm::vec3& c = s.center;
  const float m = std::max(std::abs(c.x), std::max(std::abs(c.y), std::abs(c.z))) + s.radius;
  if (!(m <= f.m_safe)) return certified_sphere(frustum, s);
  const float t = f.t_sphere * m;
  bool outside = false, inside = true;
  for (int i = 0; i < f.active_count; ++i) {
    const CertifiedPlane& p = f.fast_sphere[std::size_t(i)];
    outside = outside || mul_add(s.radius, p.norm, plane3(p, p.d_out, c.x, c.y, c.z)) < -t;
    inside = inside && mul_add(-s.radius, p.norm, plane3(p, p.d_in, c.x, c.y, c.z)) >= t;
  }
  return outside ? V::outside : inside ? V::inside : V::intersecting;
}

// The frusta of the batch tests: a perspective frustum (planes given, and end to end from a
// reversed-Z matrix), one with an infinite far plane (five active planes: the kernels' general
// loop), and an axis-aligned box (no two normals in opposite octants: M from the six arrays).
std::vector<CertifiedFrustum> batch_frusta() {
  PerspectiveCamera cam;
  cam.eye = {1, 2, 3};
  cam.target = {0, 0, -2};
  const glm::mat4 vp = view_projection(cam, {DepthRange::zero_to_one, true});
  Frustum open = F();
  open[kFar] = Plane{glm::vec3(0.0f), 1.0f};
  Frustum box;
  box[kLeft] = Plane{{1, 0, 0}, 1};
  box[kRight] = Plane{{-1, 0, 0}, 1};
  box[kBottom] = Plane{{0, 1, 0}, 1};
  box[kTop] = Plane{{0, -1, 0}, 1};
  box[kNear] = Plane{{0, 0, -1}, -1};
  box[kFar] = Plane{{0, 0, 1}, 3};
  return {certify_planes(F()), certify_matrix(vp, {DepthRange::zero_to_one, true}), certify_planes(open),
          certify_planes(box)};
}

// Random volumes near F() moved by `o`, every 50th astronomically large (the scalar hand-over),
// two in seven a few ulps outside or inside the near plane z = -1 (moved), where the margin
// decides. Moving F() far along an axis makes that axis's min or max array the largest
// coordinate, so M must read every array.
struct BatchData {
  std::size_t n = 64 * 37 + 23;  // full words and a tail
  std::vector<float> a[6], s[4];
  // wide: for the frustum wide_box(); the margin cases then stretch one of the six arrays to
  // magnitude 4000 (a different one case by case), so that M comes from that array alone.
  explicit BatchData(glm::vec3 o = glm::vec3(0.0f), bool wide = false) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-6, 6), size(0.0f, 1.5f), logm(-3, 38);
    for (auto& v : a) v.resize(n);
    for (auto& v : s) v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float scale = i % 50 == 0 ? std::pow(10.0f, logm(rng)) : 1.0f;
      const float centre[3] = {pos(rng) / 2, pos(rng) / 2, -2.0f + pos(rng) / 5};
      for (int k = 0; k < 3; ++k) {
        const float c = centre[k] * scale, h = size(rng) * scale * 0.3f;
        a[k][i] = o[k] + (c - h);
        a[3 + k][i] = o[k] + (c + h);
        s[k][i] = o[k] + c;
      }
      s[3][i] = size(rng) * scale;
      if (i % 7 == 3 || i % 7 == 5) {  // near the axis, a few ulps from the near plane z = -1
        for (int k = 0; k < 2; ++k) {
          a[k][i] = o[k] - 0.125f;
          a[3 + k][i] = o[k] + 0.125f;
          s[k][i] = o[k];
        }
        s[3][i] = 0.25f;
        const float plane = o.z - 1.0f;  // exact: small integers
        float z = plane;
        const bool out = i % 7 == 3;
        for (std::size_t k = 0; k <= i % 5; ++k) z = std::nextafter(z, out ? HUGE_VALF : -HUGE_VALF);
        if (wide) z = plane + (out ? 1.0f : -1.0f) * std::ldexp(1.0f, int(i % 17) - 23);  // 2^-23 .. 2^-7
        if (out) {  // outside by a few ulps: in the margin of "outside"
          a[2][i] = z;
          a[5][i] = z + 0.5f;
          s[2][i] = z + 0.25f;
        } else {  // inside by a few ulps: in the margin of "inside"
          a[5][i] = z;
          a[2][i] = z - 0.5f;
          s[2][i] = z - 0.25f;
        }
        if (wide) {
          const int which = int(i / 7) % 5;  // 0-3: min/max of x/y, 4: z (max when out, min when in)
          if (which < 4) (which % 2 ? a[3 + which / 2] : a[which / 2])[i] = which % 2 ? 4000.0f : -4000.0f;
          else (out ? a[5] : a[2])[i] = out ? 4000.0f : -4000.0f;
        }
      }
    }
  }
  Aabb box(std::size_t i) const { return Aabb{{a[0][i], a[1][i], a[2][i]}, {a[3][i], a[4][i], a[5][i]}}; }
  Sphere sphere(std::size_t i) const { return Sphere{{s[0][i], s[1][i], s[2][i]}, s[3][i]}; }
  AabbSoa boxes() const { return {a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), n}; }
  SphereSoa spheres() const { return {s[0].data(), s[1].data(), s[2].data(), s[3].data(), n}; }
};

// F() moved by o (exact: integer planes, integer offsets).
Frustum moved(Frustum f, glm::vec3 o) {
  for (int k = 0; k < 6; ++k) f[k].d -= glm::dot(f[k].n, o);
  return f;
}

// x, y in [-5000, 5000], z in [-5000, -1]: room for boxes 4000 long touching the near plane.
// tilted: the side planes x = -+5000 lean by 2^-12 (never near the test boxes) so that their
// normals lie in opposite octants (the kernels' M from two planes' loads); upright, no two
// normals do (M from the six arrays).
Frustum wide_box(bool tilted) {
  const float e = tilted ? 0x1p-12f : 0.0f;
  Frustum f;
  f[kLeft] = Plane{{1, e, e}, 5000};
  f[kRight] = Plane{{-1, -e, -e}, 5000};
  f[kBottom] = Plane{{0, 1, 0}, 5000};
  f[kTop] = Plane{{0, -1, 0}, 5000};
  f[kNear] = Plane{{0, 0, -1}, -1};
  f[kFar] = Plane{{0, 0, 1}, 5000};
  return f;
}

// Each case: a frustum and data around it.
std::vector<std::pair<CertifiedFrustum, BatchData>> batch_cases() {
  std::vector<std::pair<CertifiedFrustum, BatchData>> out;
  for (const CertifiedFrustum& f : batch_frusta()) out.emplace_back(f, BatchData());
  for (bool tilted : {false, true}) out.emplace_back(certify_planes(wide_box(tilted)), BatchData(glm::vec3(0.0f), true));
  for (int axis = 0; axis < 3; ++axis)
    for (float sign : {-1.0f, 1.0f}) {
      glm::vec3 o(0.0f);
      o[axis] = 4096.0f * sign;
      out.emplace_back(certify_planes(moved(F(), o)), BatchData(o));
    }
  return out;
}

bool bit(const std::vector<std::uint64_t>& v, std::size_t i) { return (v[i / 64] >> (i % 64)) & 1u; }

TEST(CertifiedBatch, EqualsItsScalarModelBitForBit) {
  const auto cases = batch_cases();
  // Every SIMD target this machine runs (without FMA: the volume-by-volume path).
  for (const std::int64_t target : hwy::SupportedAndGeneratedTargets()) {
  hwy::SetSupportedTargetsForTest(target);
  SCOPED_TRACE(hwy::TargetName(target));
  for (const auto& [f, x] : cases) {
    std::vector<std::uint64_t> vis(bitset_words(x.n)), ins(bitset_words(x.n)), svis(bitset_words(x.n)),
        sins(bitset_words(x.n)), vis_only(bitset_words(x.n));
    certified_cull_aabbs_bitset(f, x.boxes(), vis.data(), ins.data());
    certified_cull_aabbs_bitset(f, x.boxes(), vis_only.data());
    certified_cull_spheres_bitset(f, x.spheres(), svis.data(), sins.data());
    int outside = 0, inside = 0;
    for (std::size_t i = 0; i < x.n; ++i) {
      const V v = model_box(f, x.box(i));
      ASSERT_EQ(bit(vis, i), v != V::outside) << "box " << i << " of " << f.data().active_count << " planes";
      ASSERT_EQ(bit(ins, i), v == V::inside) << "box " << i;
      ASSERT_EQ(bit(vis_only, i), v != V::outside) << "box " << i << " (visible-only kernel)";
      outside += v == V::outside;
      inside += v == V::inside;
      const V w = model_sphere(f, x.sphere(i));
      ASSERT_EQ(bit(svis, i), w != V::outside) << "sphere " << i;
      ASSERT_EQ(bit(sins, i), w == V::inside) << "sphere " << i;
    }
    EXPECT_GT(outside, 50);  // the data exercises every verdict
    EXPECT_GT(inside, 10);
  }
  }
  hwy::SetSupportedTargetsForTest(0);
}

// The margin matters on this data: a kernel comparing with 0 instead of -T / T would differ.
TEST(CertifiedBatch, TheDataReachesIntoTheMargin) {
  for (int c = 0; c < 5; ++c) {
    const glm::vec3 o = c == 1 ? glm::vec3(-4096.0f, 0, 0) : c == 2 ? glm::vec3(0, 0, 4096.0f) : glm::vec3(0.0f);
    const BatchData x(o, c >= 3);
    const Frustum plain = c >= 3 ? wide_box(c == 4) : moved(F(), o);
    const CertifiedFrustum f = certify_planes(plain);
    int margin_out = 0, margin_in = 0;
    for (std::size_t i = 0; i < x.n; ++i) {
      if (model_box(f, x.box(i)) != V::intersecting) continue;
      const V v = pn_vertex(plain, x.box(i));
      margin_out += v == V::outside;
      margin_in += v == V::inside;
    }
    EXPECT_GT(margin_out, 50);
    EXPECT_GT(margin_in, 50);
  }
}

// Batch and scalar certified tests are both certified; they may differ only where one of them
// cannot decide within its margin (it then says intersecting), never outside against inside.
// The witness pass proves what it can and nothing else: the frustum of F() (|x|, |y| <= -z,
// -3 <= z <= -1), seed (0, 0, -2). Boxes past a word, so that the padded tail runs too.
TEST(CertifiedBatch, TheWitnessPassProvesBoxesThatCrossAPlane) {
  const CertifiedFrustum f = certify_planes(F());
  const float big = 3e38f;
  const std::vector<Aabb> kinds = {
      Aabb{{1.5f, -0.1f, -2.1f}, {2.5f, 0.1f, -1.9f}},   // crosses x = -z; (1.5, 0, -2) is inside: proved
      Aabb{{-0.5f, -0.5f, -2.5f}, {0.5f, 0.5f, -1.5f}},  // inside: no vertex outside, no bit
      Aabb{{5.0f, 5.0f, -2.0f}, {6.0f, 6.0f, -1.5f}},    // outside: no point inside, no bit
      Aabb{{1.9f, 1.9f, -0.5f}, {2.1f, 2.1f, 0.5f}},     // outside beyond the near plane's edge: no bit
      Aabb{{-big, -big, -big}, {big, big, big}},         // holds the frustum, but M > m_safe: no bit
      Aabb{{2.5f, 2.5f, -2.5f}, {3.5f, 3.5f, -1.5f}},    // crosses two planes, the seed clamps to a corner
                                                         // outside one, the centre (3, 3, -2) too: no bit
  };
  const std::vector<bool> proved = {true, false, false, false, false, false};
  std::vector<Aabb> boxes;
  for (int i = 0; i < 70; ++i) boxes.push_back(kinds[std::size_t(i) % kinds.size()]);
  std::vector<float> a[6];
  for (const Aabb& b : boxes)
    for (int k = 0; k < 3; ++k) a[k].push_back(b.min[k]), a[3 + k].push_back(b.max[k]);
  const AabbSoa soa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), boxes.size()};
  std::vector<std::uint64_t> todo(bitset_words(boxes.size()), ~std::uint64_t{0}), meets(todo.size(), 0);
  todo.back() = (std::uint64_t{1} << (boxes.size() % 64)) - 1;
  certified_meets_aabbs_bitset(f, soa, glm::vec3(0, 0, -2), todo.data(), meets.data());
  for (std::size_t i = 0; i < boxes.size(); ++i) EXPECT_EQ(bit(meets, i), proved[i % kinds.size()]) << "box " << i;
  EXPECT_EQ(meets.back() >> (boxes.size() % 64), 0u);  // nothing past the boxes
  // Only boxes asked about: with todo clear, no bit.
  std::fill(todo.begin(), todo.end(), 0);
  certified_meets_aabbs_bitset(f, soa, glm::vec3(0, 0, -2), todo.data(), meets.data());
  for (std::uint64_t w : meets) EXPECT_EQ(w, 0u);
}

// The sphere witness pass: a point of the ball (its centre, or the frustum's point nearest to it,
// estimated and moved inwards towards the seed (0, 0, -2)) certified inside every plane and the
// ball, and the ball reaching past one; same frustum, spheres past a word.
TEST(CertifiedBatch, TheSphereWitnessPassProvesBallsThatCrossAPlane) {
  const CertifiedFrustum f = certify_planes(F());
  const std::vector<Sphere> kinds = {
      Sphere{{1.5f, 0.0f, -2.0f}, 1.0f},     // centre inside, reaches past x = -z: proved
      Sphere{{0.0f, 0.0f, -2.0f}, 0.25f},    // inside: no point outside, no bit
      Sphere{{0.0f, 0.0f, -2.0f}, 0.999f},   // inside still (the nearest plane is 1.41 away): no bit
      Sphere{{2.5f, 0.0f, -2.0f}, 1.0f},     // centre outside, 0.354 from x = -z: proved
      Sphere{{9.0f, 9.0f, -2.0f}, 1.0f},     // outside: no bit
      Sphere{{0.0f, 0.0f, -2.0f}, 3e38f},    // holds the frustum, but M > m_safe: no bit
      Sphere{{0.0f, 0.0f, -1.0f}, 0.5f},     // centre on the near plane: proved
      Sphere{{2.5f, 0.0f, -2.0f}, 0.354f},   // 0.3536 from x = -z: the point moved inwards leaves it, no bit
      Sphere{{2.5f, 0.0f, -2.0f}, 0.5f},     // 0.354 from x = -z: proved
  };
  const std::vector<bool> proved = {true, false, false, true, false, false, true, false, true};
  std::vector<float> a[4];
  const std::size_t n = 75;
  for (std::size_t i = 0; i < n; ++i) {
    const Sphere& s = kinds[i % kinds.size()];
    a[0].push_back(s.center.x), a[1].push_back(s.center.y), a[2].push_back(s.center.z), a[3].push_back(s.radius);
  }
  const SphereSoa soa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), n};
  std::vector<std::uint64_t> todo(bitset_words(n), ~std::uint64_t{0}), meets(todo.size(), 0);
  todo.back() = (std::uint64_t{1} << (n % 64)) - 1;
  certified_meets_spheres_bitset(f, soa, glm::vec3(0, 0, -2), todo.data(), meets.data());
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(bit(meets, i), proved[i % kinds.size()]) << "sphere " << i;
  EXPECT_EQ(meets.back() >> (n % 64), 0u);
  std::fill(todo.begin(), todo.end(), 0);
  certified_meets_spheres_bitset(f, soa, glm::vec3(0, 0, -2), todo.data(), meets.data());
  for (std::uint64_t w : meets) EXPECT_EQ(w, 0u);
}

TEST(CertifiedBatch, AgreesWithTheScalarTestsOutsideTheMargin) {
  for (const auto& [f, x] : batch_cases()) {
    std::vector<std::uint64_t> vis(bitset_words(x.n)), ins(bitset_words(x.n)), svis(bitset_words(x.n)),
        sins(bitset_words(x.n));
    certified_cull_aabbs_bitset(f, x.boxes(), vis.data(), ins.data());
    certified_cull_spheres_bitset(f, x.spheres(), svis.data(), sins.data());
    int same = 0;
    for (std::size_t i = 0; i < x.n; ++i) {
      const V batch = !bit(vis, i) ? V::outside : bit(ins, i) ? V::inside : V::intersecting;
      const V scalar = certified_pn_vertex(f, x.box(i));
      if (batch != scalar) {
        EXPECT_TRUE(batch == V::intersecting || scalar == V::intersecting) << "box " << i;
      }
      same += batch == scalar;
      const V sb = !bit(svis, i) ? V::outside : bit(sins, i) ? V::inside : V::intersecting;
      const V ss = certified_sphere(f, x.sphere(i));
      if (sb != ss) {
        EXPECT_TRUE(sb == V::intersecting || ss == V::intersecting) << "sphere " << i;
      }
    }
    EXPECT_GT(same, int(x.n) * 9 / 10);
  }
}

TEST(Certified, RegisteredWithTheCertifiedClaim) {
  for (const char* name : {"point-certified", "sphere-certified", "pn-vertex-certified", "obb-pn-vertex-certified",
                           "pn-vertex-batch-certified", "sphere-batch-certified", "sat-certified"}) {
    const Method* m = find_builtin(name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_EQ(m->claim, Claim::certified_conservative) << name;
    EXPECT_EQ(m->origin, Origin::own) << name;
  }
}

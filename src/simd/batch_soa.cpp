// SIMD structure-of-arrays batch culling of AABBs and spheres (Highway, runtime dispatch).
//
// Sources: Assarsson & Möller 2000, §3.1 (n/p-vertex test; "precompute the bitfields ... for
// each view frustum plane once each frame" — here the min/max array choice is hoisted per plane
// by the sign of the normal, so the inner loop has no selection at all);
// Lighthouse3D sphereInFrustum for spheres. Highway 1.0 foreach_target.h +
// HWY_EXPORT / HWY_DYNAMIC_DISPATCH.
// Claim: conservative (the verdicts are bit-for-bit pn_vertex_index / sphere_plane_test_wide,
// which are pn_vertex / sphere_plane_test wherever the float plane values are finite):
//  - each plane value is ((nx*x + ny*y) + nz*z) + d with separate Mul and Add (no MulAdd, and
//    -ffp-contract=off), the order of Plane::eval;
//  - a lane whose value overflows (not finite: NaN compares false, -inf for a value whose sign
//    the overflow lost) is flagged, and its volume classified again by the scalar function, which
//    takes that value in double (plane_value). The flag is fma(v, 0, flag): NaN as soon as one v
//    is not finite, one instruction per plane; the verdicts never read it;
//  - a box is visible iff the minimum over planes of the p-vertex values is >= 0 (no NaN for
//    finite input: min is exact, and -0 >= 0 like the scalar `< 0` test) and inside iff the
//    minimum n-vertex value is >= 0;
//  - a sphere is outside iff some dist < -r, which equals fl(dist + r) < 0 (a rounded sum of two
//    floats has the sign of the exact sum), inside iff every fl(dist - r) >= 0; degenerate
//    planes are hoisted as in sphere_plane_test (skipped when d >= 0, everything outside when
//    d < 0).
// Touching: as the scalar tests (touching from outside: intersecting).
// Tail items (count not a multiple of 64) go through the scalar functions themselves.
// Only the AABB kernel's plane sum (s + d is compared as s >= -d) and the sphere's n.c + d can
// overflow on finite input: once s is finite the comparison is exact, and fl(v + r), fl(v - r)
// overflow only with the sign of the exact sum.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch_soa.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/core/plane_select.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <vector>

#ifndef CULLPROOF_BATCH_SOA_SHARED
#define CULLPROOF_BATCH_SOA_SHARED
namespace cullproof::batch_detail {
constexpr std::size_t kPrefetchWords = 1024, kPrefetchAhead = 8;  // batches above 64k volumes prefetch ahead
// A plane with its vertex arrays chosen by the normal's signs.
struct SelPlane {
  float nx, ny, nz, d;
  const float* px;
  const float* py;
  const float* pz;
  const float* qx;
  const float* qy;
  const float* qz;
};
inline Aabb box_at(const AabbSoa& b, std::size_t i) {
  return Aabb{glm::vec3(b.min_x[i], b.min_y[i], b.min_z[i]), glm::vec3(b.max_x[i], b.max_y[i], b.max_z[i])};
}
}  // namespace cullproof::batch_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Boxes [0, words*64): visible / inside bits. `inside` may be null.
// Per plane, fl(s + d) < 0 iff s < -d exactly (a rounded sum of two floats has the sign of the
// exact sum), so comparing s = (nx*x + ny*y) + nz*z with -d gives pn_vertex's verdict without
// the last Add. Vector-outer, plane-inner: faster than plane-outer blocking (bench/cull/NOTES.md).
void AabbKernel(const batch_detail::SelPlane* planes, const Frustum* frustum, const AabbSoa* boxes,
                std::size_t words, std::uint64_t* visible, std::uint64_t* inside) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  using batch_detail::kPrefetchAhead;
  using batch_detail::kPrefetchWords;
  const std::size_t N = hn::Lanes(d);
  V nx[6], ny[6], nz[6], nd[6];
  for (int k = 0; k < 6; ++k) {
    nx[k] = hn::Set(d, planes[k].nx);
    ny[k] = hn::Set(d, planes[k].ny);
    nz[k] = hn::Set(d, planes[k].nz);
    nd[k] = hn::Set(d, -planes[k].d);
  }
  // Large batches (more than 64k boxes, 1.5 MB: past L2) prefetch the six arrays 4 words (1 KB
  // each) ahead; in L2 the prefetches only cost load slots (the kernel is load-bound), so small
  // batches do without (bench/cull/NOTES.md).
  const float* arr[6] = {planes[0].px, planes[0].py, planes[0].pz, planes[0].qx, planes[0].qy, planes[0].qz};
  const bool prefetch = words > kPrefetchWords;
  const V zero = hn::Zero(d);
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t vis = 0, ins = 0, redo = 0;
    if (prefetch && w + kPrefetchAhead < words)
      for (int c = 0; c < 6; ++c)
        for (int l = 0; l < 64; l += 16) __builtin_prefetch(arr[c] + (w + kPrefetchAhead) * 64 + l);
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      auto ok = hn::Ge(nd[0], nd[0]);  // all true (no NaN)
      V flag = zero;                   // NaN where a plane value overflowed
      for (int k = 0; k < 6; ++k) {
        const batch_detail::SelPlane& s = planes[k];
        V v = hn::Mul(nx[k], hn::LoadU(d, s.px + i));
        v = hn::Add(v, hn::Mul(ny[k], hn::LoadU(d, s.py + i)));
        v = hn::Add(v, hn::Mul(nz[k], hn::LoadU(d, s.pz + i)));
        ok = hn::And(ok, hn::Ge(v, nd[k]));
        flag = hn::MulAdd(v, zero, flag);
      }
      vis |= mask_bits(d, ok) << j;
      if (inside) {
        for (int k = 0; k < 6; ++k) {
          const batch_detail::SelPlane& s = planes[k];
          V v = hn::Mul(nx[k], hn::LoadU(d, s.qx + i));
          v = hn::Add(v, hn::Mul(ny[k], hn::LoadU(d, s.qy + i)));
          v = hn::Add(v, hn::Mul(nz[k], hn::LoadU(d, s.qz + i)));
          ok = hn::And(ok, hn::Ge(v, nd[k]));
          flag = hn::MulAdd(v, zero, flag);
        }
        ins |= mask_bits(d, ok) << j;
      }
      redo |= mask_bits(d, hn::IsNaN(flag)) << j;
    }
    // Overflowed lanes (rare: values near FLT_MAX) through the scalar test, in double where needed.
    for (; redo != 0; redo &= redo - 1) {
      const int bit = __builtin_ctzll(redo);
      const Visibility v = pn_vertex_index(*frustum, batch_detail::box_at(*boxes, w * 64 + std::size_t(bit)));
      const std::uint64_t one = std::uint64_t{1} << bit;
      vis = v != Visibility::outside ? vis | one : vis & ~one;
      ins = v == Visibility::inside ? ins | one : ins & ~one;
    }
    visible[w] = vis;
    if (inside) inside[w] = ins;
  }
}

// Spheres [0, words*64) against `count` non-degenerate unit planes.
void SphereKernel(const batch_detail::SelPlane* planes, int count, const Frustum* frustum, const float* x,
                  const float* y, const float* z, const float* r, std::size_t words, std::uint64_t* visible,
                  std::uint64_t* inside) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  V nx[6], ny[6], nz[6], dd[6];
  for (int k = 0; k < count; ++k) {
    nx[k] = hn::Set(d, planes[k].nx);
    ny[k] = hn::Set(d, planes[k].ny);
    nz[k] = hn::Set(d, planes[k].nz);
    dd[k] = hn::Set(d, planes[k].d);
  }
  const V zero = hn::Zero(d);
  const V inf = hn::Set(d, std::numeric_limits<float>::infinity());
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t vis = 0, ins = 0, redo = 0;
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      const V cx = hn::LoadU(d, x + i), cy = hn::LoadU(d, y + i), cz = hn::LoadU(d, z + i);
      const V rad = hn::LoadU(d, r + i);
      V minp = inf, minn = inf;
      V flag = zero;  // NaN where a plane value overflowed
      for (int k = 0; k < count; ++k) {
        V v = hn::Mul(nx[k], cx);
        v = hn::Add(v, hn::Mul(ny[k], cy));
        v = hn::Add(v, hn::Mul(nz[k], cz));
        v = hn::Add(v, dd[k]);
        flag = hn::MulAdd(v, zero, flag);
        minp = hn::Min(minp, hn::Add(v, rad));
        minn = hn::Min(minn, hn::Sub(v, rad));
      }
      const auto vis_m = hn::Ge(minp, zero);
      vis |= mask_bits(d, vis_m) << j;
      if (inside) ins |= mask_bits(d, hn::And(vis_m, hn::Ge(minn, zero))) << j;
      redo |= mask_bits(d, hn::IsNaN(flag)) << j;
    }
    for (; redo != 0; redo &= redo - 1) {
      const int bit = __builtin_ctzll(redo);
      const std::size_t i = w * 64 + std::size_t(bit);
      const Visibility v = sphere_plane_test_wide(*frustum, Sphere{glm::vec3(x[i], y[i], z[i]), r[i]});
      const std::uint64_t one = std::uint64_t{1} << bit;
      vis = v != Visibility::outside ? vis | one : vis & ~one;
      ins = v == Visibility::inside ? ins | one : ins & ~one;
    }
    visible[w] = vis;
    if (inside) inside[w] = ins;
  }
}

const char* TargetNameImpl() { return hwy::TargetName(HWY_TARGET); }

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

HWY_EXPORT(AabbKernel);
HWY_EXPORT(SphereKernel);
HWY_EXPORT(TargetNameImpl);

namespace {

using batch_detail::SelPlane;

void select_planes(const Frustum& f, const AabbSoa& b, SelPlane (&out)[6]) {
  for (int k = 0; k < 6; ++k) {
    // The arrays in select_plane's order of a box's six floats.
    const float* arrays[6] = {b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z};
    const SelectedPlane sel = select_plane(f[k]);
    out[k] = SelPlane{sel.nx, sel.ny, sel.nz, sel.d, arrays[sel.px], arrays[sel.py], arrays[sel.pz],
                      arrays[sel.qx], arrays[sel.qy], arrays[sel.qz]};
  }
}

using batch_detail::box_at;

void aabbs(const Frustum& f, const AabbSoa& b, std::uint64_t* visible, std::uint64_t* inside) {
  const std::size_t full = b.count / 64;
  if (full > 0) {
    SelPlane planes[6];
    select_planes(f, b, planes);
    HWY_DYNAMIC_DISPATCH(AabbKernel)(planes, &f, &b, full, visible, inside);
  }
  if (full * 64 == b.count) return;
  std::uint64_t vis = 0, ins = 0;
  for (std::size_t i = full * 64; i < b.count; ++i) {
    const Visibility v = pn_vertex_index(f, box_at(b, i));
    vis |= std::uint64_t{v != Visibility::outside} << (i % 64);
    ins |= std::uint64_t{v == Visibility::inside} << (i % 64);
  }
  visible[full] = vis;
  if (inside) inside[full] = ins;
}

void spheres(const Frustum& f, const SphereSoa& s, std::uint64_t* visible, std::uint64_t* inside) {
  const std::size_t words = bitset_words(s.count);
  SelPlane planes[6];
  int count = 0;
  for (int k = 0; k < 6; ++k) {
    const Plane& p = f[k];
    if (p.is_degenerate()) {
      if (p.d < 0.0f) {  // contains nothing: every sphere is outside
        if (words == 0) return;  // (no words: the arrays may be null, which memset does not take)
        std::memset(visible, 0, words * sizeof(std::uint64_t));
        if (inside) std::memset(inside, 0, words * sizeof(std::uint64_t));
        return;
      }
      continue;  // contains all space
    }
    planes[count++] = SelPlane{p.n.x, p.n.y, p.n.z, p.d, nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  }
  const std::size_t full = s.count / 64;
  if (full > 0) HWY_DYNAMIC_DISPATCH(SphereKernel)(planes, count, &f, s.x, s.y, s.z, s.radius, full, visible, inside);
  if (full * 64 == s.count) return;
  std::uint64_t vis = 0, ins = 0;
  for (std::size_t i = full * 64; i < s.count; ++i) {
    const Visibility v = sphere_plane_test_wide(f, Sphere{glm::vec3(s.x[i], s.y[i], s.z[i]), s.radius[i]});
    vis |= std::uint64_t{v != Visibility::outside} << (i % 64);
    ins |= std::uint64_t{v == Visibility::inside} << (i % 64);
  }
  visible[full] = vis;
  if (inside) inside[full] = ins;
}

std::size_t to_indices(const std::uint64_t* bits, std::size_t words, std::uint32_t* out) {
  std::size_t n = 0;
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t b = bits[w];
    while (b) {
      out[n++] = static_cast<std::uint32_t>(w * 64 + static_cast<std::size_t>(__builtin_ctzll(b)));
      b &= b - 1;
    }
  }
  return n;
}

}  // namespace

void cull_aabbs_bitset(const Frustum& f, const AabbSoa& b, std::uint64_t* visible) { aabbs(f, b, visible, nullptr); }
void classify_aabbs_bitset(const Frustum& f, const AabbSoa& b, std::uint64_t* visible, std::uint64_t* inside) {
  aabbs(f, b, visible, inside);
}
std::size_t cull_aabbs_indices(const Frustum& f, const AabbSoa& b, std::uint32_t* out) {
  std::vector<std::uint64_t> bits(bitset_words(b.count));
  aabbs(f, b, bits.data(), nullptr);
  return to_indices(bits.data(), bits.size(), out);
}
void cull_spheres_bitset(const Frustum& f, const SphereSoa& s, std::uint64_t* visible) { spheres(f, s, visible, nullptr); }
void classify_spheres_bitset(const Frustum& f, const SphereSoa& s, std::uint64_t* visible, std::uint64_t* inside) {
  spheres(f, s, visible, inside);
}
std::size_t cull_spheres_indices(const Frustum& f, const SphereSoa& s, std::uint32_t* out) {
  std::vector<std::uint64_t> bits(bitset_words(s.count));
  spheres(f, s, bits.data(), nullptr);
  return to_indices(bits.data(), bits.size(), out);
}

void cull_aabbs_bitset_scalar(const Frustum& f, const AabbSoa& b, std::uint64_t* visible) {
  const std::size_t words = bitset_words(b.count);
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t vis = 0;
    const std::size_t end = std::min(b.count, (w + 1) * 64);
    for (std::size_t i = w * 64; i < end; ++i)
      vis |= std::uint64_t{pn_vertex(f, box_at(b, i)) != Visibility::outside} << (i - w * 64);
    visible[w] = vis;
  }
}

const char* batch_simd_target() { return HWY_DYNAMIC_DISPATCH(TargetNameImpl)(); }

}  // namespace cullproof
#endif  // HWY_ONCE

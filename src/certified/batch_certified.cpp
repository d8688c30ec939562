// Certified SIMD batch culling of AABBs and spheres (Highway, runtime dispatch).
//
// Sources: the n/p-vertex test of Assarsson & Möller 2000 §3.1 with the min/max choice hoisted
// per plane (as src/cull/batch_soa.cpp), and the certified margins of certified.cpp, whose
// derivation applies lane by lane: t = alpha M + beta with M the lane's largest coordinate
// magnitude, computed with the same Mul and Add as the scalar code (no MulAdd,
// -ffp-contract=off), and the plane value ((nx x + ny y) + nz z) + d in Plane::eval's order.
// So every lane's verdict equals certified_pn_vertex / certified_sphere bit for bit.
// Claim: certified-conservative. Lanes with M > m_safe (or non-finite) are recomputed by the
// scalar functions, which guard against overflow.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "batch_certified.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "batch_util-inl.h"

#include "cullproof/certified_batch.hpp"

#include <cmath>
#include <cstring>
#include <vector>

#ifndef CULLPROOF_BATCH_CERTIFIED_SHARED
#define CULLPROOF_BATCH_CERTIFIED_SHARED
namespace cullproof::certified_batch_detail {
struct CertPlane {
  float nx, ny, nz, d, alpha, beta, len;
  const float* px;
  const float* py;
  const float* pz;
  const float* qx;
  const float* qy;
  const float* qz;
};
}  // namespace cullproof::certified_batch_detail
#endif

HWY_BEFORE_NAMESPACE();
namespace cullproof {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;
using certified_batch_detail::CertPlane;

template <class D, class V>
HWY_INLINE V eval3(D, V nx, V ny, V nz, V nd, V x, V y, V z) {
  V v = hn::Mul(nx, x);
  v = hn::Add(v, hn::Mul(ny, y));
  v = hn::Add(v, hn::Mul(nz, z));
  return hn::Add(v, nd);
}

void CertAabbKernel(const CertPlane* planes, int count, const float* const* arrays, float m_safe, std::size_t words,
                    std::uint64_t* visible, std::uint64_t* inside, std::uint64_t* unsafe) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  V nx[6], ny[6], nz[6], nd[6], al[6], be[6];
  for (int k = 0; k < count; ++k) {
    nx[k] = hn::Set(d, planes[k].nx);
    ny[k] = hn::Set(d, planes[k].ny);
    nz[k] = hn::Set(d, planes[k].nz);
    nd[k] = hn::Set(d, planes[k].d);
    al[k] = hn::Set(d, planes[k].alpha);
    be[k] = hn::Set(d, planes[k].beta);
  }
  const V msafe = hn::Set(d, m_safe);
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t vis = 0, ins = 0, bad = 0;
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      V m = hn::Abs(hn::LoadU(d, arrays[0] + i));
      for (int a = 1; a < 6; ++a) m = hn::Max(m, hn::Abs(hn::LoadU(d, arrays[a] + i)));
      // Scalar: max(|min|, |max|) per axis, then max over axes; max is exact, so any order agrees.
      auto ok = hn::Le(m, msafe);
      bad |= mask_bits(d, hn::Not(ok)) << j;
      auto in = ok;
      for (int k = 0; k < count; ++k) {
        const CertPlane& s = planes[k];
        const V t = hn::Add(hn::Mul(al[k], m), be[k]);
        const V vp = eval3(d, nx[k], ny[k], nz[k], nd[k], hn::LoadU(d, s.px + i), hn::LoadU(d, s.py + i),
                           hn::LoadU(d, s.pz + i));
        ok = hn::And(ok, hn::Ge(vp, hn::Neg(t)));
        if (inside) {
          const V vn = eval3(d, nx[k], ny[k], nz[k], nd[k], hn::LoadU(d, s.qx + i), hn::LoadU(d, s.qy + i),
                             hn::LoadU(d, s.qz + i));
          in = hn::And(in, hn::Ge(vn, t));
        }
      }
      vis |= mask_bits(d, ok) << j;
      if (inside) ins |= mask_bits(d, hn::And(ok, in)) << j;
    }
    visible[w] = vis;
    if (inside) inside[w] = ins;
    unsafe[w] = bad;
  }
}

void CertSphereKernel(const CertPlane* planes, int count, const float* x, const float* y, const float* z,
                      const float* r, float m_safe, std::size_t words, std::uint64_t* visible, std::uint64_t* inside,
                      std::uint64_t* unsafe) {
  const hn::ScalableTag<float> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  V nx[6], ny[6], nz[6], nd[6], al[6], be[6], len[6];
  for (int k = 0; k < count; ++k) {
    nx[k] = hn::Set(d, planes[k].nx);
    ny[k] = hn::Set(d, planes[k].ny);
    nz[k] = hn::Set(d, planes[k].nz);
    nd[k] = hn::Set(d, planes[k].d);
    al[k] = hn::Set(d, planes[k].alpha);
    be[k] = hn::Set(d, planes[k].beta);
    len[k] = hn::Set(d, planes[k].len);
  }
  const V msafe = hn::Set(d, m_safe);
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t vis = 0, ins = 0, bad = 0;
    for (std::size_t j = 0; j < 64; j += N) {
      const std::size_t i = w * 64 + j;
      const V cx = hn::LoadU(d, x + i), cy = hn::LoadU(d, y + i), cz = hn::LoadU(d, z + i), rad = hn::LoadU(d, r + i);
      const V m = hn::Add(hn::Max(hn::Abs(cx), hn::Max(hn::Abs(cy), hn::Abs(cz))), rad);
      auto ok = hn::Le(m, msafe);
      bad |= mask_bits(d, hn::Not(ok)) << j;
      auto in = ok;
      for (int k = 0; k < count; ++k) {
        const V t = hn::Add(hn::Mul(al[k], m), be[k]);
        const V s = eval3(d, nx[k], ny[k], nz[k], nd[k], cx, cy, cz);
        const V rho = hn::Mul(rad, len[k]);
        ok = hn::And(ok, hn::Ge(hn::Add(s, rho), hn::Neg(t)));
        in = hn::And(in, hn::Ge(hn::Sub(s, rho), t));
      }
      vis |= mask_bits(d, ok) << j;
      if (inside) ins |= mask_bits(d, hn::And(ok, in)) << j;
    }
    visible[w] = vis;
    if (inside) inside[w] = ins;
    unsafe[w] = bad;
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace cullproof
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace cullproof {

HWY_EXPORT(CertAabbKernel);
HWY_EXPORT(CertSphereKernel);

namespace {

using certified_batch_detail::CertPlane;

template <class Scalar>
void patch(std::size_t count, std::size_t words, const std::uint64_t* unsafe, std::uint64_t* visible,
           std::uint64_t* inside, Scalar&& scalar) {
  for (std::size_t w = 0; w < words; ++w) {
    std::uint64_t b = unsafe ? unsafe[w] : ~std::uint64_t{0};
    if (!unsafe) {  // the tail: every lane up to count
      const std::size_t end = std::min<std::size_t>(64, count - w * 64);
      b = end >= 64 ? ~std::uint64_t{0} : ((std::uint64_t{1} << end) - 1);
      visible[w] = 0;
      if (inside) inside[w] = 0;
    }
    while (b) {
      const int bit = __builtin_ctzll(b);
      b &= b - 1;
      const Visibility v = scalar(w * 64 + std::size_t(bit));
      const std::uint64_t one = std::uint64_t{1} << bit;
      visible[w] = (visible[w] & ~one) | (v != Visibility::outside ? one : 0);
      if (inside) inside[w] = (inside[w] & ~one) | (v == Visibility::inside ? one : 0);
    }
  }
}

void clear(std::size_t words, std::uint64_t* visible, std::uint64_t* inside) {
  if (words == 0) return;  // the arrays may be null then
  std::memset(visible, 0, words * sizeof(std::uint64_t));
  if (inside) std::memset(inside, 0, words * sizeof(std::uint64_t));
}

}  // namespace

void certified_cull_aabbs_bitset(const CertifiedFrustum& f, const AabbSoa& b, std::uint64_t* visible,
                                 std::uint64_t* inside) {
  const std::size_t words = bitset_words(b.count), full = b.count / 64;
  if (f.empty) return clear(words, visible, inside);
  CertPlane planes[6];
  for (int i = 0; i < f.active_count; ++i) {
    const int k = f.active[static_cast<std::size_t>(i)];
    const Plane& p = f.planes[k];
    // Hoisted per plane: the p-vertex reads max where n >= 0 (certified_pn_vertex's choice).
    planes[i] = CertPlane{p.n.x, p.n.y, p.n.z, p.d, f.alpha_narrow[k], f.beta_narrow[k], 0.0f,
                          p.n.x >= 0.0f ? b.max_x : b.min_x, p.n.y >= 0.0f ? b.max_y : b.min_y,
                          p.n.z >= 0.0f ? b.max_z : b.min_z, p.n.x >= 0.0f ? b.min_x : b.max_x,
                          p.n.y >= 0.0f ? b.min_y : b.max_y, p.n.z >= 0.0f ? b.min_z : b.max_z};
  }
  auto scalar = [&](std::size_t i) {
    return certified_pn_vertex(f, Aabb{glm::vec3(b.min_x[i], b.min_y[i], b.min_z[i]),
                                       glm::vec3(b.max_x[i], b.max_y[i], b.max_z[i])});
  };
  if (full > 0) {
    std::vector<std::uint64_t> unsafe(full);
    const float* arrays[6] = {b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z};
    HWY_DYNAMIC_DISPATCH(CertAabbKernel)(planes, f.active_count, arrays, f.m_safe, full, visible, inside, unsafe.data());
    patch(b.count, full, unsafe.data(), visible, inside, scalar);
  }
  if (full < words) patch(b.count - full * 64, 1, nullptr, visible + full, inside ? inside + full : nullptr,
                          [&](std::size_t i) { return scalar(full * 64 + i); });
}

void certified_cull_spheres_bitset(const CertifiedFrustum& f, const SphereSoa& s, std::uint64_t* visible,
                                   std::uint64_t* inside) {
  const std::size_t words = bitset_words(s.count), full = s.count / 64;
  if (f.empty) return clear(words, visible, inside);
  CertPlane planes[6];
  for (int i = 0; i < f.active_count; ++i) {
    const int k = f.active[static_cast<std::size_t>(i)];
    const Plane& p = f.planes[k];
    planes[i] = CertPlane{p.n.x, p.n.y, p.n.z, p.d, f.alpha_wide[k], f.beta_wide[k],
                          std::sqrt(glm::dot(p.n, p.n)), nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
  }
  auto scalar = [&](std::size_t i) {
    return certified_sphere(f, Sphere{glm::vec3(s.x[i], s.y[i], s.z[i]), s.radius[i]});
  };
  if (full > 0) {
    std::vector<std::uint64_t> unsafe(full);
    HWY_DYNAMIC_DISPATCH(CertSphereKernel)(planes, f.active_count, s.x, s.y, s.z, s.radius, f.m_safe, full, visible,
                                           inside, unsafe.data());
    patch(s.count, full, unsafe.data(), visible, inside, scalar);
  }
  if (full < words) patch(s.count - full * 64, 1, nullptr, visible + full, inside ? inside + full : nullptr,
                          [&](std::size_t i) { return scalar(full * 64 + i); });
}

}  // namespace cullproof
#endif  // HWY_ONCE

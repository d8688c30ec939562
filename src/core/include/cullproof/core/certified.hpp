// Certified conservative culling: float tests whose decisions carry a rigorous
// rounding-error bound, derived from the operations performed (src/core/certified/certified.cpp has
// the derivation), covering the plane extraction from the matrix as well (end to end). They
// never give a false reject or a false inside for any valid float input, with or without FMA
// contraction; where the bound does not let them decide, they answer `intersecting`.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"

#include <array>
#include <optional>
#include <utility>

namespace cullproof {

/// One plane of the certified fast path (CertifiedFrustum::Data::fast_box / fast_sphere).
struct CertifiedPlane {
  float nx = 0, ny = 0, nz = 0;  ///< the float normal times 2^-e, rounded away from zero (signs kept)
  float d_out = 0;               ///< d 2^-e + delta, rounded up: the offset of the "outside" test
  float d_in = 0;                ///< d 2^-e - delta, rounded down: the offset of the "inside" test
  float norm = 0;                ///< |n| of the scaled normal, in double, rounded to float (sphere tests)
};

/// The factors of the certified margins, derived in src/core/certified/certified.cpp from the
/// standard model with u = 2^-24 (docs/certified.md) and checked against that derivation when it
/// compiles (static_asserts there): a margin is factor * bound + kUnderflow.
struct CertifiedMargins {
  /// Points and AABBs: covers 5.0001 u, the error of a plane value, after three roundings.
  static constexpr float kNarrow = 0x1p-21f;
  /// Spheres (11 u: the plane value and r |n|) and OBBs (13.1 u: the projected half-widths).
  static constexpr float kWide = 0x1p-20f;
  /// Every absolute underflow error of a margin's computation (a few 2^-150).
  static constexpr float kUnderflow = 0x1p-126f;
  /// A float point x lies in the ball (c, r) when fl(fl(s kBallScale) + kBallAbsolute) < fl(r r),
  /// s = fl(sum fl(x_i - c_i)^2) in any order, fused or not (the SIMD sphere witness pass).
  static constexpr float kBallScale = 1.0f + 0x1p-20f;
  static constexpr float kBallAbsolute = 0x1p-140f;
};

/// A frustum prepared for certified tests (once per frame). For each plane k: the float plane a
/// culler uses, and `bound[k]` = (a_x, a_y, a_z, a_d) with |true coefficient| <= a and
/// |float coefficient - true coefficient| <= u * a (u = 2^-24). For planes given as planes,
/// a = |plane| (they are the truth). For a matrix, the truth is the exact row sum r4 +- rk and
/// a = |r4| + |rk| (or |r3| for the [0,1] near plane), componentwise.
class CertifiedFrustum {
 public:
  /// What certify_planes / certify_matrix derive; read through data(). Nothing outside them
  /// writes it: a changed field would void the bound the tests rely on.
  struct Data {
    Frustum planes;
    std::array<glm::vec4, 6> bound{};
    std::array<float, 6> bound_sum{};  ///< a_x + a_y + a_z, rounded up
    // Derived once per frame (certify_*): the margin of plane k for a volume whose coordinates
    // are at most M in magnitude is t = alpha[k] M + beta[k] (8 u bounds, `narrow`, for points and
    // AABBs; 16 u, `wide`, for spheres and OBBs). Degenerate planes are decided exactly here:
    // "all space" planes are left out of `active`, a "nothing" plane sets `empty`. Volumes with
    // M <= m_safe cannot overflow anything in the tests; larger ones take a guarded path.
    std::array<float, 6> alpha_narrow{}, beta_narrow{}, alpha_wide{}, beta_wide{};
    std::array<double, 6> norm{};  ///< |n| of the float plane, in double (the guarded sphere test)
    std::array<int, 6> active{};
    int active_count = 0;
    bool empty = false;
    float m_safe = 0.0f;
    // The fast path of the AABB and sphere tests (certified.cpp, "Fast path"), one entry per
    // active plane in `active` order: plane k scaled by a power of two so that its bound sum is
    // about 1, the constant part of its margin folded into d_out / d_in, and the part that grows
    // with the volume's magnitude M made uniform over the planes: T = fl(t * M). A volume is
    // outside when some plane's value with d_out (plus rho, spheres) is < -T, inside when every
    // plane's value with d_in (minus rho) is >= T. Per volume this costs M and one product, not a
    // margin per plane. Used when M <= m_safe; larger volumes take the guarded per-plane path.
    std::array<CertifiedPlane, 6> fast_box{}, fast_sphere{};
    float t_box = 0.0f, t_sphere = 0.0f;
  };

  /// All space: no plane, every volume inside.
  CertifiedFrustum() = default;
  const Data& data() const noexcept { return d_; }

 private:
  explicit CertifiedFrustum(Data d) noexcept : d_(std::move(d)) {}
  friend CertifiedFrustum certify_planes(const Frustum& f);
  friend CertifiedFrustum certify_matrix(const glm::mat4& m, DepthConvention depth);
  Data d_;
};

/// Prepares planes given as planes (they are the exact truth).
CertifiedFrustum certify_planes(const Frustum& f);
/// Prepares the float Gribb–Hartmann extraction of `m`, bounding the extraction error (end to end).
CertifiedFrustum certify_matrix(const glm::mat4& m, DepthConvention depth = {});
/// certify_matrix when the case gives a matrix, certify_planes otherwise.
CertifiedFrustum certify(const CaseFrustum& f);

/// Certified point test: inside, outside, or intersecting when a plane is within the bound.
Visibility certified_point(const CertifiedFrustum& f, const Point& p) noexcept;
/// Certified sphere test (per plane: outside beyond -r |n|, inside beyond +r |n|).
Visibility certified_sphere(const CertifiedFrustum& f, const Sphere& s) noexcept;
/// Certified n/p-vertex AABB test (Assarsson & Möller §3.1 with a rounding margin per plane).
Visibility certified_pn_vertex(const CertifiedFrustum& f, const Aabb& b) noexcept;
/// Certified n/p-vertex OBB test (normal projected on the box axes).
Visibility certified_obb_pn_vertex(const CertifiedFrustum& f, const Obb& b) noexcept;
/// Certified separating-axis test: the certified plane tests, then every other axis on which the
/// float SAT separates is re-checked exactly enough to be sure: the frustum's side of the axis is
/// replaced by a non-negative combination of the three planes meeting at the extreme frustum
/// corner (a half-space that provably holds the whole frustum), and the box is tested against it
/// with a derived bound. nullopt where sat-exact does not apply.
std::optional<Visibility> certified_sat(const CertifiedFrustum& f, const Obb& b);

}  // namespace cullproof

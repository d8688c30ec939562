// Internal (not installed): what the oracle's translation units share. The oracle is four steps,
// each in its own file, and classify() (oracle.cpp) runs them in order, as CGAL's
// Filtered_predicate does: the interval filter (oracle_filter.cpp) decides what it can prove;
// the exact route (oracle_exact.cpp) decides the rest with CGAL's exact LP/QP solver; every
// certificate is checked in exact rationals (oracle_certificates.cpp); exact distances measure
// how far the case lies from the boundary (oracle_distance.cpp).
#pragma once

#include "cullproof/oracle/oracle.hpp"

#include "exact_input.hpp"

#include <CGAL/Gmpq.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Interval_nt.h>

#include <array>
#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace cullproof::oracle::internal {

using ET = CGAL::Gmpzf;              // exact dyadic numbers: every float, sum and product of floats
using Q = CGAL::Gmpq;                // exact rationals: LP solutions and certificates
using I = CGAL::Interval_nt<false>;  // filter intervals (need Protect_FPU_rounding in scope)

/// Calls of the exact LP/QP solver (counted by the exact route, reported by stats()).
extern std::atomic<std::uint64_t> g_exact_lp;
/// Closest pairs found in double and proven exactly, in place of a QP solve.
extern std::atomic<std::uint64_t> g_closest_pairs;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---- exact conversions ------------------------------------------------------------------

inline ET et_of(float x) { return ET(static_cast<double>(x)); }
inline Q q_of(float x) { return Q(static_cast<double>(x)); }

// Gmpzf value man * 2^exp as a rational, exactly.
inline Q q_of(const ET& x) {
  Q r;
  mpq_set_z(r.mpq(), x.man());
  const long e = x.exp();
  if (e > 0) mpq_mul_2exp(r.mpq(), r.mpq(), static_cast<mp_bitcnt_t>(e));
  if (e < 0) mpq_div_2exp(r.mpq(), r.mpq(), static_cast<mp_bitcnt_t>(-e));
  return r;
}
inline Q q_of(const CGAL::Quotient<ET>& x) { return q_of(x.numerator()) / q_of(x.denominator()); }

inline std::string text(const Q& q) {
  char* s = mpq_get_str(nullptr, 10, q.mpq());
  std::string out(s);
  void (*freefunc)(void*, size_t);
  mp_get_memory_functions(nullptr, nullptr, &freefunc);
  freefunc(s, out.size() + 1);
  return out;
}
inline double approx(const Q& q) { return mpq_get_d(q.mpq()); }
inline double approx(const ET& x) { return CGAL::to_double(x); }

inline Rational rational(const Q& q) { return Rational{text(q), approx(q)}; }
template <std::size_t N>
std::array<Rational, N> rationals(const std::array<Q, N>& v) {
  std::array<Rational, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = rational(v[i]);
  return out;
}

[[noreturn]] inline void self_check_failed(const std::string& what) {
  throw OracleError("cullproof oracle self-check failed: " + what +
                    " (this is an oracle bug; please file the case)");
}

// ---- the case in exact numbers ------------------------------------------------------------

struct Planes {
  std::array<detail::Coeffs<ET>, 6> p;
  std::array<bool, 6> degenerate{};  // n == 0 exactly
};

inline Planes exact_planes_et(const CaseFrustum& f) {
  Planes out;
  out.p = detail::exact_planes<ET>(f, [](float x) { return et_of(x); });
  for (int j = 0; j < 6; ++j) {
    const auto& c = out.p[j];
    out.degenerate[j] = CGAL::is_zero(c[0]) && CGAL::is_zero(c[1]) && CGAL::is_zero(c[2]);
  }
  return out;
}

inline std::array<detail::Coeffs<Q>, 6> exact_planes_q(const CaseFrustum& f) {
  return detail::exact_planes<Q>(f, [](float x) { return q_of(x); });
}

inline detail::BoxT<Q> exact_box_q(const Volume& v) {
  return detail::exact_box<Q>(v, [](float x) { return q_of(x); }, Q(1, 2));
}

// The case in Gmpq, converted once per call and only when a check needs it.
class QCase {
 public:
  QCase(const CaseFrustum& f, const Volume& v) : f_(f), v_(v) {}
  const std::array<detail::Coeffs<Q>, 6>& planes() {
    if (!planes_) planes_ = exact_planes_q(f_);
    return *planes_;
  }
  const detail::BoxT<Q>& box() {
    if (!box_) box_ = exact_box_q(v_);
    return *box_;
  }
  const Volume& volume() const { return v_; }
  /// Options::closest_in_double: try a closest pair found in double before the exact QP.
  bool guess = true;

 private:
  const CaseFrustum& f_;
  const Volume& v_;
  std::optional<std::array<detail::Coeffs<Q>, 6>> planes_;
  std::optional<detail::BoxT<Q>> box_;
};

// ---- what the steps hand each other ---------------------------------------------------------

/// A decision and its certificate, not yet checked.
struct Decision {
  Visibility truth = Visibility::outside;
  std::optional<std::array<Q, 3>> t_or_point;  // box: t of a point in B ∩ F; sphere: the point
  std::optional<std::array<Q, 6>> lambda;      // outside: Farkas multipliers
};

/// The interval filter's answer: decided only when its interval bounds prove it.
struct FilterAnswer {
  bool decided = false;
  Visibility truth = Visibility::outside;
  std::array<double, 6> lambda{};  // outside: Farkas multipliers
  std::array<double, 3> pt{};      // box: t of a point of B ∩ F; sphere: the point itself
};

// Closest point y of F to the centre c (exact QP); nullopt when F is empty, with the Farkas
// certificate of emptiness in `lambda`. Checked: y ∈ F, dist2 == |y - c|^2 exactly, and
// `lambda` holds KKT multipliers (λ >= 0, y - c = Σ λ_j n_j over planes active at y), which
// prove optimality: every x ∈ F has Σ λ_j plane_j(x) >= 0, i.e. (y - c)·(x - y) >= 0.
struct Closest {
  std::optional<std::array<Q, 3>> y;
  Q dist2;
  std::array<Q, 6> lambda;  // F empty: Farkas multipliers; else KKT multipliers at y
};

// Box (or point) margins: per non-degenerate plane, max and min over B of the plane value,
// exactly, divided by |n| at the end.
struct Margins {
  double penetration = kInf;  // min_j max_B dist_j
  double protrusion = 0.0;    // max_j max(0, -min_B dist_j)
  double clearance = kInf;    // min_j min_B dist_j
};

// ---- the interval filter (oracle_filter.cpp) ------------------------------------------------

FilterAnswer filter_box(const CaseFrustum& f, const Volume& v);
FilterAnswer filter_sphere(const CaseFrustum& f, const Sphere& sp);

// ---- the exact route (oracle_exact.cpp) -------------------------------------------------------

/// Box (or point, or OBB) against F, exactly: a point of B ∩ F or Farkas multipliers.
Decision exact_box_route(const Planes& P, const detail::BoxT<ET>& b);
/// Ball against F, exactly; sets dist2 to the squared distance from the centre to F when the
/// closest-point QP ran.
Decision exact_sphere(const Planes& P, QCase& qc, const Sphere& sp, std::optional<Q>& dist2);
Closest closest_point_of_frustum(QCase& qc, const Planes& P, const std::array<ET, 3>& c);
/// Exact squared Euclidean distance between a box and F (nullopt when F is empty).
std::optional<Q> box_distance2(QCase& qc, const Planes& P, const detail::BoxT<ET>& b);

// ---- a candidate closest pair (oracle_closest.cpp) ---------------------------------------------

/// The closest pair of B (c + Σ t_i e_i, |t_i| <= 1; a point when every e_i is 0) and F, proven:
/// the squared distance, and with `want_point` the point y of F and multipliers λ (y - x =
/// Σ λ_j n_j, λ >= 0, non-zero on planes through y only: the KKT multipliers closest_point_of_frustum
/// returns). Found in double (GJK between B's corners and F's vertices, F bounded), solved exactly
/// on the constraints active there, and kept only when the QP's optimality conditions hold
/// exactly; nullopt otherwise (F empty or unbounded, the sets meet or nearly, a singular system, a
/// condition that fails): the exact QP then decides.
struct ClosestPair {
  Q dist2;
  std::array<Q, 3> y;
  std::array<Q, 6> lambda;
};
std::optional<ClosestPair> proven_closest_pair(const Planes& P, const detail::BoxT<ET>& b, bool want_point);

// ---- certificate checks (oracle_certificates.cpp) ---------------------------------------------

std::array<Q, 3> check_box_point(QCase& qc, const std::array<Q, 3>& t);
void check_sphere_point(QCase& qc, const Sphere& s, const std::array<Q, 3>& x);
detail::Coeffs<Q> check_separation(QCase& qc, const std::array<Q, 6>& lambda);
std::pair<int, std::optional<std::array<Q, 3>>> check_not_inside(QCase& qc);
Witness separation_witness(const std::array<Q, 6>& lambda, const detail::Coeffs<Q>& P);
Witness point_witness(const std::array<Q, 3>& x);

// ---- exact distances (oracle_distance.cpp) -----------------------------------------------------

Margins box_margins(const Planes& P, const detail::BoxT<ET>& b);
Margins sphere_margins(const Planes& P, const Sphere& sp);
void set_margin_distance(Result& r, const Margins& m);

}  // namespace cullproof::oracle::internal

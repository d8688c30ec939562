// The exact oracle. classify() runs its steps in order, as CGAL's Filtered_predicate does: the
// interval filter, else the exact route; then the certificate checked exactly; then the exact
// distance. Semantics are docs/semantics.md "The truth"; contracts are in cullproof/oracle/oracle.hpp.
//
// Every float reaches the exact route through an explicit lossless conversion (float -> double
// -> Gmpzf/Gmpq, both exact for binary floats). No tolerance appears anywhere: the filter only
// answers when its rounded-outward interval bounds prove the answer.

#include "oracle_internal.hpp"

#include <atomic>
#include <cmath>
#include <optional>
#include <string>

namespace cullproof::oracle {

namespace {

using namespace internal;

std::atomic<std::uint64_t> g_calls{0}, g_filtered{0}, g_fallbacks{0};

template <std::size_t N>
std::array<Q, N> q_array(const std::array<double, N>& a) {
  std::array<Q, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = Q(a[i]);
  return out;
}

// The case's exact numbers, converted once per call and only when a step needs them.
class ExactCase {
 public:
  ExactCase(const CaseFrustum& f, const Volume& v, const Options& o) : qc(f, v), f_(f), v_(v) { qc.guess = o.closest_in_double; }
  const Planes& planes() {
    if (!planes_) planes_ = exact_planes_et(f_);
    return *planes_;
  }
  detail::BoxT<ET> box() const { return detail::exact_box<ET>(v_, [](float x) { return et_of(x); }, ET(0.5)); }
  QCase qc;
  std::optional<Q> sphere_dist2;  // squared distance from the sphere's centre to F, once known

 private:
  const CaseFrustum& f_;
  const Volume& v_;
  std::optional<Planes> planes_;
};

// Step 1: the interval filter, else the exact route.
Decision decide(const CaseFrustum& f, const Volume& v, const Options& o, ExactCase& ec, Result& r) {
  const Sphere* sphere = std::get_if<Sphere>(&v);
  if (o.filter) {
    g_calls.fetch_add(1, std::memory_order_relaxed);
    const FilterAnswer fa = sphere ? filter_sphere(f, *sphere) : filter_box(f, v);
    if (fa.decided) {
      g_filtered.fetch_add(1, std::memory_order_relaxed);
      r.filtered = true;
      Decision d;
      d.truth = fa.truth;
      // The certificate in exact numbers, for the witness alone: the filter's bounds proved it.
      if (o.witness) {
        if (fa.truth == Visibility::outside) d.lambda = q_array(fa.lambda);
        else d.t_or_point = q_array(fa.pt);
      }
      return d;
    }
    g_fallbacks.fetch_add(1, std::memory_order_relaxed);
  }
  return sphere ? exact_sphere(ec.planes(), ec.qc, *sphere, ec.sphere_dist2) : exact_box_route(ec.planes(), ec.box());
}

// Step 2: the certificate. The filter's were proved by its interval bounds; the exact route's
// are checked here in Gmpq, in x-space. With Options::witness, every certificate (filtered or
// not) is re-checked exactly while it is written out.
void check(const Volume& v, const Options& o, const Decision& dec, ExactCase& ec, Result& r) {
  if (r.filtered && !o.witness) return;
  if (r.truth == Visibility::outside) {
    const auto P = check_separation(ec.qc, *dec.lambda);
    if (o.witness) r.witness = separation_witness(*dec.lambda, P);
    return;
  }
  std::array<Q, 3> x;
  if (const Sphere* sphere = std::get_if<Sphere>(&v)) {
    x = *dec.t_or_point;
    check_sphere_point(ec.qc, *sphere, x);
  } else {
    x = check_box_point(ec.qc, *dec.t_or_point);
  }
  if (o.witness) r.witness = point_witness(x);
  if (r.truth == Visibility::intersecting) {
    const auto [plane, corner] = check_not_inside(ec.qc);
    if (o.witness) {
      r.witness.violated_plane = plane;
      if (corner) r.witness.outside_corner = rationals(*corner);
    }
  }
}

// Step 3, outside: the exact Euclidean distance between the volume and F.
double outside_distance(const Volume& v, bool filtered, ExactCase& ec) {
  const Sphere* sphere = std::get_if<Sphere>(&v);
  if (!sphere) {
    const auto d2 = box_distance2(ec.qc, ec.planes(), ec.box());
    return d2 ? std::sqrt(approx(*d2)) : kInf;
  }
  // The exact route ended before its closest-point QP only when F is empty.
  if (!ec.sphere_dist2 && !filtered) return kInf;
  if (!ec.sphere_dist2) {
    const std::array<ET, 3> c{et_of(sphere->center.x), et_of(sphere->center.y), et_of(sphere->center.z)};
    const Closest cl = closest_point_of_frustum(ec.qc, ec.planes(), c);
    if (cl.y) ec.sphere_dist2 = cl.dist2;
  }
  if (!ec.sphere_dist2) return kInf;
  // dist(ball, F) = |y - c| - r = (|y-c|^2 - r^2) / (|y-c| + r), no cancellation.
  const Q rq = q_of(sphere->radius);
  const double num = approx(*ec.sphere_dist2 - rq * rq);
  return num / (std::sqrt(approx(*ec.sphere_dist2)) + double(sphere->radius));
}

// Step 3: how far from the boundary the case lies.
void measure(const Volume& v, ExactCase& ec, Result& r) {
  if (r.truth == Visibility::outside) {
    r.distance_kind = DistanceKind::euclidean;
    r.distance = outside_distance(v, r.filtered, ec);
    return;
  }
  const Sphere* sphere = std::get_if<Sphere>(&v);
  set_margin_distance(r, sphere ? sphere_margins(ec.planes(), *sphere) : box_margins(ec.planes(), ec.box()));
}

}  // namespace

// ---- public API ---------------------------------------------------------------------------------

Result classify(const CaseFrustum& f, const Volume& v, const Options& o) {
  detail::validate_case(f, v);
  Result r;
  r.distance = kNaN;
  ExactCase ec(f, v, o);
  const Decision dec = decide(f, v, o, ec, r);
  r.truth = dec.truth;
  check(v, o, dec, ec, r);
  if (o.distance) measure(v, ec, r);
  return r;
}

Result classify(const CaseFrustum& f, const Volume& v) { return classify(f, v, Options{}); }

Visibility truth(const CaseFrustum& f, const Volume& v) {
  Options o;
  o.distance = false;
  o.witness = false;
  return classify(f, v, o).truth;
}

double distance(const CaseFrustum& f, const Volume& v, Visibility truth) {
  detail::validate_case(f, v);
  Result r;
  r.truth = truth;
  r.filtered = true;  // no exact route ran: a ball's closest point is still to be found
  ExactCase ec(f, v, Options{});
  measure(v, ec, r);
  return r.distance;
}

std::string_view to_string(DistanceKind k) noexcept {
  switch (k) {
    case DistanceKind::euclidean: return "euclidean";
    case DistanceKind::margin: return "margin";
    case DistanceKind::clearance: return "clearance";
    case DistanceKind::none: break;
  }
  return "none";
}

nlohmann::json to_json(const Result& r) {
  nlohmann::json j;
  j["truth"] = std::string(cullproof::to_string(r.truth));
  if (std::isfinite(r.distance)) j["distance"] = r.distance;
  else j["distance"] = nullptr;
  j["distance_kind"] = to_string(r.distance_kind);
  j["filtered"] = r.filtered;
  j["witness"] = to_json(r.witness);
  return j;
}

std::string_view to_string(Witness::Kind k) noexcept {
  switch (k) {
    case Witness::Kind::point: return "point";
    case Witness::Kind::separating_plane: return "separating_plane";
    case Witness::Kind::none: break;
  }
  return "none";
}

nlohmann::json to_json(const Witness& w) {
  auto exact = [](const auto& values) {
    nlohmann::json a = nlohmann::json::array();
    for (const Rational& q : values) a.push_back(q.exact);
    return a;
  };
  auto approx = [](const auto& values) {
    nlohmann::json a = nlohmann::json::array();
    for (const Rational& q : values) a.push_back(q.approx);
    return a;
  };
  nlohmann::json j = nlohmann::json::object();
  if (w.kind == Witness::Kind::none) return j;
  j["kind"] = std::string(to_string(w.kind));
  if (w.kind == Witness::Kind::separating_plane) {
    j["plane"] = exact(w.plane);
    j["plane_approx"] = approx(w.plane);
    j["multipliers"] = exact(w.multipliers);
    return j;
  }
  j["point"] = exact(w.point);
  j["point_approx"] = approx(w.point);
  if (w.violated_plane >= 0) j["violated_plane"] = w.violated_plane;
  if (w.outside_corner) j["outside_corner"] = exact(*w.outside_corner);
  if (w.penetration) j["penetration"] = *w.penetration;
  if (w.protrusion) j["protrusion"] = *w.protrusion;
  return j;
}

Stats stats() noexcept {
  Stats s;
  s.calls = g_calls.load(std::memory_order_relaxed);
  s.filtered = g_filtered.load(std::memory_order_relaxed);
  s.fallbacks = g_fallbacks.load(std::memory_order_relaxed);
  s.exact_lp = g_exact_lp.load(std::memory_order_relaxed);
  s.closest_pairs = g_closest_pairs.load(std::memory_order_relaxed);
  return s;
}

void reset_stats() noexcept {
  g_calls.store(0);
  g_filtered.store(0);
  g_fallbacks.store(0);
  g_exact_lp.store(0);
  g_closest_pairs.store(0);
}

}  // namespace cullproof::oracle

// Geometry core: names, normalisation and validation of the shapes of docs/semantics.md.
#include "cullproof/core/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cullproof {

std::string_view to_string(Visibility v) noexcept {
  switch (v) {
    case Visibility::outside: return "outside";
    case Visibility::intersecting: return "intersecting";
    case Visibility::inside: return "inside";
  }
  return "invalid";
}

Visibility visibility_from_string(std::string_view s) {
  if (s == "outside") return Visibility::outside;
  if (s == "intersecting") return Visibility::intersecting;
  if (s == "inside") return Visibility::inside;
  throw std::invalid_argument("unknown visibility \"" + std::string(s) +
                              "\" (expected outside, intersecting or inside)");
}

Plane Plane::normalized() const noexcept {
  if (is_degenerate()) return *this;
  // Length in double so that huge or tiny coefficients neither overflow nor underflow.
  const double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
  return Plane{glm::vec3(float(n.x / len), float(n.y / len), float(n.z / len)), float(d / len)};
}

std::string_view plane_name(int index) noexcept {
  static constexpr std::string_view kNames[] = {"left", "right", "bottom", "top", "near", "far"};
  return (index >= 0 && index < 6) ? kNames[index] : std::string_view("invalid");
}

Frustum Frustum::normalized() const noexcept {
  Frustum f;
  for (int i = 0; i < kPlaneCount; ++i) f[i] = (*this)[i].normalized();
  return f;
}

unsigned volume_kind(const Volume& v) noexcept {
  switch (v.index()) {
    case 0: return kPointKind;
    case 1: return kSphereKind;
    case 2: return kAabbKind;
    default: return kObbKind;
  }
}

std::string_view volume_kind_name(unsigned kind_bit) noexcept {
  switch (kind_bit) {
    case kPointKind: return "point";
    case kSphereKind: return "sphere";
    case kAabbKind: return "aabb";
    case kObbKind: return "obb";
    default: return "invalid";
  }
}

float float_at_least(double v) noexcept {
  float f = static_cast<float>(v);
  if (double(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

float float_at_most(double v) noexcept {
  float f = static_cast<float>(v);
  if (double(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

Obb to_obb(const Aabb& b) noexcept {
  glm::vec3 c = b.center(), h = b.half_extent();
  // Where min + max or max - min overflows float (a box reaching across most of the range), from
  // the halves: 0.5 min + 0.5 max cannot overflow, and halving is exact for normal values, so it
  // rounds once as the sum would.
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(c[i])) c[i] = 0.5f * b.min[i] + 0.5f * b.max[i];
    if (!std::isfinite(h[i])) h[i] = 0.5f * b.max[i] - 0.5f * b.min[i];
  }
  return Obb{c, glm::mat3(1.0f), h};
}

namespace {

// The smallest float >= a - b (floats a >= b): the double difference and its rounding error
// (Knuth's TwoSum, exact for doubles), so that a rounded-down difference is rounded up.
float difference_at_least(float a, float b) noexcept {
  const double x = double(a), y = -double(b), s = x + y, yv = s - x, e = (x - (s - yv)) + (y - yv);
  return float_at_least(e > 0.0 ? std::nextafter(s, std::numeric_limits<double>::infinity()) : s);
}

// x + y for doubles: the sum rounded, and its rounding error, exactly (Knuth's TwoSum).
struct ExactSum {
  double sum, error;
};
ExactSum two_sum(double x, double y) noexcept {
  const double s = x + y, yv = s - x;
  return {s, (x - (s - yv)) + (y - yv)};
}

// The float bounds of c - e and c + e, for a float c and e >= 0 given as a rounded double
// with its error `e_error` (the exact e is e + e_error), rounded outward.
void outward(float c, double e, double e_error, float& lo, float& hi) noexcept {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const ExactSum l = two_sum(double(c), -e), h = two_sum(double(c), e);
  // Exact: lo = l.sum + l.error - e_error, hi = h.sum + h.error + e_error. Where anything was
  // rounded, a step of one double outward (far more than the errors) before rounding to float.
  const bool exact_lo = l.error == 0.0 && e_error == 0.0, exact_hi = h.error == 0.0 && e_error == 0.0;
  lo = float_at_most(exact_lo ? l.sum : std::nextafter(l.sum, -inf));
  hi = float_at_least(exact_hi ? h.sum : std::nextafter(h.sum, inf));
}

}  // namespace

Aabb enclosing_box(const Volume& v) noexcept {
  Aabb out;
  if (const auto* p = std::get_if<Point>(&v)) {
    out = Aabb{*p, *p};
  } else if (const auto* b = std::get_if<Aabb>(&v)) {
    out = *b;
  } else if (const auto* s = std::get_if<Sphere>(&v)) {
    for (int k = 0; k < 3; ++k) outward(s->center[k], double(s->radius), 0.0, out.min[k], out.max[k]);
  } else {
    const Obb& o = std::get<Obb>(v);
    for (int k = 0; k < 3; ++k) {
      // The extent along axis k, sum_i h_i |u_i[k]|: each product exact in double, the two sums
      // with their errors (all terms >= 0).
      const double t0 = double(o.half[0]) * std::abs(double(o.axes[0][k])), t1 = double(o.half[1]) * std::abs(double(o.axes[1][k])),
                   t2 = double(o.half[2]) * std::abs(double(o.axes[2][k]));
      const ExactSum a = two_sum(t0, t1), e = two_sum(a.sum, t2);
      outward(o.center[k], e.sum, a.error + e.error, out.min[k], out.max[k]);
    }
  }
  return out;
}

Obb enclosing_obb(const Aabb& b) noexcept {
  Obb o = to_obb(b);
  for (int i = 0; i < 3; ++i)
    o.half[i] = std::max(difference_at_least(b.max[i], o.center[i]), difference_at_least(o.center[i], b.min[i]));
  return o;
}

namespace {

[[noreturn]] void fail(std::string_view what, const std::string& problem) {
  throw ValidationError(std::string(what) + ": " + problem);
}

std::string comp_name(std::string_view what, int i) {
  return std::string(what) + "[" + std::to_string(i) + "]";
}

void check_finite(float x, const std::string& where) {
  if (std::isnan(x)) fail(where, "is NaN");
  if (std::isinf(x)) fail(where, x > 0 ? "is +infinity" : "is -infinity");
}

void check_vec(const glm::vec3& v, std::string_view what) {
  for (int i = 0; i < 3; ++i) check_finite(v[i], comp_name(what, i));
}

}  // namespace

void validate(const Point& p, std::string_view what) { check_vec(p, what); }

void validate(const Plane& p, std::string_view what) {
  check_vec(p.n, std::string(what) + ".n");
  check_finite(p.d, std::string(what) + ".d");
}

void validate(const Frustum& f, std::string_view what) {
  if (is_valid(f)) return;
  for (int i = 0; i < kPlaneCount; ++i)
    validate(f[i], std::string(what) + "." + std::string(plane_name(i)));
}

void validate(const Aabb& b, std::string_view what) {
  check_vec(b.min, std::string(what) + ".min");
  check_vec(b.max, std::string(what) + ".max");
  for (int i = 0; i < 3; ++i)
    if (b.min[i] > b.max[i])
      fail(what, "min[" + std::to_string(i) + "] = " + std::to_string(b.min[i]) + " > max[" +
                     std::to_string(i) + "] = " + std::to_string(b.max[i]));
}

void validate(const Obb& b, std::string_view what) {
  check_vec(b.center, std::string(what) + ".center");
  for (int i = 0; i < 3; ++i) {
    const std::string axis = std::string(what) + ".axes[" + std::to_string(i) + "]";
    check_vec(b.axes[i], axis);
    if (b.axes[i].x == 0.0f && b.axes[i].y == 0.0f && b.axes[i].z == 0.0f)
      fail(axis, "is a zero-length axis");
  }
  check_vec(b.half, std::string(what) + ".half");
  for (int i = 0; i < 3; ++i)
    if (b.half[i] < 0.0f)
      fail(comp_name(std::string(what) + ".half", i),
           "is negative (" + std::to_string(b.half[i]) + ")");
}

void validate(const Sphere& s, std::string_view what) {
  check_vec(s.center, std::string(what) + ".center");
  check_finite(s.radius, std::string(what) + ".radius");
  if (s.radius < 0.0f) fail(std::string(what) + ".radius", "is negative (" + std::to_string(s.radius) + ")");
}

namespace {

bool finite3(const glm::vec3& v) noexcept { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

bool is_valid(const Volume& v) noexcept {
  if (const auto* p = std::get_if<Point>(&v)) return finite3(*p);
  if (const auto* a = std::get_if<Aabb>(&v))
    return finite3(a->min) && finite3(a->max) && a->min.x <= a->max.x && a->min.y <= a->max.y && a->min.z <= a->max.z;
  if (const auto* o = std::get_if<Obb>(&v)) {
    bool ok = finite3(o->center) && finite3(o->half) && o->half.x >= 0.0f && o->half.y >= 0.0f && o->half.z >= 0.0f;
    for (int i = 0; i < 3; ++i) ok = ok && finite3(o->axes[i]) && o->axes[i] != glm::vec3(0.0f);
    return ok;
  }
  const Sphere& s = std::get<Sphere>(v);
  return finite3(s.center) && std::isfinite(s.radius) && s.radius >= 0.0f;
}

bool is_valid(const Frustum& f) noexcept {
  for (const Plane& p : f.planes)
    if (!finite3(p.n) || !std::isfinite(p.d)) return false;
  return true;
}

void validate(const Volume& v, std::string_view what) {
  if (is_valid(v)) return;  // the named checks below build strings: only on failure
  std::visit([&](const auto& x) { validate(x, what); }, v);
}

}  // namespace cullproof

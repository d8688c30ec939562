// cullproof geometry core: the shapes every culler, the oracle and the corpus speak.
//
// Semantics are fixed by docs/semantics.md:
//  - a point x is inside plane (n, d) when dot(n, x) + d >= 0; normals point into the frustum;
//  - a frustum is six planes, left, right, bottom, top, near, far, each a *closed* half-space;
//  - n == 0 with d > 0 is "all space" (infinite far plane), n == 0 with d < 0 is "nothing".
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>

namespace cullproof {

/// Three-way answer of a culler: the volume is outside the frustum, straddles it, or lies in it.
enum class Visibility : std::uint8_t { outside = 0, intersecting = 1, inside = 2 };

/// Stable lower-case name ("outside", "intersecting", "inside") used in reports and case files.
std::string_view to_string(Visibility v) noexcept;
/// Parses a name produced by to_string; throws std::invalid_argument naming the bad text.
Visibility visibility_from_string(std::string_view s);

/// A closed half-space {x : dot(n, x) + d >= 0}. Not necessarily normalised.
struct Plane {
  glm::vec3 n{0.0f};
  float d = 0.0f;

  /// Signed value of the plane equation at x, in float (dot(n, x) + d).
  float eval(const glm::vec3& x) const noexcept { return n.x * x.x + n.y * x.y + n.z * x.z + d; }
  /// True when n is exactly zero (the plane is all space or nothing).
  bool is_degenerate() const noexcept { return n.x == 0.0f && n.y == 0.0f && n.z == 0.0f; }
  /// Copy scaled to a unit normal (in float). A degenerate plane is returned unchanged: an
  /// infinite far plane stays "contains all space", with no NaN.
  Plane normalized() const noexcept;
};

/// Plane order inside a Frustum (docs/semantics.md: left, right, bottom, top, near, far).
enum PlaneIndex : int { kLeft = 0, kRight = 1, kBottom = 2, kTop = 3, kNear = 4, kFar = 5 };
inline constexpr int kPlaneCount = 6;
/// Stable plane names in the plane order of docs/semantics.md.
std::string_view plane_name(int index) noexcept;

/// The intersection of six closed half-spaces, in the plane order of docs/semantics.md. May be unbounded.
struct Frustum {
  std::array<Plane, 6> planes{};

  const Plane& operator[](int i) const noexcept { return planes[static_cast<std::size_t>(i)]; }
  Plane& operator[](int i) noexcept { return planes[static_cast<std::size_t>(i)]; }
  /// Every plane normalised (degenerate planes kept as they are).
  Frustum normalized() const noexcept;
};

/// Axis-aligned box; min <= max per component (equality allowed: flat, segment or point box).
struct Aabb {
  glm::vec3 min{0.0f};
  glm::vec3 max{0.0f};
  glm::vec3 center() const noexcept { return 0.5f * (min + max); }
  glm::vec3 half_extent() const noexcept { return 0.5f * (max - min); }
};

/// Oriented box: centre c, axes u0 u1 u2 (columns of `axes`), half-extents h >= 0.
/// The geometry is { c + sum t_i h_i u_i : |t_i| <= 1 } of the float values as given.
struct Obb {
  glm::vec3 center{0.0f};
  glm::mat3 axes{1.0f};
  glm::vec3 half{0.0f};
};

/// Closed ball; radius >= 0 (zero is a point).
struct Sphere {
  glm::vec3 center{0.0f};
  float radius = 0.0f;
};

/// A single point.
using Point = glm::vec3;

/// Any bounding volume a case may carry.
using Volume = std::variant<Point, Sphere, Aabb, Obb>;

/// Kinds of volume as bits, so a method can say which it takes.
enum VolumeKind : unsigned { kPointKind = 1u, kSphereKind = 2u, kAabbKind = 4u, kObbKind = 8u };
/// The kind bit of a volume.
unsigned volume_kind(const Volume& v) noexcept;
/// "point", "sphere", "aabb" or "obb".
std::string_view volume_kind_name(unsigned kind_bit) noexcept;

/// An OBB with the same geometry as the box (axes = identity columns): centre 0.5 (min + max)
/// and half-extents 0.5 (max - min), each rounded once to float, also where the float sum or
/// difference would overflow (then taken from the halves).
Obb to_obb(const Aabb& b) noexcept;
/// An OBB that holds the whole box: to_obb's centre, and half-extents that reach from it to both
/// faces, rounded up. to_obb's roundings can drop a sliver of the box (half an ulp of a subnormal
/// centre, say); a method that claims never to reject a visible box takes this one instead.
Obb enclosing_obb(const Aabb& b) noexcept;
/// The smallest float box that holds the whole volume: its extreme coordinates worked out with
/// their rounding errors (TwoSum) and rounded outward. What a system that culls objects by their
/// boxes tests. A volume whose extent overflows float gets infinite bounds.
Aabb enclosing_box(const Volume& v) noexcept;

/// Thrown when input geometry is invalid. what() names the field and the problem.
class ValidationError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// The smallest float >= v (v finite): rounds a double bound up without losing its guarantee.
float float_at_least(double v) noexcept;
/// The largest float <= v (v finite).
float float_at_most(double v) noexcept;

/// The conditions of validate() below, as a cheap yes/no (no message is built): every value
/// finite, min <= max, half-extents and radius >= 0, no zero-length OBB axis.
bool is_valid(const Volume& v) noexcept;
/// Every plane coefficient finite.
bool is_valid(const Frustum& f) noexcept;

/// Is this a valid point? Every component finite. Throws ValidationError naming `what`.
void validate(const Point& p, std::string_view what = "point");
/// Is this a valid plane? Every coefficient finite.
void validate(const Plane& p, std::string_view what = "plane");
/// Is this a valid frustum? Every plane valid. The message names the plane (e.g. "frustum.near").
void validate(const Frustum& f, std::string_view what = "frustum");
/// Is this a valid AABB? Finite, and min <= max per component.
void validate(const Aabb& b, std::string_view what = "aabb");
/// Is this a valid OBB? Finite, half-extents >= 0, no zero-length axis.
void validate(const Obb& b, std::string_view what = "obb");
/// Is this a valid sphere? Finite centre and radius, radius >= 0.
void validate(const Sphere& s, std::string_view what = "sphere");
/// Dispatches on the volume kind.
void validate(const Volume& v, std::string_view what = "volume");

}  // namespace cullproof

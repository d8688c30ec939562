// The building blocks of the case families (src/gen, not installed): random draws inside a
// RapidCheck generator, cameras and their frusta, where volumes are placed, exact frames; and each
// family's case, which the registry of distributions (distributions.cpp) names.
#pragma once

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/gen/generators.hpp"

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace cullproof::gen::detail {

// ---- Draws -----------------------------------------------------------------------------------
// Every random choice of a family is one integer(lo, hi), drawn one of three ways:
//  - inside rc::gen::exec (the property tests): from RapidCheck, shrinking towards lo;
//  - under a FastDraw (the campaign's cases and frames): the k-th draw is a function of the key
//    and k alone (splitmix64 of key + k * golden ratio, reduced to the range by Lemire's
//    multiply), no allocation, no shared state, so any case is drawn directly from its index and
//    on any thread; the values drawn may be logged;
//  - under a Replay inside rc::gen::exec: from RapidCheck, but each draw's value, until shrunk, is
//    the logged value of the same position (clamped to its range), so that the Shrinkable's root is
//    the case the FastDraw drew and its shrinks are RapidCheck's.

/// The draws of the enclosed code come from `key`'s stream (this thread, for the scope's life).
class FastDraw {
 public:
  explicit FastDraw(std::uint64_t key, std::vector<std::int64_t>* log = nullptr);
  ~FastDraw();
  FastDraw(const FastDraw&) = delete;
  FastDraw& operator=(const FastDraw&) = delete;

 private:
  friend std::int64_t integer(std::int64_t lo, std::int64_t hi);
  std::uint64_t key_, count_ = 0;
  std::vector<std::int64_t>* log_;
  FastDraw* outer_;
};

/// The draws of the enclosed code (run inside rc::gen::exec) start from `values` in order.
class Replay {
 public:
  explicit Replay(const std::vector<std::int64_t>& values);
  ~Replay();
  Replay(const Replay&) = delete;
  Replay& operator=(const Replay&) = delete;

 private:
  friend std::int64_t integer(std::int64_t lo, std::int64_t hi);
  const std::vector<std::int64_t>& values_;
  std::size_t next_ = 0;
  Replay* outer_;
};

/// An integer in [lo, hi] (lo <= hi), shrinking towards lo.
std::int64_t integer(std::int64_t lo, std::int64_t hi);
/// A double in [0, 1] (a multiple of 2^-30), shrinking towards 0.
double unit();
double in(double lo, double hi);
double log_in(double lo_exp10, double hi_exp10);
bool coin(int percent_true);
int pick(int n);
/// One of the values, shrinking towards the first.
template <class T, std::size_t N>
T one_of(const T (&values)[N]) {
  return values[std::size_t(pick(int(N)))];
}
glm::dvec3 unit_vector();
/// A rotation from three uniforms (Shoemake), as a float matrix: orthonormal only up to rounding.
glm::mat3 rotation();

// ---- Cameras -------------------------------------------------------------------------------
// What a camera generator decides; the matrix and the planes follow from it.
struct Camera {
  glm::vec3 eye{0.0f};
  glm::vec3 dir{0.0f, 0.0f, -1.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  bool ortho = false;
  float l = -1, r = 1, b = -1, t = 1;  // window at the near plane (ortho: the box)
  float n = 1, f = 100;
  bool infinite = false;
  DepthConvention depth;
  bool as_matrix = false;
  bool normalize = false;
};

/// A projection turned to reversed Z (depth 1 at the near plane) in the given range.
glm::mat4 reverse_depth(const glm::mat4& proj, DepthRange range);
glm::mat4 projection(const Camera& c, bool finite_only);
glm::mat4 view_matrix(const Camera& c);
CaseFrustum realize(const Camera& c);
/// The generic camera: anywhere, looking anywhere.
Camera generic_camera();
DepthConvention any_depth();

// ---- Placing volumes -----------------------------------------------------------------------
// The frustum's bounded part used to place volumes (an infinite far plane is brought in to
// 1000 near distances); corners in double.
struct Placement {
  std::array<glm::dvec3, 8> corner{};
  glm::dvec3 center{0.0};
  double size = 1.0;  // diameter
  bool ok = false;
};

Placement placement_of(const Frustum& f);
Placement placement_for(const Camera& c);
enum class Shape { point, sphere, aabb, obb };
Shape any_shape();
/// A volume of the given shape centred at c with typical half-size s (each axis 0.1..1 of s).
Volume volume_at(Shape shape, const glm::dvec3& c, double s);
double rel_size(double lo_exp, double hi_exp);
Volume near_boundary(const Placement& p, Shape shape, double s);
Volume near_corner(const Placement& p, Shape shape, double s);
GenCase make(const Camera& cam, const Placement& p, Volume v);
/// A volume of generic distribution d around placement p (its draws follow the camera's).
Volume generic_volume(Distribution d, const Placement& p);
/// The largest coordinate magnitude of a volume, its extent included (double: no overflow).
double volume_magnitude(const Volume& v);

// ---- Exact frames (touch.cpp) ----------------------------------------------------------------
// View space frustum with integer planes: glm::frustum(-n, n, -n, n, n, f) in [-1,1], so
// |x| <= -z, |y| <= -z, z in [-f, -n]; f/n in {2, 3, 5, 9} keeps every matrix entry dyadic. The
// world transform is an axis permutation with signs and an integer translation: exact.
struct ExactFrame {
  glm::mat3 rot{1.0f};  // world = rot * view + shift
  glm::vec3 shift{0.0f};
  float n = 1, f = 3;
};

ExactFrame exact_frame();
glm::mat4 view_of(const ExactFrame& e);
CaseFrustum exact_frustum(const ExactFrame& e, bool as_matrix);
glm::vec3 to_world(const ExactFrame& e, glm::vec3 v);
Aabb world_box(const ExactFrame& e, glm::vec3 lo, glm::vec3 hi);
/// A dyadic value in [lo, hi] with at most 4 fractional bits.
float dyadic(float lo, float hi);

// ---- The families: one case each -------------------------------------------------------------
GenCase generic_case(Distribution d);                   // generic.cpp
/// `frustum`: how the case's frustum is made from its frame (unset: the touch family's, planes or
/// an OpenGL matrix).
GenCase touch_case(bool nudge, const std::function<CaseFrustum(const ExactFrame&)>& frustum = nullptr);  // touch.cpp
/// touch_case's volume on frame e, its frustum made by `frustum` (called where touch_case draws it).
GenCase touch_on(const ExactFrame& e, bool nudge, const std::function<CaseFrustum()>& frustum);
/// A frame of the contact family: the frustum its volumes touch and what places them.
struct ContactFrame {
  bool ortho = true;         ///< an orthographic box (else the touch family's perspective frustum)
  ExactFrame e;
  float w = 1, f = 3;        ///< orthographic: |x|, |y| <= w, z in [-f, -e.n]
  bool unit_planes = false;  ///< orthographic, given as unit planes (where spheres are exact)
  CaseFrustum frustum;
};
ContactFrame contact_frame();                            // contact.cpp
GenCase contact_volume(const ContactFrame& frame);
GenCase contact_case();                                  // contact_volume(contact_frame())
GenCase far_offset_case();                               // hard.cpp
GenCase tiny_near_case();
GenCase reversed_infinite_case();
GenCase extreme_fov_case();
GenCase ill_conditioned_case();
GenCase rod_case();
GenCase huge_case();                                     // float_range.cpp
GenCase subnormal_case();
GenCase exact_touching_case();                           // integer_frusta.cpp
GenCase exact_containment_case();
GenCase exact_degenerate_case();
CameraPath make_camera_path();                           // camera_path.cpp

}  // namespace cullproof::gen::detail

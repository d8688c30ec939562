// Culling systems: how cullproof sees what an engine ships, its own or a user's.
//
// A culling test answers for one volume and one frustum; a culling *system* holds a scene: it is
// built over the scene's objects (a hierarchy, a grid, a flat list), told which objects moved, and
// asked every frame for the visible set of a camera. State kept between frames (plane masks,
// coherency caches, refitted boxes, last frame's answers) is the system's own and under test.
//
// A system is a description (SystemInfo: as a method's, see cullproof/methods/methods.hpp) and a
// builder. Its phases, in the order a run calls them:
//  - build(scene), once: returns the system's state for that scene;
//  - update(moved), before a frame in which objects moved: each moved object with its new
//    bounds (same id, new world volume and transform);
//  - cull(view, out), once per frame: the ids of the objects the system draws, each with its
//    verdict (inside or intersecting; a two-way system may leave `verdicts` empty: every listed
//    object is then visible, `intersecting`). An object not listed is `outside`.
// An object's truth on a frame is its world volume against the frame's frustum, decided exactly;
// a system that works from local bounds and transforms is judged against that world volume
// (the transform of the local volume, rounded once per coordinate) within its tolerance.
//
// make_system() turns three plain functions into a System:
//
//   cullproof::SystemInfo info;
//   info.name = "my-bvh";
//   info.claim = cullproof::Claim::conservative;
//   info.tolerance = 1e-6;
//   auto s = cullproof::make_system(info,
//       [](const cullproof::Scene& scene) { return MyBvh(scene); },                          // build
//       [](MyBvh& b, const std::vector<cullproof::SceneObject>& moved) { b.refit(moved); },  // update
//       [](MyBvh& b, const cullproof::CullView& v, cullproof::VisibleSet& out) { b.cull(v, out); });
//
// Contracts a run relies on: a system's state is used by one thread at a time; build may be
// called again for a new scene while an older state lives (each run builds its own). Ids are
// unique within a scene, stable across frames, and need not be dense.
#pragma once

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"
#include "cullproof/methods/methods.hpp"

#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace cullproof {

/// One object of a scene.
struct SceneObject {
  std::uint32_t id = 0;  ///< stable across frames, unique in the scene
  Volume world;          ///< the bounds the truth is decided on
  /// The bounds in the object's own frame and the transform to the world, for a system that
  /// works from local bounds (an instance's model-space box and its model matrix): `world` is
  /// `local` moved by `transform`, computed in double and rounded once. A rotation times a
  /// per-axis scale, then a translation; a sphere's scale is uniform.
  Volume local;
  glm::mat4 transform{1.0f};
};

/// A scene: the objects a system is built over.
struct Scene {
  std::string name;
  std::vector<SceneObject> objects;
};

/// The camera of one frame, as an engine has it.
struct CullView {
  CaseFrustum frustum;  ///< the world-space planes (and, when given, the clip matrix and depth convention)
  glm::mat4 view{1.0f}, projection{1.0f};  ///< frustum.matrix is projection * view when set
  glm::vec3 eye{0.0f};
  glm::mat3 axes{1.0f};  ///< columns right, up, back (the camera looks along -back)
  bool perspective = true;
};

/// A system's description: the fields of a method's (name, description, source, claim, tolerance,
/// volume kinds, touching, two- or three-way, origin, program); `stateful` is not used (every
/// system keeps its state from frame to frame). make_system leaves `volumes` at every kind when
/// it is 0.
using SystemInfo = MethodInfo;

/// What build() made of one scene.
class SystemState {
 public:
  virtual ~SystemState() = default;
  virtual void update(const std::vector<SceneObject>& moved) = 0;
  virtual void cull(const CullView& view, VisibleSet& out) = 0;
  /// The system's own time for its last cull in nanoseconds, where it reports one (a program's
  /// "ns", docs/protocol.md); NaN otherwise. cullproof's clock around cull() takes in what
  /// reaching the system costs (a program's messages), this does not.
  virtual double last_cull_ns() const { return std::numeric_limits<double>::quiet_NaN(); }
};

/// One system: its description and its builder.
class System : public SystemInfo {
 public:
  using Build = std::function<std::unique_ptr<SystemState>(const Scene&)>;
  System() = default;
  System(SystemInfo info, Build build);
  std::unique_ptr<SystemState> build(const Scene& scene) const { return build_(scene); }

 private:
  Build build_;
};

/// cullproof's own systems, in a stable order: the BVHs of the fast family over the objects'
/// enclosing boxes (plain, masked, plane-coherent, 4- and 8-wide masked), a flat loop, and the
/// hierarchy culler's coherent node tests (plane coherency with the octant test, with TR
/// coherency, with both: cullproof/systems/hierarchy.hpp).
const std::vector<System>& builtin_systems();
/// The built-in systems with these names, in this order; all when `names` is empty. Throws
/// std::invalid_argument naming an unknown name and listing the known ones.
std::vector<System> builtin_systems(const std::vector<std::string>& names);

namespace detail {

template <class S, class U, class C>
class MadeSystem final : public SystemState {
 public:
  MadeSystem(S state, std::shared_ptr<const U> update, std::shared_ptr<const C> cull)
      : state_(std::move(state)), update_(std::move(update)), cull_(std::move(cull)) {}
  void update(const std::vector<SceneObject>& moved) override { (*update_)(state_, moved); }
  void cull(const CullView& view, VisibleSet& out) override { (*cull_)(state_, view, out); }

 private:
  S state_;
  std::shared_ptr<const U> update_;
  std::shared_ptr<const C> cull_;
};

}  // namespace detail

/// A System from plain functions: build(const Scene&) returns the state by value;
/// update(state&, const std::vector<SceneObject>&) and cull(state&, const CullView&, VisibleSet&).
template <class B, class U, class C>
System make_system(SystemInfo info, B build, U update, C cull) {
  using S = std::decay_t<std::invoke_result_t<const B&, const Scene&>>;
  static_assert(std::is_invocable_v<const U&, S&, const std::vector<SceneObject>&>,
                "update must take (state&, const std::vector<cullproof::SceneObject>&)");
  static_assert(std::is_invocable_v<const C&, S&, const CullView&, VisibleSet&>,
                "cull must take (state&, const cullproof::CullView&, cullproof::VisibleSet&)");
  if (info.volumes == 0) info.volumes = kPointKind | kSphereKind | kAabbKind | kObbKind;
  auto upd = std::make_shared<const U>(std::move(update));
  auto cul = std::make_shared<const C>(std::move(cull));
  return System(std::move(info), [build = std::move(build), upd, cul](const Scene& scene) -> std::unique_ptr<SystemState> {
    return std::make_unique<detail::MadeSystem<S, U, C>>(build(scene), upd, cul);
  });
}

}  // namespace cullproof

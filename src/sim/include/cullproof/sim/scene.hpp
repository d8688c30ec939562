// cullproof::sim scenes: the scene file format "cullproof-scene/1", mesh reading, the world
// (instances of real meshes turned into a bounding-volume hierarchy), camera paths and
// projections. The simulator (simulate.hpp) runs the cullers over a scene frame by frame.
//
// A scene declares, and the simulator simulates, only what it declares: models (real
// meshes read from disk and a procedural floor), layouts (grid, row, scatter, single), the
// hierarchy's target size, the projection (perspective, off-axis, stereo pair, orthographic;
// a zoom only when declared), the camera path (keyframes, or one of the four path kinds of
// Assarsson & Möller 2000 §4) and moving objects (only when declared).
// The format is documented in corpus/scenes/README.md.
#pragma once

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/frustum_build.hpp"
#include "cullproof/core/geometry.hpp"
#include "cullproof/systems/system.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>
#include <string_view>

namespace cullproof::sim {

/// The format tag every scene file carries ("format": "cullproof-scene/1").
inline constexpr const char* kSceneFormat = "cullproof-scene/1";

// Limits of load_scene: a scene file past one is refused with a SceneError naming the file, the
// limit and the line, before it costs more than a small multiple of the limit in memory or time.
// The shipped scenes are about 1 KB, nest 4 deep (camera.keyframes[i].eye) and have lines of under
// 200 bytes; "reference" is free-form, hence room to spare.

/// Arrays and objects nested in a scene file; refused as soon as the parser opens the first
/// container past it.
inline constexpr int kMaxSceneDepth = 64;
/// Bytes of one line of a scene file (without its '\n').
inline constexpr std::size_t kMaxSceneLineBytes = std::size_t(1) << 20;  // 1 MiB
/// Bytes of a scene file (a regular file is refused by its size before it is read); about 200,000
/// keyframes.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t(16) << 20;  // 16 MiB

/// A bad scene file: what() is "<file>: <field>: <problem>" (field as a JSON path, e.g.
/// "camera.frames").
class SceneError : public std::runtime_error {
 public:
  SceneError(std::string file, std::string field, const std::string& problem);
  const std::string& file() const noexcept { return file_; }
  const std::string& field() const noexcept { return field_; }

 private:
  std::string file_, field_;
};

/// A bad or missing mesh file: what() is "<file>:<line>: <problem>" (line 0 when not per line).
class MeshError : public std::runtime_error {
 public:
  MeshError(std::string file, int line, const std::string& problem);
  const std::string& file() const noexcept { return file_; }
  int line() const noexcept { return line_; }

 private:
  std::string file_;
  int line_;
};

/// A triangle mesh. Polygons of the file are fan-triangulated; `polygons` counts the file's faces.
struct Mesh {
  std::vector<glm::vec3> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t polygons = 0;
};

/// Bytes of a mesh file (the shipped meshes are at most 2.6 MB); a regular file is refused by its
/// size before it is read.
inline constexpr std::uintmax_t kMaxMeshFileBytes = std::uintmax_t(256) << 20;  // 256 MiB
/// Bytes of one line of a mesh file (a face of some 100,000 vertices).
inline constexpr std::size_t kMaxMeshLineBytes = std::size_t(1) << 20;  // 1 MiB

/// Reads an OFF file (optional "OFF" header, '#' comments, vertex count, face count, edge count,
/// vertices, faces "k i0 .. ik-1" with optional colour). Throws MeshError naming file and line
/// for a missing file, a file or line past the limits above, bad counts, a non-finite coordinate,
/// an index out of range, a face with fewer than 3 vertices, or a truncated file (also when the
/// counts promise more than the file can hold: memory is set aside for what it can).
Mesh read_off(const std::filesystem::path& file);

/// Where meshes are looked up: $CULLPROOF_MESH_DIR, else ${XDG_CACHE_HOME:-$HOME/.cache}/
/// cullproof/meshes (the directory scripts/fetch-meshes fills).
std::filesystem::path default_mesh_dir();

// ---------------------------------------------------------------------------------------------
// Scene description (what the file says; no mesh I/O)

/// A model: a mesh file, scaled so its largest extent is `size`, its base centred on the origin
/// (bounding box min y = 0, centre x = z = 0), `up` naming the mesh axis that becomes +y.
struct ModelDesc {
  std::string id;
  std::string mesh;    ///< file name, looked up in the mesh directory
  double size = 1.0;   ///< largest extent after scaling, world units
  int up_axis = 1;     ///< 0 x, 1 y, 2 z: the mesh's up axis
};

/// Instances of one model. pattern: "single" (at origin), "row" (count along x), "grid"
/// (columns x rows, spacing), "scatter" (count at random positions in `area`, seeded).
struct InstanceGroup {
  std::string model;
  std::string pattern = "single";
  int count = 1;
  int columns = 1;
  double spacing = 1.0;
  glm::dvec3 origin{0.0};
  std::array<double, 4> area{0, 0, 0, 0};  ///< scatter: x0, z0, x1, z1
  double yaw_deg = 0.0;
  bool random_yaw = false;
  std::uint64_t seed = 1;
};

/// A procedural floor: tiles_x * tiles_z quads (two triangles each) centred at `center`.
struct FloorDesc {
  double size_x = 10.0, size_z = 10.0;
  int tiles_x = 1, tiles_z = 1;
  glm::dvec3 center{0.0};
};

/// The hierarchy: leaves of `leaf_triangles` triangles, or (when target_nodes > 0) the leaf size
/// whose node count is nearest to target_nodes.
struct HierarchyDesc {
  int target_nodes = 0;
  int leaf_triangles = 0;
};

enum class ProjectionKind { perspective, off_axis, stereo, orthographic };
/// "perspective", "off-axis", "stereo", "orthographic".
std::string_view to_string(ProjectionKind k) noexcept;

struct ProjectionDesc {
  ProjectionKind kind = ProjectionKind::perspective;
  double fovy_deg = 60.0, aspect = 4.0 / 3.0, near_dist = 0.1, far_dist = 200.0;
  /// off-axis: window at the near plane; orthographic: the view volume's x/y extent.
  double left = -1, right = 1, bottom = -1, top = 1;
  double eye_separation = 0.065, convergence = 2.0;  ///< stereo
  std::optional<double> zoom_fovy_end;  ///< perspective/stereo: fovy at the last frame (linear)
};

enum class PathKind { navigation, translation_rotation, rotation, translation, keyframes };
/// "navigation", "translation-rotation", "rotation", "translation", "keyframes".
std::string_view to_string(PathKind k) noexcept;
/// Parses the names above; std::nullopt for anything else.
std::optional<PathKind> path_kind_from_string(const std::string& s);

struct Keyframe {
  int frame = 0;
  glm::dvec3 eye{0.0};
  double yaw_deg = 0.0, pitch_deg = 0.0;  ///< yaw about +y from -z towards -x; pitch up
};

/// The camera path. The four A&M kinds (§4): navigation (path 1: segments of walking, turning,
/// looking around and standing, as a user at the keyboard; synthetic, seeded), translation-
/// rotation (path 2: both every frame), rotation (path 3: pure rotations about one camera axis at
/// a time), translation (path 4: pure translations, fixed orientation). `speed` is world units per
/// frame, `turn_deg` degrees per frame; the path stays inside `bounds` (x0, z0, x1, z1).
struct CameraPathDesc {
  PathKind kind = PathKind::navigation;
  int frames = 100;
  double speed = 0.1, turn_deg = 1.0;
  std::uint64_t seed = 1;
  glm::dvec3 eye{0.0, 1.7, 0.0};
  double yaw_deg = 0.0, pitch_deg = 0.0;
  std::optional<std::array<double, 4>> bounds;
  std::vector<Keyframe> keyframes;  ///< kind keyframes: eye and angles interpolated linearly
};

/// A declared moving object: instances of a group (by index in layout order) that move each
/// frame: "spin" (yaw about the instance's own vertical axis, deg/frame), "translate" (velocity
/// per frame), "orbit" (about `center` on the floor, deg/frame).
struct MovingDesc {
  int group = 0;
  std::vector<int> instances;  ///< indices within the group; empty: all of them
  std::string motion = "spin";
  double rate = 1.0;
  glm::dvec3 velocity{0.0};
  glm::dvec3 center{0.0};
};

struct SceneDesc {
  std::string file;  ///< where it was read from (for messages)
  std::string name, description;
  std::vector<ModelDesc> models;
  std::vector<InstanceGroup> groups;
  std::optional<FloorDesc> floor;
  HierarchyDesc hierarchy;
  ProjectionDesc projection;
  CameraPathDesc camera;
  std::vector<MovingDesc> moving;
  nlohmann::json reference;  ///< free-form ("assarsson-moller-2000": {"model": 1, ...})
};

/// Parses and validates a scene. Throws SceneError naming `source` and the field for: wrong or
/// missing format tag, a missing or mistyped field, an unknown key, an unknown enum value, a
/// non-positive size/count/frame count, near >= far, fov outside (0, 180), an unknown model
/// reference, a moving group or instance out of range, keyframes not increasing.
SceneDesc parse_scene(const nlohmann::json& j, const std::string& source = "<scene>");
/// Parses and validates the text of a scene file (parse errors name `source` and the line). Throws
/// SceneError, also for text past kMaxSceneFileBytes, a line past kMaxSceneLineBytes or nesting past
/// kMaxSceneDepth.
SceneDesc parse_scene_text(std::string_view text, const std::string& source = "<scene>");
/// Reads a scene file (parse_scene_text). Throws SceneError, also for a file that cannot be read or
/// is past kMaxSceneFileBytes.
SceneDesc load_scene(const std::filesystem::path& file);

// ---------------------------------------------------------------------------------------------
// The built world

/// One placed model: world = translation * rotation * scale (model space = the mesh normalised).
struct Instance {
  int group = -1;       ///< -1: the floor
  int index_in_group = 0;
  std::string model;
  glm::dmat3 rotation{1.0};
  glm::dvec3 position{0.0};
  std::uint32_t root = 0;        ///< its subtree root node
  std::uint32_t node_end = 0;    ///< its subtree is nodes [root, node_end)
  std::size_t triangles = 0;
  bool moving = false;
};

/// The scene as a hierarchy. `bvh` is a cullproof::Bvh whose primitives are the leaves (clusters
/// of at most leaf_triangles triangles of one instance); every leaf node holds exactly one
/// primitive whose box equals the leaf's box; top levels group instances (median split of their
/// centres), each instance's subtree splits its triangles at the median on the longest axis of
/// the centroid bounds, rounded to a multiple of the leaf size. Node boxes are exact min/max of
/// their children.
struct World {
  Bvh bvh;
  std::vector<std::int32_t> parent;         ///< per node; -1 at the root
  std::vector<std::int32_t> node_instance;  ///< per node: instance index, -1 for top levels
  std::vector<std::uint32_t> leaf_node;     ///< per leaf (primitive index): its node
  std::vector<Aabb> local_box;              ///< per instance node: box in the instance's model space
  std::vector<Instance> instances;
  std::size_t triangles = 0, polygons = 0;
  std::uint32_t leaf_triangles = 0;
  Aabb bounds;
  std::uint32_t node_count() const noexcept { return static_cast<std::uint32_t>(bvh.nodes.size()); }
  std::uint32_t leaf_count() const noexcept { return static_cast<std::uint32_t>(leaf_node.size()); }
};

/// Reads the meshes (from `mesh_dir`) and builds the world. A missing mesh throws MeshError
/// naming the file, the scene field and the command that provides it (scripts/fetch-meshes).
World build_world(const SceneDesc& scene, const std::filesystem::path& mesh_dir = default_mesh_dir());

/// Moves the declared moving instances to their pose at `frame` (0-based) and refits: their
/// nodes get the AABB of the transformed model-space box (leaves) or the exact union of their
/// children, their top-level ancestors are refitted. Returns the nodes whose box changed
/// (including ancestors), sorted. Frame 0 is the layout pose.
std::vector<std::uint32_t> move_objects(const SceneDesc& scene, World& world, int frame);

// ---------------------------------------------------------------------------------------------
// Camera path and projection per frame

/// Camera motion between two consecutive frames, as built by the path (not detected).
enum class FrameMotion { first, still, translation, rotation, general };
std::string_view to_string(FrameMotion m) noexcept;

struct CameraFrame {
  glm::dvec3 eye{0.0};
  glm::dmat3 axes{1.0};  ///< columns right, up, back (looks along -back)
  double fovy_deg = 60.0;
  FrameMotion motion = FrameMotion::first;
};

/// The whole path: frames camera poses, deterministic for a scene.
std::vector<CameraFrame> camera_path(const SceneDesc& scene, const World& world);

/// One view of a frame (a stereo frame has two): clip matrix, world-space planes (Gribb–Hartmann
/// from the float clip matrix), the eye pose in float.
struct View {
  glm::mat4 clip{1.0f};
  glm::mat4 proj{1.0f};  ///< the projection alone (clip = proj * look)
  glm::mat4 look{1.0f};  ///< the view matrix
  DepthConvention depth{};
  Frustum frustum;
  glm::vec3 eye{0.0f};
  glm::mat3 axes{1.0f};
  bool perspective = true;
};

/// The views of one frame: 1, or 2 for a stereo pair (left eye, right eye). The view matrix is
/// built from the float pose directly (not lookAt), so a pure translation keeps every plane
/// normal bitwise identical.
std::vector<View> frame_views(const ProjectionDesc& projection, const CameraFrame& frame);

/// A view as a culling system gets it (the planes, the clip matrix and its depth convention, the
/// view and projection matrices, the pose).
CullView cull_view(const View& view);

}  // namespace cullproof::sim

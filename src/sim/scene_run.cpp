// A real-mesh scene as a culling-system run (cullproof/sim/scene_run.hpp, mesh_scene_run): the
// world's leaves as the scene's objects, its camera path as frames, its moving instances as moves.
#include "cullproof/sim/scene_run.hpp"

#include <algorithm>
#include <unordered_map>

namespace cullproof::sim {

namespace {

// What the camera did, in the words of scenes::RunFrame::camera.
std::string camera_event(const CameraFrame& c, const CameraFrame* previous) {
  if (!previous) return "first";
  if (c.fovy_deg != previous->fovy_deg) return "zoom";
  switch (c.motion) {
    case FrameMotion::first: return "first";
    case FrameMotion::still: return "still";
    case FrameMotion::translation: return "translate";
    case FrameMotion::rotation: return "turn";
    case FrameMotion::general: return "general";
  }
  return "general";
}

SceneObject leaf_object(const World& w, std::uint32_t leaf) {
  SceneObject o;
  o.id = leaf;
  o.world = Volume(w.bvh.prim_boxes[leaf]);
  o.local = o.world;  // a leaf's box is taken in the world: no local bounds
  return o;
}

}  // namespace

scenes::SceneRun mesh_scene_run(const SceneDesc& scene, const std::filesystem::path& mesh_dir) {
  World world = build_world(scene, mesh_dir);
  scenes::SceneRun run;
  run.family = "scene-" + scene.name;
  run.scene.name = scene.name;
  run.motion = scene.moving.empty() ? "static" : "moving instances";
  if (!scene.moving.empty()) move_objects(scene, world, 0);
  // The world's primitive order is its leaf order: leaf k is primitive k.
  std::unordered_map<std::uint32_t, std::uint32_t> leaf_of_node;
  for (std::uint32_t k = 0; k < world.leaf_count(); ++k) {
    leaf_of_node.emplace(world.leaf_node[k], k);
    run.scene.objects.push_back(leaf_object(world, k));
  }
  const std::vector<CameraFrame> path = camera_path(scene, world);
  for (std::size_t f = 0; f < path.size(); ++f) {
    std::vector<SceneObject> moved;
    if (f > 0 && !scene.moving.empty()) {
      for (std::uint32_t node : move_objects(scene, world, static_cast<int>(f))) {
        const auto it = leaf_of_node.find(node);
        if (it != leaf_of_node.end()) moved.push_back(leaf_object(world, it->second));
      }
      std::sort(moved.begin(), moved.end(), [](const SceneObject& a, const SceneObject& b) { return a.id < b.id; });
    }
    const std::vector<View> views = frame_views(scene.projection, path[f]);
    for (std::size_t v = 0; v < views.size(); ++v) {
      scenes::RunFrame rf;
      rf.view = cull_view(views[v]);
      rf.camera = v == 0 ? camera_event(path[f], f > 0 ? &path[f - 1] : nullptr) : "eye";
      if (v == 0) rf.moved = std::move(moved);
      run.frames.push_back(std::move(rf));
    }
  }
  return run;
}

}  // namespace cullproof::sim

// A real-mesh scene (cullproof/sim/scene.hpp) as a culling system's run (cullproof/scenes/scenes.hpp).
#pragma once

#include "cullproof/scenes/scenes.hpp"
#include "cullproof/sim/scene.hpp"

#include <filesystem>

namespace cullproof::sim {

/// The scene as a culling-system run (cullproof/scenes/scenes.hpp), judged as the generated
/// families are: every leaf of the world (a box of a few triangles of one instance, or of the
/// floor) is an object, its id the leaf's index and its volume the leaf's box; every view of every
/// frame of the camera path is a frame (a stereo pair's second view is the event "eye"; a change
/// of field of view "zoom", a move and turn at once "general"); the moving instances' leaves move.
/// The run's family is "scene-" + the scene's name, its seed and index 0. Reads the meshes from
/// `mesh_dir` (MeshError as build_world).
scenes::SceneRun mesh_scene_run(const SceneDesc& scene, const std::filesystem::path& mesh_dir = default_mesh_dir());

}  // namespace cullproof::sim

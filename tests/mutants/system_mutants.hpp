// Planted-bug culling systems and their correct controls: a hierarchy culler written as a user
// would write one against the public API (cullproof::build_bvh for the tree, its own traversal
// with plane masks), with one of the bugs users report planted in each mutant.
#pragma once

#include "cullproof/systems/system.hpp"

#include <string>
#include <vector>

namespace cullproof::mutants {

enum class SystemBug {
  none,                ///< control: masks handed to children, boxes refitted, planes from the matrix
  skip_near,           ///< the near plane missing from the loop
  skip_far,            ///< the far plane skipped although the projection is finite
  mask_to_sibling,     ///< the plane mask a child leaves handed to its sibling instead of the parent's
  one_frame_late,      ///< last frame's visible set answered (results used a frame late)
  no_refit,            ///< a moved object's leaf updated, its ancestors' boxes not refitted
  unscaled_instances,  ///< bounds from local bounds and the model matrix with its scale dropped
  half_nearest,        ///< bounds stored in half precision rounded to nearest (a radius shrinks)
  cache_keyed_on_eye,  ///< last frame's set reused while the eye has not moved (turns, zooms, cuts kept)
  perspective_rebuilt, ///< an orthographic camera's frustum rebuilt from perspective parameters
  tr_unchecked,        ///< TR offsets kept across turns and cuts (the plane normals not compared)
};

/// One system of the mutation table: a mutant, or a control (a correct system through the same
/// code path as the mutants it stands beside).
struct SystemMutant {
  std::string name;
  std::string bug;  ///< what is planted ("" for a control)
  SystemBug kind = SystemBug::none;
  /// For the bounds variants: how the control builds its bounds (see make_system_mutant).
  enum class Bounds { world, local, half_outward } bounds = Bounds::world;
  bool matrix_keyed_cache = false;  ///< the control of cache_keyed_on_eye
  /// Translation coherency (Assarsson & Möller 2000, §3.5): a node rejected by a plane keeps that
  /// plane's p-vertex value and offset, and while the plane's normal is unchanged (the camera only
  /// translated) the node stays rejected until the offset has moved it across. The control of
  /// tr_unchecked.
  bool tr_offsets = false;
  bool control() const noexcept { return kind == SystemBug::none; }
};

/// The mutants and their controls, in table order.
const std::vector<SystemMutant>& system_mutants();
/// The system of one row (claim conservative, tolerance 1e-6, origin user).
System make_system_mutant(const SystemMutant& m);

}  // namespace cullproof::mutants

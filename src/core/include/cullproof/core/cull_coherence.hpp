// cullproof frame-coherent (stateful) cullers: Assarsson & Möller 2000 §3.2 plane coherency,
// §3.3 octant test, §3.5 TR (translation/rotation) coherency. Usable over a sequence of frames
// by a scene simulator: the culler holds per-frame data, the caller keeps one small state object
// per scene object and passes it with the object's box.
//
// Every culler states when it is valid and throws CullerPreconditionError (a
// std::invalid_argument naming the culler and the reason) for a frustum it cannot handle.
#pragma once

#include "cullproof/core/cull.hpp"

#include <cstdint>
#include <stdexcept>

namespace cullproof {

/// Thrown when a stateful culler is given a frustum (or pose) it is not valid for.
/// what() starts with the culler's method name, e.g. "octant: frustum is not symmetric ...".
class CullerPreconditionError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// ---------------------------------------------------------------------------------------------
// Plane coherency (src/core/cull/plane_coherency.cpp)

/// Per-object cache of the plane-coherency test: the plane that rejected the box last time.
struct PlaneCoherencyCache {
  std::int8_t last_outside_plane = -1;  ///< plane index 0..5, or -1 for none
};

/// A&M §3.2: test the cached plane first, then the others in the order left, right, near, far,
/// top, bottom; each with the n/p-vertex test of §3.1. Updates the cache when a plane rejects.
/// Valid for every frustum; verdicts equal pn_vertex. Adds the planes tested to *plane_tests.
Visibility plane_coherency_test(const Frustum& frustum, const Aabb& box, PlaneCoherencyCache& cache,
                                std::uint64_t* plane_tests = nullptr) noexcept;

// ---------------------------------------------------------------------------------------------
// Octant test (src/core/cull/octant.cpp)

/// A&M §3.3: for a symmetric frustum, a box whose centre-to-corner distance d2 is at most the
/// distance d1 from the frustum centre (mean of the 8 corners) to its nearest plane is tested
/// against the three outer planes of the octant holding the box centre only. Boxes that fail
/// the fig. 6 precondition get the full six-plane test.
class OctantCuller {
 public:
  /// Per-frame set-up. Throws CullerPreconditionError when the frustum is unbounded or not
  /// symmetric (is_symmetric(frustum, 1e-5)): the octant test is only valid for symmetric
  /// frusta (A&M footnote 6).
  explicit OctantCuller(const Frustum& frustum);
  /// As published: n/p-vertex test against the three outer planes.
  Visibility classify(const Aabb& box) const noexcept;
  /// Corrected: the three outer planes are tested as given (not normalised: a box touching a plane
  /// is not culled for what normalisation rounds), `outside` when one rejects; `inside` only when
  /// those three accept the whole box and either the box's bounding sphere is inside both planes
  /// of every pair, by more than what evaluating in double can round, or the n/p-vertex tests of
  /// the three inner planes confirm it. The fig. 6 fallback is the n/p-vertex test on the given
  /// planes.
  Visibility classify_corrected(const Aabb& box) const noexcept;
  /// classify_corrected, counting its plane tests in `tests` (the fig. 6 fallback counts six) and
  /// setting `rejecting` to the outer plane that rejected the box (left as it was otherwise).
  Visibility classify_corrected(const Aabb& box, std::uint64_t& tests, std::int8_t& rejecting) const noexcept;
  /// For a frustum whose projection the one-argument constructor accepted, moved rigidly (a
  /// rigid camera motion keeps the frustum symmetric and its centre distance): no checks, d1 as
  /// given (<= 0: the octant never applies, every box takes the fallback).
  OctantCuller(const Frustum& frustum, double centre_distance);
  /// d1: distance from the frustum centre to its nearest plane.
  double centre_distance() const noexcept { return d1_; }

 private:
  Frustum given_;        // as the frustum came
  Frustum planes_;       // normalised (as published)
  double inv_len_[6] = {};  // 1 / |n| of the given planes, in double
  double d1_ = 0.0;
  double d1_sq_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// TR coherency (src/core/cull/tr_coherency.cpp)

/// Camera pose for rotation bookkeeping: eye position and the camera axes as columns
/// (right, up, back); the camera looks along -axes[2] (OpenGL / gluLookAt convention).
struct CameraPose {
  glm::vec3 eye{0.0f};
  glm::mat3 axes{1.0f};
};
/// The pose of a gluLookAt camera.
CameraPose camera_pose(const PerspectiveCamera& cam);

/// Per-object state of the TR coherency culler (one per scene object, owned by the caller).
struct TrObjectState {
  Aabb box;                         ///< the box at the last full test; a different box = moved
  std::uint64_t test_frame = 0;     ///< frame of the last full test or translation update; 0 = never
  double angle_at_test = 0.0;       ///< the culler's accumulated rotation at that frame
  float p_value[6] = {};            ///< plane value at the p-vertex (max over the box)
  float n_value[6] = {};            ///< plane value at the n-vertex (min over the box)
  std::uint8_t outside_bits = 0;    ///< bit i: the box was outside plane i
};

/// A&M §3.5: (2) after a pure translation every plane keeps its normal and its value moves by
/// the same delta_i = d_i(now) - d_i(before) for every point, so stored n/p-vertex values are
/// updated without touching the box; (1) after a pure rotation about one camera axis, a box that
/// was outside the plane the frustum turns away from stays outside while the accumulated
/// rotation is below 180 degrees minus the frustum's opening angle between that pair of planes
/// (about z, the roll, near and far are unchanged: no limit). Objects that moved (a different
/// box) get a full test. Full tests evaluate all six planes (no early exit) so the distances are
/// known next frame. Verdicts of full tests equal pn_vertex.
class TrCoherencyCuller {
 public:
  /// What happened to the camera since the previous frame.
  enum class Motion { first, still, translation, rotation_x, rotation_y, rotation_z, general };

  /// Starts a frame without a pose: translation coherency only (detected from the planes: all
  /// six normals bitwise equal to the previous frame's). Valid for every frustum.
  void begin_frame(const Frustum& frustum);
  /// Starts a frame with the camera pose: adds rotation coherency. Throws
  /// CullerPreconditionError unless the frustum is a perspective frustum of this pose: axes
  /// orthonormal, left/right/bottom/top planes through the eye, left/right parallel to the up
  /// axis, bottom/top parallel to the right axis, near/far normals along the view axis
  /// (relative tolerance 1e-4). Orthographic frusta are refused (use begin_frame(frustum)).
  void begin_frame(const Frustum& frustum, const CameraPose& pose);
  /// Classifies a box (not moved since last frame or moved: both handled), updating its state.
  Visibility classify(const Aabb& box, TrObjectState& state) noexcept;

  Motion motion() const noexcept { return motion_; }
  /// Accumulated rotation of the current pure-rotation run, radians.
  double accumulated_rotation() const noexcept { return angle_total_ - epoch_base_angle_; }
  /// Rotation limit of the current run (radians; infinity for roll), 0 when none is active.
  double rotation_limit() const noexcept { return rotation_valid_ ? limit_ : 0.0; }

  struct Stats {
    std::uint64_t full_tests = 0, translation_updates = 0, rotation_rejects = 0;
  };
  Stats stats;

 private:
  void start(const Frustum& frustum);
  Visibility full_test(const Aabb& box, TrObjectState& st) noexcept;

  Frustum planes_{}, prev_planes_{};
  bool has_prev_ = false, has_pose_ = false, prev_has_pose_ = false;
  CameraPose pose_{}, prev_pose_{};
  std::uint64_t frame_ = 0;
  Motion motion_ = Motion::first;
  bool translation_valid_ = false;
  float delta_[6] = {};
  // Rotation run: frames epoch_start_frame_ .. frame_ are linked by rotations about one axis in
  // one direction. angle_total_ grows by |theta| each rotation frame.
  bool rotation_valid_ = false;
  int rot_axis_ = -1, rot_sign_ = 0;
  std::uint64_t epoch_start_frame_ = 0;
  double angle_total_ = 0.0, epoch_base_angle_ = 0.0, limit_ = 0.0;
  std::uint8_t allowed_bits_ = 0;
};

}  // namespace cullproof

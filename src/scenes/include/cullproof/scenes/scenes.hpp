// Scenes to cull and a system judged on them, every object of every frame.
//
// A scene run is a scene (objects), a camera path (frames) and the objects that move between
// frames, drawn from a family by (seed, index): the same seed and index give the same run on every
// machine (splitmix64, no standard-library distribution). The families stress what hierarchies
// get wrong: dense clusters beside sparse fields, objects straddling the split planes of a
// hierarchy, tiny objects along the frustum's planes and corners, a few huge objects, instances
// given as local bounds with rotation and non-uniform scale, scenes far from the origin. In half
// the runs of every family some objects move (drift, teleport, oscillate across a frustum plane,
// grow). The camera translates, turns, rolls, zooms, cuts to another place, switches projection
// and renders stereo pairs, through every projection cullproof knows: perspective and off-axis,
// orthographic, reversed-Z, infinite far, both depth ranges.
//
// Judging: each frame the system's visible set is checked (ids of the scene, none twice, a verdict
// per id) and every object's verdict compared with the exact truth of its world volume against
// the frame's frustum (the clip matrix, end to end), under the system's claim as a method's is
// (docs/semantics.md "Claims"): error classes, the distance an error lies from being right, the
// rounding allowance only where the case rounds.
#pragma once

#include "cullproof/io/case_io.hpp"
#include "cullproof/judge/judge.hpp"
#include "cullproof/systems/system.hpp"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace cullproof::scenes {

/// One frame of a run.
struct RunFrame {
  CullView view;
  /// The objects that moved since the previous frame, with their new bounds (update() before cull).
  std::vector<SceneObject> moved;
  /// What the camera did since the previous frame: "first", "still", "translate", "turn", "roll",
  /// "zoom", "cut" (another place and direction), "projection" (another projection kind), "eye"
  /// (the other eye of a stereo pair).
  std::string camera;
};

/// A scene, its camera path and its motions.
struct SceneRun {
  std::string family;
  std::uint64_t seed = 0, index = 0;
  Scene scene;
  std::vector<RunFrame> frames;
  /// What moves ("static", or the motions used, e.g. "drift, teleport").
  std::string motion;
};

/// The scene families, in a stable order: name and one line on what each makes.
struct FamilyInfo {
  std::string_view name, description;
};
const std::vector<FamilyInfo>& families();
/// Family names from a name or "all"; throws std::invalid_argument naming the unknown one and listing the known.
std::vector<std::string> parse_families(std::string_view name);

/// The size of a run.
struct RunSize {
  std::size_t objects = 200;
  std::size_t frames = 12;
};

/// Run `index` of `family` for `seed`. Throws std::invalid_argument for an unknown family or
/// more than kMaxObjects objects.
SceneRun draw_run(std::string_view family, std::uint64_t seed, std::uint64_t index, const RunSize& size = {});
inline constexpr std::size_t kMaxObjects = 1000000;

/// A system faulted: it threw in a phase, or answered a visible set that is not one (an id not in
/// the scene, an id twice, verdicts that do not match the ids, `outside` listed, `inside` from a
/// two-way system). what() names the system, the phase, the frame and the problem.
class SystemFault : public std::runtime_error {
 public:
  SystemFault(const std::string& what, std::size_t frame) : std::runtime_error(what), frame_(frame) {}
  /// The frame the fault happened in (0 for build).
  std::size_t frame() const noexcept { return frame_; }

 private:
  std::size_t frame_;
};

/// One object on one frame that the system got wrong.
struct Finding {
  std::size_t frame = 0;
  std::uint32_t id = 0;
  std::size_t object = 0;  ///< its position in the scene
  Visibility verdict = Visibility::outside, truth = Visibility::outside;
  ErrorClass error = ErrorClass::correct;
  double distance = 0.0;  ///< error_distance: how far the verdict is from being right (when measured)
  bool breaks_claim = false;
};

/// What a system did on one run.
struct RunJudgement {
  std::uint64_t judged = 0;  ///< object-frames
  std::uint64_t by_class[5] = {};  ///< per ErrorClass
  std::uint64_t claim_broken = 0;
  /// The first object-frame that breaks the claim, else the first error of any class.
  std::optional<Finding> first_broken, first_error;
  double cull_seconds = 0.0;  ///< build, updates and culls
  double judge_seconds = 0.0;  ///< the exact truth of every object-frame
};

/// Runs `system` over `run` (build, then per frame update and cull) and judges every object of
/// every frame. Throws SystemFault on a fault.
RunJudgement judge_run(const System& system, const SceneRun& run);

/// A system's visible set as verdicts by scene position (outside where not listed), checked as
/// SystemFault describes; `position` maps ids to scene positions.
void verdicts_by_position(const SystemInfo& info, const std::unordered_map<std::uint32_t, std::size_t>& position,
                          const VisibleSet& set, std::vector<Visibility>& out);

/// A run's object-frame as a case of the case format (the frame's frustum, the object's world
/// volume; id "<family>-<index>-f<frame>-o<id>"), for printing and for `cullproof classify`.
Case case_of(const SceneRun& run, std::size_t frame, std::size_t object);

}  // namespace cullproof::scenes

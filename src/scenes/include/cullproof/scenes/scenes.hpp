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

#include "cullproof/core/certified.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/judge/judge.hpp"
#include "cullproof/systems/system.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
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
  /// (the other eye of a stereo pair); in a real-mesh scene's run also "general" (the camera
  /// moved and turned at once).
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
  SystemFault(const std::string& what, std::size_t frame, std::shared_ptr<const SceneRun> run = nullptr)
      : std::runtime_error(what), frame_(frame), run_(std::move(run)) {}
  /// The frame the fault happened in (0 for build).
  std::size_t frame() const noexcept { return frame_; }
  /// The run it happened on, when verify_system drew it (to save and rerun).
  const std::shared_ptr<const SceneRun>& run() const noexcept { return run_; }

 private:
  std::size_t frame_;
  std::shared_ptr<const SceneRun> run_;
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
  std::uint64_t truth_outside = 0;  ///< object-frames whose truth is outside (the false-intersect rate's denominator)
  std::uint64_t by_class[5] = {};  ///< per ErrorClass
  std::uint64_t claim_broken = 0;
  /// The first object-frame that breaks the claim, else the first error of any class.
  std::optional<Finding> first_broken, first_error;
  double cull_seconds = 0.0;  ///< build, updates and culls
  double judge_seconds = 0.0;  ///< the exact truth of every object-frame
  /// The system's own time for its culls, where it reports one (SystemState::last_cull_ns): the
  /// sum over the `own_culls` frames that reported it, and the object-frames of those frames.
  double own_cull_ns = 0.0;
  std::uint64_t own_culls = 0, own_object_frames = 0;
  std::uint64_t oracle_calls = 0;  ///< the object-frames the oracle decided
  std::uint64_t exact_decisions = 0;  ///< those the exact-certified cascade decided (the others were proved certified)
};

/// The exact truth of every object of a scene against a frustum, decided down a hierarchy: a BVH
/// over the objects' enclosing boxes (build_bvh, leaves of 4; refit_bvh after objects move). A
/// node whose box the certified n/p-vertex test proves inside the frustum holds only inside
/// objects, one it proves outside only outside ones (each object lies in its enclosing box, the
/// box in its node's: closed sets); the objects of the other leaves are proved by the certified
/// test of their kind, and those it leaves undecided (it answers `intersecting`: near the
/// boundary, or truly intersecting) are decided by the exact-certified cascade (spheres, boxes
/// and OBBs: its verdict is the exact truth, docs/exact-culling.md) or, for points and volumes
/// with a value past float's range, by the exact oracle. The certified tests never give a false
/// reject or a false inside, rounding and the plane extraction from the matrix included
/// (docs/certified.md), so `outside` and `inside` from them are proofs. The same truths as
/// oracle::truth object by object (tests/systems, SceneTruths.EqualTheOracleObjectByObject).
class SceneTruths {
 public:
  explicit SceneTruths(std::vector<Volume> world);
  /// Object `position` now has the volume `v` (the hierarchy is refitted before the next decide).
  void move(std::size_t position, const Volume& v);
  /// truth[i] for object i.
  void decide(const CaseFrustum& f, std::vector<Visibility>& truth);
  const std::vector<Volume>& world() const noexcept { return world_; }
  /// Decisions made so far: by the oracle, by the exact-certified cascade, and certified tests of
  /// node boxes and objects.
  std::uint64_t oracle_calls() const noexcept { return calls_; }
  std::uint64_t exact_decisions() const noexcept { return exact_; }
  std::uint64_t certified_tests() const noexcept { return certified_; }

 private:
  struct Frame;
  Visibility exact(Frame& frame, const Volume& v);
  void visit(const CertifiedFrustum& cf, Frame& frame, std::uint32_t node, std::vector<Visibility>& truth);
  void fill(std::uint32_t node, Visibility v, std::vector<Visibility>& truth) const;
  std::vector<Volume> world_;
  std::vector<Aabb> boxes_;
  Bvh bvh_;
  bool stale_ = false;
  std::uint64_t calls_ = 0, exact_ = 0, certified_ = 0;
};

/// Runs `system` over `run` (build, then per frame update and cull) and judges every object of
/// every frame (SceneTruths). Throws SystemFault on a fault.
RunJudgement judge_run(const System& system, const SceneRun& run);

/// A system's visible set as verdicts by scene position (outside where not listed), checked as
/// SystemFault describes; `position` maps ids to scene positions.
void verdicts_by_position(const SystemInfo& info, const std::unordered_map<std::uint32_t, std::size_t>& position,
                          const VisibleSet& set, std::vector<Visibility>& out);

/// Which runs a system verification draws: `runs` of every family in `families` (or the one run
/// `only_index` of each), each of `size`.
struct VerifyRuns {
  std::uint64_t runs = 6;
  std::uint64_t seed = 1;
  RunSize size;
  std::vector<std::string> families = parse_families("all");
  std::optional<std::uint64_t> only_index;
  /// Runs given whole (the real-mesh scenes, cullproof/sim/scene_run.hpp mesh_scene_run): judged
  /// after the drawn families, each tallied as a family of its own (its run's family).
  std::vector<SceneRun> given;
};

/// A system over one family's runs.
struct FamilyTally {
  std::string family;
  std::uint64_t runs = 0, judged = 0, truth_outside = 0, claim_broken = 0;
  std::uint64_t by_class[5] = {};  ///< per ErrorClass
  double cull_seconds = 0.0, judge_seconds = 0.0;
  /// The system's own time for its culls, as RunJudgement's, summed over the runs.
  double own_cull_ns = 0.0;
  std::uint64_t own_culls = 0, own_object_frames = 0;
  /// The first run whose claim broke, and what broke it.
  std::optional<SceneRun> broken_run;
  std::optional<Finding> broken;
  /// From the start of verify_system to the end of that run (families in order, runs in order):
  /// seconds and object-frames judged, the cost of finding the failure.
  double seconds_to_broken = 0.0;
  std::uint64_t judged_to_broken = 0;
};

/// Draws the runs and judges `system` on each (judge_run), family by family; throws SystemFault
/// on a fault.
std::vector<FamilyTally> verify_system(const System& system, const VerifyRuns& runs);

/// What shrink_run did.
struct ShrinkStats {
  int tries = 0;
  std::size_t objects_before = 0, objects_after = 0, frames_before = 0, frames_after = 0, moves_before = 0,
              moves_after = 0;
  bool budget_spent = false;  ///< stopped by the budget, not because nothing smaller broke the claim
};

/// A smaller run on which `system` still breaks its claim, from `run` and its `failure`
/// (judge_run's first_broken): the frames after the failing one dropped, earlier frames dropped
/// (their moves folded into the scene or the next frame), objects removed in halving chunks then
/// one by one, moves dropped (an object left standing). Each try rebuilds the system and runs it
/// through every frame; at most `budget` tries. A try on which the system faults does not count as
/// breaking the claim. The run returned breaks the claim (or is `run` itself when the system does
/// not break it again: a system whose answers are not a function of its inputs).
SceneRun shrink_run(const System& system, const SceneRun& run, const Finding& failure, int budget = 300,
                    ShrinkStats* stats = nullptr);

/// A run in JSON: the scene's objects (id, world and local volumes in the case format's forms,
/// the transform as 16 numbers, column by column) and the frames (the frustum in the case format,
/// view and projection matrices, eye, axes, whether perspective, the camera event, the moved
/// objects); floats written as the shortest decimals that read back to them.
nlohmann::json to_json(const SceneRun& run);
/// Reads what to_json wrote; throws std::runtime_error naming `where` and the field that is wrong.
SceneRun run_from_json(const nlohmann::json& j, const std::string& where);

/// A system's failure as a corpus record: the system, its claim, the shrunk run, the frame and
/// object judged, the verdict, the truth, the error class and distance, the run it was found on
/// (family, seed, index, size) and how to reproduce it. Written atomically to
/// `<dir>/<system>/<family>/<error class>-<hash of the record>.json`; returns the file.
std::filesystem::path write_system_record(const std::filesystem::path& dir, const System& system, const SceneRun& run,
                                          const Finding& failure, const std::string& reproduce);

/// A system record read back: the run, the frame and object, and what was recorded.
struct SystemRecord {
  std::string system;
  SceneRun run;
  Finding failure;
  nlohmann::json record;
};
SystemRecord read_system_record(const std::filesystem::path& file);

/// A run's object-frame as a case of the case format (the frame's frustum, the object's world
/// volume; id "<family>-<index>-f<frame>-o<id>"), for printing and for `cullproof classify`.
Case case_of(const SceneRun& run, std::size_t frame, std::size_t object);

}  // namespace cullproof::scenes

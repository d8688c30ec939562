// cullproof::sim simulation: the cullers run over a scene's frames, each coherence optimisation
// enabled only when the scene keeps it valid, every configuration's visible set checked against
// the exact oracle, and the reproduction of Assarsson & Möller 2000, Table 1.
//
// Configurations: the tests of the hierarchy culler (cullproof/systems/hierarchy.hpp), the same
// culling stack as cullproof's node-test systems; lib-bvh-* (cull_bvh.hpp's traversals on the same
// hierarchy) are verified, not timed.
#pragma once

#include "cullproof/sim/scene.hpp"
#include "cullproof/systems/hierarchy.hpp"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>
#include <string_view>

namespace cullproof::sim {

/// A configuration is one of the hierarchy culler's tests (cullproof/systems/hierarchy.hpp);
/// to_string gives its stable name.
using Config = HierarchyTest;
inline constexpr int kConfigCount = kHierarchyTestCount;

/// Options of `cullproof simulate`.
struct SimulateOptions {
  std::vector<std::string> scenes;   ///< scene files (Table 1: the model scenes; default the shipped three)
  bool exhaustive = false;           ///< check every leaf of every frame against the oracle
  int samples = 32;                  ///< else: random leaves checked per frame and view (plus every
                                     ///< leaf on which two configurations disagree)
  int frames = 0;                    ///< 0: the scene's frame count; else the first N frames
  std::string csv, json;             ///< per-frame output files ("" = none)
  bool table1 = false;               ///< reproduce A&M Table 1
  int repetitions = 11;              ///< Table 1 timing: runs per configuration (median reported)
  bool verify = true;                ///< run the oracle (Table 1 may skip it with --no-verify)
  std::string corpus_dir = "corpus/scenes-mismatch";
  bool write_corpus = true;
  int corpus_per_config = 5;         ///< mismatches written per configuration and run
  bool progress = true;              ///< progress bar on stderr
  std::string mesh_dir;              ///< "" = default_mesh_dir()
  std::uint64_t seed = 1;            ///< sampling seed
  /// Negative control (tests only, unsound): let TR coherency run through a zoom, as if the
  /// projection had not changed, to show that the verification and the corpus writer catch the
  /// stale rejections this causes.
  bool bypass_zoom_guard = false;
};

/// One optimisation and whether the simulator enabled it for this scene, with the reason.
struct Optimisation {
  std::string name;   ///< plane-coherency, octant, tr-translation, tr-rotation, masking
  std::string state;  ///< "enabled", "disabled", "partly"
  std::string why;
};

/// Counters of one configuration over one frame and view (or summed over a run).
struct Counters {
  std::uint64_t nodes_visited = 0, plane_tests = 0;
  std::uint64_t leaves = 0, visible = 0, inside = 0;
  std::uint64_t checked = 0, false_reject = 0, false_inside = 0, false_intersect = 0, under_inside = 0;
  std::uint64_t tr_frames = 0, octant_frames = 0;
  double time_ns = 0.0;
  void add(const Counters& o);
};

struct FrameRecord {
  int frame = 0, view = 0;
  FrameMotion motion = FrameMotion::first;
  Config config = Config::basic_np;
  bool tr_used = false, octant_used = false;
  std::uint32_t moved_nodes = 0;
  Counters c;
};

struct Mismatch {
  int frame = 0, view = 0;
  Config config = Config::basic_np;
  std::uint32_t leaf = 0, node = 0;
  std::string error;  ///< "false-reject" or "false-inside"
  std::string file;   ///< corpus file written ("" when over the per-run limit)
};

struct SimResult {
  std::string scene, file;
  std::size_t triangles = 0, polygons = 0, nodes = 0, leaves = 0, instances = 0;
  std::uint32_t leaf_triangles = 0;
  int frames = 0, views_per_frame = 1;
  std::vector<Optimisation> optimisations;
  std::vector<Config> configs;
  std::vector<Counters> totals;  ///< per configs[i]
  std::vector<FrameRecord> records;
  std::vector<Mismatch> mismatches;
  std::uint64_t oracle_calls = 0;
  double wall_seconds = 0.0;
  /// False rejects and false insides over every configuration and frame.
  std::uint64_t forbidden_errors() const noexcept;
};

/// Runs every configuration over the scene's frames with per-frame verification. `world` is
/// modified by moving objects (rebuild it to run again from the start).
SimResult simulate(const SceneDesc& scene, World& world, const SimulateOptions& options);

/// Which optimisations the scene permits, and why the others are not (also in SimResult).
std::vector<Optimisation> decide_optimisations(const SceneDesc& scene, const World& world,
                                               const std::vector<CameraFrame>& path);

/// Per-frame CSV (one line per frame, view and configuration; header first).
void write_csv(const SimResult& r, std::ostream& out);
/// The whole result as JSON (summary, optimisations, totals, per-frame records, mismatches).
nlohmann::json to_json(const SimResult& r);
/// The human summary `cullproof simulate` prints.
void print_summary(const SimResult& r, std::ostream& out);

/// One Table 1 cell group: a model and a path kind, each configuration's median time.
struct Table1Cell {
  int model = 0;  ///< 1..3
  PathKind path = PathKind::navigation;
  int frames = 0;
  std::vector<Config> configs;
  std::vector<double> median_ns;        ///< per run of all frames
  std::vector<double> plane_tests_per_node, culled_fraction, visited_per_frame;
  std::uint64_t checked = 0, forbidden = 0, false_intersects = 0;
};
struct Table1Result {
  std::vector<SimResult> models;  ///< scene summaries (sizes) per model
  std::vector<Table1Cell> cells;
  int repetitions = 0;
  double wall_seconds = 0.0;
};
/// Reproduces A&M Table 1 on the model scenes (options.scenes, or the three shipped
/// corpus/scenes/table1-model{1,2,3}.json): the four path kinds, speedups over the
/// perspective-transform baseline, median of options.repetitions timed runs.
Table1Result run_table1(const SimulateOptions& options);
/// Our table beside the paper's, plus plane tests per node, culled fraction and frame time.
void print_table1(const Table1Result& t, std::ostream& out);
nlohmann::json to_json(const Table1Result& t);

}  // namespace cullproof::sim

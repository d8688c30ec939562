// `cullproof simulate`: the cullers over a scene's frames, every frame verified (src/sim).
#include "commands.hpp"

#include "cli_checks.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/sim/simulate.hpp"

#include <fmt/format.h>

#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

namespace cullproof::app {

using namespace sim;

namespace {

void write_text(const std::string& file, const std::string& text) { write_file_atomic(file, text, true); }

// Ranges of the numeric options: CLI11 refuses a value outside, naming the option and the range,
// before anything runs (--seed takes any 64-bit unsigned value).
constexpr int kMaxSimulateSamples = 1000000;    ///< random leaves per frame and view
constexpr int kMaxSimulateFrames = 10000000;    ///< as a scene's camera.frames
constexpr int kMaxSimulateRepetitions = 1000;   ///< Table 1 timed runs per configuration

}  // namespace

void add_simulate(CLI::App& app, SimulateCommand& c) {
  SimulateOptions& o = c.options;
  auto* cmd = c.cmd = app.add_subcommand(
      "simulate", "Run the cullers over a scene's frames (corpus/scenes/*.json), verify every frame against the oracle; "
                  "--table1 reproduces Assarsson & Moller's Table 1");
  cmd->add_option("scenes", o.scenes, "Scene files (with --table1: the model scenes; default the shipped three)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--exhaustive", o.exhaustive, "Check every leaf of every frame against the oracle (default: sampled)");
  cmd->add_option("--samples", o.samples, "Random leaves checked per frame and view when not exhaustive (plus every "
                                          "leaf on which configurations disagree)")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxSimulateSamples));
  cmd->add_option("--frames", o.frames, "Simulate only the first N frames (0: the scene's)")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxSimulateFrames));
  cmd->add_option("--csv", o.csv, "Write per-frame records (frame, view, configuration) as CSV to FILE");
  cmd->add_option("--json", o.json, "Write the whole result as JSON to FILE");
  cmd->add_flag("--table1", o.table1, "Reproduce A&M 2000 Table 1 (three models x four paths, speedups over the "
                                      "perspective-transform baseline)");
  cmd->add_option("--repetitions", o.repetitions, "Table 1: timed runs per configuration (median)")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxSimulateRepetitions));
  cmd->add_flag_callback("--no-verify", [&o] { o.verify = false; }, "Skip the oracle (timing only)");
  cmd->add_option("--corpus", o.corpus_dir, "Write mismatches under DIR")->capture_default_str();
  cmd->add_flag_callback("--no-corpus", [&o] { o.write_corpus = false; }, "Do not write mismatches");
  cmd->add_flag_callback("--no-progress", [&o] { o.progress = false; }, "No progress bar");
  cmd->add_option("--mesh-dir", o.mesh_dir, "Mesh directory (default: $CULLPROOF_MESH_DIR or the cache dir "
                                            "scripts/fetch-meshes fills)");
  cmd->add_option("--seed", o.seed, "Sampling seed")
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, std::numeric_limits<std::uint64_t>::max()));
}


int run_simulate_command(const SimulateCommand& c) {
  const SimulateOptions& opt = c.options;
  try {
    if (opt.table1) {
      const Table1Result t = run_table1(opt);
      print_table1(t, std::cout);
      if (!opt.json.empty()) write_text(opt.json, to_json(t).dump(1) + "\n");
      std::uint64_t forbidden = 0;
      for (const Table1Cell& cell : t.cells) forbidden += cell.forbidden;
      return forbidden ? 1 : 0;
    }
    if (opt.scenes.empty()) {
      std::cerr << "cullproof simulate: give a scene file (corpus/scenes/*.json) or --table1\n";
      return 2;
    }
    if (opt.scenes.size() > 1 && (!opt.csv.empty() || !opt.json.empty())) {
      std::cerr << "cullproof simulate: --csv/--json take one scene at a time\n";
      return 2;
    }
    const std::filesystem::path mesh_dir = opt.mesh_dir.empty() ? default_mesh_dir() : std::filesystem::path(opt.mesh_dir);
    std::uint64_t forbidden = 0;
    for (const std::string& file : opt.scenes) {
      const SceneDesc scene = load_scene(file);
      World world = build_world(scene, mesh_dir);
      const SimResult r = simulate(scene, world, opt);
      print_summary(r, std::cout);
      forbidden += r.forbidden_errors();
      if (!opt.csv.empty()) {
        std::ostringstream os;
        write_csv(r, os);
        write_text(opt.csv, os.str());
      }
      if (!opt.json.empty()) write_text(opt.json, to_json(r).dump(1) + "\n");
    }
    return forbidden ? 1 : 0;
  } catch (const SceneError& e) {
    std::cerr << "cullproof simulate: " << e.what() << "\n";
    return 2;
  } catch (const MeshError& e) {
    std::cerr << "cullproof simulate: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace cullproof::app

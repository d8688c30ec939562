// The `simulate` subcommand's options for a CLI11 program (app/main.cpp):
//
//   cullproof::sim::SimulateOptions sim_opt;
//   auto* simulate_cmd = cullproof::sim::add_simulate_subcommand(app, sim_opt);
//   ...
//   if (*simulate_cmd) return cullproof::sim::run_simulate_command(sim_opt);
//
// Header-only, so cullproof_sim itself does not depend on CLI11.
#pragma once

#include "cullproof/cli_checks.hpp"
#include "cullproof/simulate.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>

namespace cullproof::sim {

// Ranges of the numeric options: CLI11 refuses a value outside, naming the option and the range,
// before anything runs (--seed takes any 64-bit unsigned value).
inline constexpr int kMaxSimulateSamples = 1000000;    ///< random leaves per frame and view
inline constexpr int kMaxSimulateFrames = 10000000;    ///< as a scene's camera.frames
inline constexpr int kMaxSimulateRepetitions = 1000;   ///< Table 1 timed runs per configuration

/// Adds `simulate SCENE... [--exhaustive] [--frames N] [--csv FILE] [--json FILE] [--table1] ...`.
inline CLI::App* add_simulate_subcommand(CLI::App& app, SimulateOptions& o) {
  auto* cmd = app.add_subcommand(
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
  return cmd;
}

}  // namespace cullproof::sim

// The program's subcommands, every option declared once: each subcommand adds its options to the
// CLI11 app, bound to the fields of its struct (which must outlive the parse), and runs from them;
// main.cpp only parses and dispatches. The options of a verification run (RunOptions) serve
// `verify` and `report` alike.
#pragma once

#include "cullproof/methods/methods.hpp"
#include "cullproof/systems/system.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#ifdef CULLPROOF_HAVE_ORACLE
#include "cullproof/campaign/campaign.hpp"
#endif
#ifdef CULLPROOF_HAVE_SIM
#include "cullproof/sim/simulate.hpp"
#endif

namespace cullproof::app {

/// A program under test through the process protocol (docs/protocol.md):
/// --external NAME ... -- PROGRAM ARGS.
struct ExternalProgram {
  std::vector<std::string> names;    ///< --external (repeatable; 'all': every method it offers)
  std::vector<std::string> command;  ///< everything after the first '--'
  int timeout_ms = 10000;            ///< --external-timeout
  int handshake_timeout_ms = 30000;  ///< --external-handshake-timeout
  int jobs = 1;                      ///< --external-jobs (verify)
  std::vector<std::string> shaders;  ///< --shader FILE (repeatable): a shader's description (docs/gpu.md)
  std::vector<std::string> device;   ///< --device (repeatable; 'all': every device): the Vulkan devices the shaders run on
  std::vector<std::string> arithmetic;  ///< --arithmetic (comma-separated, repeatable): the shaders' arithmetic variants
  /// The devices the shaders of the last methods() run on, as `devices --json` gives them (an
  /// array; empty without shaders): for the run's JSON.
  mutable nlohmann::json devices = nlohmann::json::array();
  /// Adds --external, --external-timeout, --external-jobs, --shader, --device and --arithmetic to cmd.
  void add_options(CLI::App* cmd);
  /// The program's methods named by --external and the shaders of --shader beside the built-in
  /// ones named in `builtin`, or the built-in ones alone; std::invalid_argument when a name or the
  /// program is missing, std::runtime_error for a shader that cannot be read or compiled.
  std::vector<Method> methods(const std::vector<std::string>& builtin, int instances = 1) const;
  /// Whether a program or a shader is under test (not the built-in methods alone).
  bool any() const { return !names.empty() || !shaders.empty(); }
  /// The program's culling systems named by --external beside the built-in ones named in
  /// `builtin`, or the built-in ones alone (all of them when none is named).
  std::vector<System> systems(const std::vector<std::string>& builtin) const;
};

/// `methods [--json]`.
struct MethodsCommand {
  CLI::App* cmd = nullptr;
  bool json = false;
};
void add_methods(CLI::App& app, MethodsCommand& c);
int run_methods_command(const MethodsCommand& c);

#ifdef CULLPROOF_HAVE_GPU
/// `devices`: the Vulkan devices and their float controls.
struct DevicesCommand {
  CLI::App* cmd = nullptr;
  bool json = false;
};
void add_devices(CLI::App& app, DevicesCommand& c);
}  // namespace cullproof::app
namespace cullproof::gpu {
struct DeviceInfo;
}
namespace cullproof::app {
/// A device as JSON: what it is, its float controls per width, its measured arithmetic.
nlohmann::json device_json(const gpu::DeviceInfo& d);
int run_devices_command(const DevicesCommand& c);
#endif

/// `classify FILE... [--method NAME ...] [--no-oracle]`.
struct ClassifyCommand {
  CLI::App* cmd = nullptr;
  std::vector<std::string> files, methods;
  bool no_oracle = false;
};
void add_classify(CLI::App& app, ClassifyCommand& c);
int run_classify_command(const ClassifyCommand& c, const ExternalProgram& external);

#ifdef CULLPROOF_HAVE_ORACLE
/// Cases per distribution at most: a run keeps about 330 bytes a case, 3.3 GB at the limit (a
/// hundred times the default).
inline constexpr std::uint64_t kMaxCases = 10000000;
inline constexpr int kMaxThreads = 1024;  ///< worker threads (0: all cores)

/// What a verification run draws and runs: --cases, --seed, --distribution, --method, --threads,
/// --no-progress (`verify`, and `report` when it runs one).
struct RunOptions {
  std::uint64_t cases = VerifyOptions{}.cases, seed = VerifyOptions{}.seed;
  std::vector<std::string> distributions, methods;
  int threads = 0;
  bool no_progress = false;
  /// Adds the options to cmd; `lead` begins each description ("Run: " where the run is optional).
  void add_options(CLI::App* cmd, const std::string& lead = "");
  /// The run's VerifyOptions (distributions parsed, each once, in the order named; the campaign's
  /// default when none is named); std::invalid_argument for an unknown distribution.
  VerifyOptions verify_options() const;
  /// The `cullproof verify` command line that runs the same.
  std::string command() const;
};

/// `verify ...`: the side-by-side run.
struct VerifyCommand {
  CLI::App* cmd = nullptr;
  CLI::Option* index_option = nullptr;
  RunOptions run;
  std::string json_file, corpus_dir = "corpus", shard;
  bool no_corpus = false;
  std::uint64_t index = 0;
};
void add_verify(CLI::App& app, VerifyCommand& c, ExternalProgram& external);
int run_verify_command(VerifyCommand& c, const ExternalProgram& external);
/// "K/N" as a shard; std::invalid_argument naming what is wrong.
Shard parse_shard(const std::string& text);

/// `merge SHARD.json... [--json FILE] [--partial]`.
struct MergeCommand {
  CLI::App* cmd = nullptr;
  std::vector<std::string> files;
  std::string json_file;
  std::string corpus;  ///< where the merged run's corpus goes (empty: none)
  bool partial = false;
};
void add_merge(CLI::App& app, MergeCommand& c);
/// 0, or 1 / 3 as verify (a claim broken, a fault), 4 for a partial merge that is otherwise clean.
int run_merge_command(const MergeCommand& c);

/// `corpus list|show ID|replay|rerecord METHOD ...`.
struct CorpusCommand {
  CLI::App* cmd = nullptr;
  std::string action, id, dir = "corpus";
  bool strict = false;
  std::string html, svg, zoom_svg;  ///< show: the case drawn (with the report)
};
void add_corpus(CLI::App& app, CorpusCommand& c, ExternalProgram& external);
int run_corpus_command(const CorpusCommand& c, const ExternalProgram& external);
#endif

#ifdef CULLPROOF_HAVE_REPORT
/// `report [--from FILE | the run's options] [--out FILE] [--json FILE] [--corpus DIR | --no-corpus]`.
struct ReportCommand {
  CLI::App* cmd = nullptr;
  std::string from;                 ///< a `cullproof verify --json` result; empty: run one
  std::string out = "report.html";  ///< the page
  std::string json;                 ///< where the run's JSON goes as well (when report runs it)
  std::string corpus = "corpus";    ///< the corpus shown (and written by a run)
  std::string systems;              ///< a `cullproof systems --json` result shown in its own section
  bool no_corpus = false;           ///< neither write nor show a corpus
  RunOptions run;                   ///< the run, when there is no --from
};
void add_report(CLI::App& app, ReportCommand& c);
/// 0 when the page is written (and, for a run, no claim of an own or user method broke: then 1,
/// as `verify`); 2 for bad input or missing page scripts.
int run_report_command(const ReportCommand& c);
#endif

#ifdef CULLPROOF_HAVE_SCENES
/// `systems [--system NAME ...] [--family F ...] [--scene FILE ...] [--mesh-dir DIR] [--runs N]
/// [--objects N] [--frames N] [--seed S] [--index I] [--json FILE] [--corpus DIR | --no-corpus]
/// [--replay]`.
struct SystemsCommand {
  CLI::App* cmd = nullptr;
  CLI::Option* index_option = nullptr;
  std::vector<std::string> systems, families, scene_files;
  std::string mesh_dir;
  std::uint64_t runs = 6, objects = 200, frames = 12, seed = 1, index = 0;
  int shrink_budget = 300;
  std::string json_file, corpus_dir = "corpus";
  bool no_corpus = false, replay = false;
};
void add_systems(CLI::App& app, SystemsCommand& c, ExternalProgram& external);
/// Per system a table per family; 1 when the claim of an own or user system broke (its first
/// failing run shrunk and recorded), 2 for bad input or a fault (the run it happened on recorded
/// under <corpus>/systems/faults/; the faulted system stops, the others run to the end).
int run_systems_command(const SystemsCommand& c, const ExternalProgram& external);

/// The system records under <dir>/systems/ (the shrunk failing runs; faults/ aside) replayed with
/// the systems of `systems` by name, one line each ("still failing" where the recorded frame and
/// object break the claim again, "changed" where another does, "fixed", "not replayed" for a
/// system not among `systems`). Returns the number of records of known systems that no longer fail
/// as recorded; `records` gets the number read.
std::size_t replay_system_records(const std::string& dir, const std::vector<System>& systems, std::size_t& records);
#ifdef CULLPROOF_HAVE_REPORT
/// `corpus show ID --html FILE [--svg FILE] [--zoom-svg FILE]` for a system record: the page of the
/// failing object-frame in 3D with the frame's other objects (report::system_html) and the
/// drawings of its case. -1 when no record is named `id`; 0 when written; 2 with a message.
int write_system_record_page(const std::string& dir, const std::string& id, const std::string& html_file,
                             const std::string& svg_file, const std::string& zoom_svg_file);
/// The views of every system record under <dir>/systems/ (faults aside) for the report's corpus
/// section: each a case view (report::case_view_json) with the frame's other objects and the run.
/// Throws what reading a record throws.
nlohmann::json system_record_views(const std::string& dir);
#endif
/// Prints the system record whose file name (without .json) is `id`; false when there is none.
bool show_system_record(const std::string& dir, const std::string& id);
#endif

#ifdef CULLPROOF_HAVE_SIM
/// `simulate SCENE... [--exhaustive] [--frames N] [--csv FILE] [--json FILE] [--table1] ...`.
struct SimulateCommand {
  CLI::App* cmd = nullptr;
  sim::SimulateOptions options;
};
void add_simulate(CLI::App& app, SimulateCommand& c);
/// Prints the scene, the optimisations enabled and why the others are not, the per-configuration
/// totals; exit status 1 when any false reject or false inside was found, 2 for a bad scene.
int run_simulate_command(const SimulateCommand& c);
#endif

}  // namespace cullproof::app

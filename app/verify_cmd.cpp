// `cullproof verify`: the side-by-side verification run (src/campaign/campaign.cpp), its tables, its
// JSON and its corpus.
#include "commands.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cli_checks.hpp"
#include "cullproof/corpus/corpus.hpp"
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/report/summary.hpp"
#endif

#include <algorithm>
#include <atomic>
#include <cctype>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>

namespace cullproof::app {

namespace {

constexpr std::uint64_t kMaxUnsigned = std::numeric_limits<std::uint64_t>::max();

// SIGINT and SIGTERM stop the run (VerifyOptions::stop): what was judged is reported, marked
// interrupted. The handler is installed once per run and resets itself, so a second signal ends
// the process at once.
std::atomic<bool> g_stop{false};
volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_stop_signal(int sig) {
  g_signal = sig;
  g_stop.store(true);
}

void catch_stop_signals() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);
}

int cmd_verify(VerifyOptions opt, const std::string& json_file, const std::vector<Method>& methods,
               const nlohmann::json& devices) {
  static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
  catch_stop_signals();
  opt.stop = &g_stop;
  // Each distribution's table as soon as it is done; the notes under the last.
  opt.on_distribution = [&](const DistributionResult& d) { print_table(d, opt.seed, std::cout); };
  const VerifyResult r = run_verify(opt, methods);
  print_table_notes(r, std::cout);
  nlohmann::json json = to_json(r);
  if (!devices.empty()) json["devices"] = devices;  // where the shaders ran, and how it computes
  if (!json_file.empty()) write_file_atomic(json_file, json.dump(2) + "\n");
  std::size_t written = 0;
  for (const auto& d : r.distributions)
    for (const auto& m : d.methods) written += m.corpus_written.size();
  if (opt.corpus) std::cout << "corpus: " << written << " new case(s) written under " << opt.corpus->string() << "\n";
#ifdef CULLPROOF_HAVE_REPORT
  report::print_summary(report::summarize(json), std::cout);
#endif
  if (r.interrupted) {
    const int sig = g_signal ? int(g_signal) : SIGINT;
    std::cout << "INTERRUPTED by signal " << sig << ": the results above are over the cases judged before it\n";
    return 128 + sig;
  }
  if (r.faults() > 0) {
    std::cout << "FAILED: " << r.faults() << " fault(s) (see FAULT above); the faulted methods' counts are incomplete\n";
    return 3;
  }
  if (r.claim_broken()) {
    std::cout << "FAILED: a claim of one of cullproof's own methods or of a user's method was refuted (see REFUTED above)\n";
    return 1;
  }
  return 0;
}

// A description with `lead` before it, its first letter lower case after a lead.
std::string described(const std::string& lead, std::string text) {
  if (!lead.empty() && !text.empty()) text[0] = char(std::tolower(static_cast<unsigned char>(text[0])));
  return lead + text;
}

}  // namespace

// Ranges of the numeric options: CLI11 refuses a value outside, naming the option and the range,
// before anything runs (seed and index take any 64-bit unsigned value).
void RunOptions::add_options(CLI::App* cmd, const std::string& lead) {
  cmd->add_option("--cases", cases, described(lead, "Cases per distribution"))
      ->capture_default_str()
      ->check(cli::UnsignedRange(1, kMaxCases));
  cmd->add_option("--seed", seed, described(lead, "Seed: the same seed gives the same cases and verdicts"))
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, kMaxUnsigned));
  cmd->add_option("--distribution,-d", distributions,
                  described(lead, "Distributions (repeatable; 'all', 'all-generic', 'all-hard')"));
  cmd->add_option("--method,-m", methods, described(lead, "Methods (repeatable; default: all)"));
  cmd->add_option("--threads", threads, described(lead, "Worker threads (0: all cores)"))
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxThreads));
  cmd->add_flag("--no-progress", no_progress, "No progress bar");
}

VerifyOptions RunOptions::verify_options() const {
  VerifyOptions v;
  v.cases = cases;
  v.seed = seed;
  v.methods = methods;
  v.threads = threads;
  v.progress = !no_progress;
  if (!distributions.empty()) {
    v.distributions.clear();
    for (const std::string& d : distributions)
      for (gen::Distribution x : gen::parse_distributions(d))
        if (std::find(v.distributions.begin(), v.distributions.end(), x) == v.distributions.end())
          v.distributions.push_back(x);
  }
  return v;
}

std::string RunOptions::command() const {
  std::string c = "cullproof verify --cases " + std::to_string(cases) + " --seed " + std::to_string(seed);
  for (const auto& d : distributions) c += " -d " + d;
  for (const auto& m : methods) c += " -m " + m;
  return c;
}

void add_verify(CLI::App& app, VerifyCommand& c, ExternalProgram& external) {
  CLI::App* cmd = c.cmd =
      app.add_subcommand("verify", "The side-by-side verification run: every method and the oracle on generated cases");
  c.run.add_options(cmd);
  cmd->add_option("--corpus", c.corpus_dir, "Write new mismatches under DIR")->capture_default_str();
  cmd->add_flag("--no-corpus", c.no_corpus, "Do not write the corpus");
  cmd->add_option("--json", c.json_file, "Write the whole result as JSON to FILE");
  c.index_option = cmd->add_option("--index", c.index, "Run only case INDEX of each distribution (reproduce)")
                       ->check(cli::UnsignedRange(0, kMaxUnsigned));
  external.add_options(cmd);
}

int run_verify_command(VerifyCommand& c, const ExternalProgram& external) {
  VerifyOptions vopt = c.run.verify_options();
  vopt.corpus = c.no_corpus ? std::nullopt : std::optional<std::filesystem::path>(c.corpus_dir);
  if (*c.index_option) vopt.only_index = c.index;
  const std::vector<Method> methods = external.methods(vopt.methods, external.jobs);
  return cmd_verify(vopt, c.json_file, methods, external.devices);
}

}  // namespace cullproof::app

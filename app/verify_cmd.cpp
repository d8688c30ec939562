// `cullproof verify`: the side-by-side verification run (src/campaign/campaign.cpp), its tables, its
// JSON and its corpus.
#include "commands.hpp"

#include <fmt/format.h>

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/io/limits.hpp"
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
// A shard's result holds its counts, its false-intersect distances in full and the text of the
// records it would write: large runs' results reach hundreds of MiB.
constexpr std::uintmax_t kMaxShardBytes = std::uintmax_t(4) << 30;  // 4 GiB

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

// How many records a run (verify's or merge's) wrote into its corpus folder.
void print_corpus_line(const VerifyResult& r, const std::filesystem::path& dir) {
  std::size_t written = 0;
  for (const auto& d : r.distributions)
    for (const auto& m : d.methods) written += m.corpus_written.size();
  std::cout << "corpus: " << written << " new case(s) written under " << dir.string() << "\n";
}

// The summary and the exit status of a complete run, verify's or merge's: 3 for a fault, 1 for a
// broken claim, else 0.
int outcome(const VerifyResult& r, const nlohmann::json& json) {
#ifdef CULLPROOF_HAVE_REPORT
  report::print_summary(report::summarize(json), std::cout);
#else
  (void)json;
#endif
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

int cmd_verify(VerifyOptions opt, const std::string& json_file, const std::vector<Method>& methods,
               const nlohmann::json& devices) {
  static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
  catch_stop_signals();
  opt.stop = &g_stop;
  // Each distribution's table as soon as it is done; the notes under the last.
  opt.on_distribution = [&](const DistributionResult& d) {
    if (opt.shard)
      std::cout << fmt::format("\nshard {}/{}: {}", opt.shard->index, opt.shard->count,
                               d.cases_asked ? fmt::format("cases {} to {} of {}", d.first_case, d.first_case + d.cases_asked - 1, opt.cases)
                                             : fmt::format("none of the {} cases (they are shared out in whole frames)", opt.cases));
    print_table(d, opt.seed, std::cout);
  };
  const VerifyResult r = run_verify(opt, methods);
  print_table_notes(r, std::cout);
  nlohmann::json json = to_json(r);
  if (!devices.empty()) json["devices"] = devices;  // where the shaders ran, and how it computes
  if (!json_file.empty()) write_file_atomic(json_file, json.dump(2) + "\n");
  if (opt.corpus) print_corpus_line(r, *opt.corpus);
  if (r.interrupted) {
#ifdef CULLPROOF_HAVE_REPORT
    report::print_summary(report::summarize(json), std::cout);
#endif
    const int sig = g_signal ? int(g_signal) : SIGINT;
    std::cout << "INTERRUPTED by signal " << sig << ": the results above are over the cases judged before it\n";
    return 128 + sig;
  }
  return outcome(r, json);
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
  cmd->add_option("--shard", c.shard,
                  "Run only shard K of N (K/N, 0 <= K < N): the K-th of N consecutive ranges of whole frames of "
                  "every distribution's cases; the shards' --json files merge with 'cullproof merge' (docs/cluster.md)")
      ->excludes(c.index_option);
  external.add_options(cmd);
}

Shard parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto number = [&](const std::string& part, const char* what) {
    if (part.empty() || part.size() > 19 || part.find_first_not_of("0123456789") != std::string::npos)
      throw std::invalid_argument("--shard " + text + ": " + what + " is not a whole number (K/N, 0 <= K < N)");
    return std::stoull(part);
  };
  if (slash == std::string::npos) throw std::invalid_argument("--shard " + text + ": not K/N (shard K of N, 0 <= K < N)");
  const Shard s{number(text.substr(0, slash), "K"), number(text.substr(slash + 1), "N")};
  if (s.count == 0 || s.index >= s.count)
    throw std::invalid_argument("--shard " + text + ": K must be below N (shards 0 to N - 1 of N)");
  return s;
}

int run_verify_command(VerifyCommand& c, const ExternalProgram& external) {
  VerifyOptions vopt = c.run.verify_options();
  vopt.corpus = c.no_corpus ? std::nullopt : std::optional<std::filesystem::path>(c.corpus_dir);
  if (*c.index_option) vopt.only_index = c.index;
  if (!c.shard.empty()) vopt.shard = parse_shard(c.shard);
  const std::vector<Method> methods = external.methods(vopt.methods, external.jobs);
  return cmd_verify(vopt, c.json_file, methods, external.devices);
}

}  // namespace cullproof::app

namespace cullproof::app {

void add_merge(CLI::App& app, MergeCommand& c) {
  c.cmd = app.add_subcommand("merge",
                             "Merge the results of a run's shards (verify --shard K/N --json FILE) into the run's tables, "
                             "summary and JSON: counts summed exactly (docs/cluster.md)");
  c.cmd->add_option("shards", c.files, "The shards' JSON files")->required();
  c.cmd->add_option("--json", c.json_file, "Write the merged result as JSON to FILE");
  c.cmd->add_option("--corpus", c.corpus,
                    "Write the merged run's corpus to DIR: the records one run would have written, chosen among the "
                    "shards' (which must have run with a corpus)");
  c.cmd->add_flag("--partial", c.partial, "Merge the shards given though some are missing or were interrupted (the result "
                                          "says which and is marked partial)");
}

int run_merge_command(const MergeCommand& c) {
  std::vector<ShardFile> shards;
  for (const std::string& file : c.files) {
    std::string text;
    try {
      text = read_file_limited(file, kMaxShardBytes, "a shard's result");
    } catch (const std::system_error& e) {
      throw std::invalid_argument(file + ": cannot be read: " + e.code().message());
    }
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
      throw std::invalid_argument(file + ": not JSON (a truncated or damaged shard's result; run the shard again)");
    }
    shards.push_back({file, std::move(j)});
  }
  MergedRun merged = merge_shards(shards, c.partial);
  VerifyResult& r = merged.result;
  if (!c.corpus.empty()) {
    if (!shards.front().json["run"].value("corpus", false))
      throw std::invalid_argument(shards.front().file + ": the shards ran without a corpus (--no-corpus): there are no records to merge");
    write_merged_corpus(r, c.corpus);
  }
  std::cout << fmt::format("merged {} of {} shards (seed {}, {} cases per distribution){}\n", merged.shards - merged.missing.size(),
                           merged.shards, r.options.seed, r.options.cases,
                           merged.missing.empty() ? std::string() : fmt::format("; PARTIAL: {} missing", merged.missing.size()));
  print_tables(r, std::cout);
  std::cout << fmt::format("merged: counts summed over the shards; costs the median of the shards' (each the fastest of its "
                           "passes over the same frames); wall time the sum, {:.1f} s on the longest shard\n",
                           merged.longest_shard_seconds);
  nlohmann::json json = to_json(r);
  // The devices the shards' shaders ran on, each once.
  nlohmann::json devices = nlohmann::json::array();
  for (const ShardFile& f : shards)
    if (f.json.contains("devices") && f.json["devices"].is_array())
      for (const nlohmann::json& d : f.json["devices"])
        if (std::find(devices.begin(), devices.end(), d) == devices.end()) devices.push_back(d);
  if (!devices.empty()) json["devices"] = devices;
  json["merged"] = {{"shards", merged.shards}, {"files", c.files}, {"partial", !merged.missing.empty()},
                    {"missing_shards", merged.missing}, {"longest_shard_seconds", merged.longest_shard_seconds}};
  if (!c.json_file.empty()) write_file_atomic(c.json_file, json.dump(2) + "\n");
  if (!c.corpus.empty()) print_corpus_line(r, c.corpus);
  if (!merged.missing.empty()) {
    std::string list;
    for (std::uint64_t k : merged.missing) list += (list.empty() ? "" : ", ") + std::to_string(k);
    std::cout << "PARTIAL: shards " << list << " of " << merged.shards << " are missing or were interrupted; the counts are "
              << "over the others\n";
  }
  const int status = outcome(r, json);
  return status != 0 ? status : (merged.missing.empty() ? 0 : 4);
}

}  // namespace cullproof::app

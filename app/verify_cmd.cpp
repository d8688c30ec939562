// `cullproof verify`: the side-by-side verification run (harness/campaign.cpp), its tables, its
// JSON and its corpus.
#include "commands.hpp"

#include "cullproof/case_io.hpp"
#include "cullproof/cli_checks.hpp"
#include "cullproof/corpus.hpp"
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/summary.hpp"
#endif

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>

namespace cullproof::app {

namespace {

// Ranges of the numeric options: CLI11 refuses a value outside, naming the option and the range,
// before anything runs (seed and index take any 64-bit unsigned value).
/// Cases per distribution: a run keeps about 330 bytes a case, 3.3 GB at the limit (a hundred
/// times the default).
constexpr std::uint64_t kMaxCases = 10000000;
constexpr int kMaxThreads = 1024;  ///< worker threads (0: all cores)
constexpr std::uint64_t kMaxUnsigned = std::numeric_limits<std::uint64_t>::max();

int cmd_verify(VerifyOptions opt, const std::vector<std::string>& dists, const std::string& json_file,
               const std::vector<Method>& methods) {
  if (!dists.empty()) {
    opt.distributions.clear();
    for (const std::string& d : dists)
      for (gen::Distribution x : gen::parse_distributions(d))
        if (std::find(opt.distributions.begin(), opt.distributions.end(), x) == opt.distributions.end())
          opt.distributions.push_back(x);
  }
  VerifyResult r;
  try {
    r = run_verify(opt, methods);
  } catch (const MethodFault& e) {
    std::cerr << "cullproof verify: FAULT: " << e.what() << "\n";
    return 3;
  }
  print_tables(r, std::cout);
  if (!json_file.empty()) write_file_atomic(json_file, to_json(r).dump(2) + "\n");
  std::size_t written = 0;
  for (const auto& d : r.distributions)
    for (const auto& m : d.methods) written += m.corpus_written.size();
  if (opt.corpus) std::cout << "corpus: " << written << " new case(s) written under " << opt.corpus->string() << "\n";
#ifdef CULLPROOF_HAVE_REPORT
  report::print_summary(report::summarize(to_json(r)), std::cout);
#endif
  if (r.claim_broken()) {
    std::cout << "FAILED: a claim of one of cullproof's own methods or of a user's method was refuted (see REFUTED above)\n";
    return 1;
  }
  return 0;
}

}  // namespace

void add_verify(CLI::App& app, VerifyCommand& c, ExternalProgram& external) {
  VerifyOptions& vopt = c.options;
  CLI::App* verify_cmd = c.cmd =
      app.add_subcommand("verify", "The side-by-side verification run: every method and the oracle on generated cases");
  verify_cmd->add_option("--cases", vopt.cases, "Cases per distribution")
      ->capture_default_str()
      ->check(cli::UnsignedRange(1, kMaxCases));
  verify_cmd->add_option("--seed", vopt.seed, "Seed: the same seed gives the same cases and verdicts")
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, kMaxUnsigned));
  verify_cmd->add_option("--distribution,-d", c.distributions, "Distributions (repeatable; 'all', 'all-generic', 'all-hard')");
  verify_cmd->add_option("--method,-m", vopt.methods, "Methods (repeatable; default: all)");
  verify_cmd->add_option("--threads", vopt.threads, "Worker threads (0: all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxThreads));
  verify_cmd->add_option("--corpus", c.corpus_dir, "Write new mismatches under DIR")->capture_default_str();
  verify_cmd->add_flag("--no-corpus", c.no_corpus, "Do not write the corpus");
  verify_cmd->add_option("--json", c.json_file, "Write the whole result as JSON to FILE");
  c.index_option = verify_cmd->add_option("--index", c.index, "Run only case INDEX of each distribution (reproduce)")
                       ->check(cli::UnsignedRange(0, kMaxUnsigned));
  external.add_options(verify_cmd);
  verify_cmd->add_flag("--no-progress", c.no_progress, "No progress bar");
}

int run_verify_command(VerifyCommand& c, const ExternalProgram& external) {
  VerifyOptions& vopt = c.options;
  vopt.corpus = c.no_corpus ? std::nullopt : std::optional<std::filesystem::path>(c.corpus_dir);
  vopt.progress = !c.no_progress;
  if (*c.index_option) vopt.only_index = c.index;
  return cmd_verify(vopt, c.distributions, c.json_file, external.methods(vopt.methods, external.jobs));
}

}  // namespace cullproof::app

// The `report` subcommand for a CLI11 program (app/main.cpp):
//
//   cullproof::report::ReportOptions report_opt;
//   auto* report_cmd = cullproof::report::add_report_subcommand(app, report_opt);
//   ...
//   if (*report_cmd) return cullproof::report::run_report_command(report_opt);
//
// Header-only, so cullproof_report itself does not depend on CLI11.
#pragma once

#include "cullproof/cli_checks.hpp"
#include "cullproof/report.hpp"

#include <CLI/CLI.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace cullproof::report {

struct ReportOptions {
  std::string from;                    ///< a `cullproof verify --json` result; empty: run verify
  std::string out = "report.html";     ///< the page
  std::string json;                    ///< where the run's JSON goes as well (when report runs verify)
  std::string corpus = "corpus";       ///< the corpus shown (and written by a run)
  bool no_corpus = false;              ///< neither write nor show a corpus
  // The run, when there is no --from (as `cullproof verify`).
  std::uint64_t cases = 100000, seed = 1;
  std::vector<std::string> distributions, methods;
  int threads = 0;
  bool progress = true;
};

inline constexpr std::uint64_t kMaxReportCases = 10000000;  ///< as `cullproof verify --cases`

/// Adds `report [--from FILE] [--out FILE] [--corpus DIR | --no-corpus] [verify's options]`.
inline CLI::App* add_report_subcommand(CLI::App& app, ReportOptions& o) {
  auto* cmd = app.add_subcommand(
      "report", "Write one self-contained HTML page of a verification run: the summary, what accuracy costs (charts), "
                "where claims break, the corpus in 3D (docs/report.md)");
  cmd->add_option("--from", o.from, "Read the run from FILE (cullproof verify --json FILE) instead of running one")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out,-o", o.out, "The page to write")->capture_default_str();
  cmd->add_option("--json", o.json, "Also write the run's JSON to FILE (when report runs it)");
  cmd->add_option("--corpus", o.corpus, "The corpus the page shows in 3D (and where a run writes new mismatches)")
      ->capture_default_str();
  cmd->add_flag("--no-corpus", o.no_corpus, "Neither write nor show a corpus");
  cmd->add_option("--cases", o.cases, "Run: cases per distribution")
      ->capture_default_str()
      ->check(cli::UnsignedRange(1, kMaxReportCases));
  cmd->add_option("--seed", o.seed, "Run: seed")
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_option("--distribution,-d", o.distributions, "Run: distributions (repeatable; 'all', 'all-generic', 'all-hard')");
  cmd->add_option("--method,-m", o.methods, "Run: methods (repeatable; default: all)");
  cmd->add_option("--threads", o.threads, "Run: worker threads (0: all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1024));
  cmd->add_flag_callback("--no-progress", [&o] { o.progress = false; }, "No progress bar");
  return cmd;
}

/// Runs the subcommand: 0 when the page is written (and, for a run, no claim of an own or user
/// method broke: then 1, as `cullproof verify`); 2 for bad input or missing page scripts.
int run_report_command(const ReportOptions& o);

}  // namespace cullproof::report

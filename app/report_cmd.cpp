// `cullproof report`: one self-contained HTML page of a verification run, read or run.
#include "commands.hpp"

#include "cullproof/campaign/campaign.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/io/limits.hpp"
#include "cullproof/report/case_view.hpp"
#include "cullproof/report/report.hpp"
#include "cullproof/report/summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>

namespace cullproof::app {

using namespace report;

namespace {

/// A run's JSON: about 2 KiB per method and family; this is far past any real run.
constexpr std::uintmax_t kMaxResultBytes = std::uintmax_t(256) << 20;
constexpr int kMaxResultDepth = 16;

nlohmann::json read_result(const std::string& file, const char* what = "a verify result") {
  const std::string text = read_file_limited(file, kMaxResultBytes, what);
  try {
    return parse_json_limited(text, kMaxResultDepth, what);
  } catch (const nlohmann::json::parse_error& e) {
    throw ResultError(fmt::format("{} is not JSON: {}", file, e.what()));
  }
}

}  // namespace

void add_report(CLI::App& app, ReportCommand& c) {
  c.cmd = app.add_subcommand(
      "report", "Write one self-contained HTML page of a verification run: the summary, what accuracy costs (charts), "
                "where claims break, the corpus in 3D (docs/report.md)");
  c.cmd->add_option("--from", c.from, "Read the run from FILE (cullproof verify --json FILE) instead of running one")
      ->check(CLI::ExistingFile);
  c.cmd->add_option("--out,-o", c.out, "The page to write")->capture_default_str();
  c.cmd->add_option("--json", c.json, "Also write the run's JSON to FILE (when report runs it)");
  c.cmd->add_option("--corpus", c.corpus, "The corpus the page shows in 3D (and where a run writes new mismatches)")
      ->capture_default_str();
  c.cmd->add_flag("--no-corpus", c.no_corpus, "Neither write nor show a corpus");
#ifdef CULLPROOF_HAVE_SCENES
  c.cmd->add_option("--systems", c.systems, "Add a section for culling systems from FILE (cullproof systems --json FILE)")
      ->check(CLI::ExistingFile);
#endif
  c.run.add_options(c.cmd, "Run: ");
}

int run_report_command(const ReportCommand& o) {
  const char* who = "cullproof report: ";
  try {
    // The scripts first: a missing bundle is reported before a long run, not after.
    const std::string report_js = load_web_asset("report.js");
    nlohmann::json result;
    PageInputs in;
    bool failed = false;
    if (!o.systems.empty()) {  // refused before a run is made
      in.systems_from = o.systems;
      try {
        in.systems = read_result(o.systems, "a systems result");
      } catch (const ResultError& e) {  // names the file
        std::cerr << who << e.what() << "\n";
        return 2;
      } catch (const InputLimitError& e) {
        std::cerr << who << o.systems << ": " << e.what() << "\n";
        return 2;
      }
      try {
        check_systems_result(in.systems);
      } catch (const ResultError& e) {
        std::cerr << who << o.systems << ": " << e.what() << "\n";
        return 2;
      }
    }
    if (!o.from.empty()) {
      result = read_result(o.from);
      in.made_by = "cullproof report --from " + o.from;
      summarize(result);  // refuses a malformed result naming the field, before anything is written
    } else {
      VerifyOptions v = o.run.verify_options();
      if (!o.no_corpus) v.corpus = std::filesystem::path(o.corpus);
      const VerifyResult r = run_verify(v);
      result = to_json(r);
      failed = r.failed();
      in.made_by = o.run.command();
      if (!o.json.empty()) write_file_atomic(o.json, result.dump(2) + "\n");
    }
    if (!o.no_corpus && std::filesystem::is_directory(o.corpus)) {
      in.corpus_dir = o.corpus;
      for (const CorpusEntry& e : load_corpus(o.corpus)) in.corpus.push_back(case_view_json(e));
#ifdef CULLPROOF_HAVE_SCENES
      for (nlohmann::json& v : system_record_views(o.corpus)) in.corpus.push_back(std::move(v));  // systems' records
#endif
    } else if (!o.no_corpus) {
      std::cerr << who << "no corpus section: " << o.corpus << " is not a folder (--corpus DIR, or --no-corpus)\n";
    }
    write_file_atomic(o.out, report_html(result, in, report_js));
    const Summary s = summarize(result);
    print_summary(s, std::cout);
    std::cout << "report: " << o.out << "\n";
    if (failed) {
      std::cout << "FAILED: a claim of one of cullproof's own methods or of a user's method was refuted (see above)\n";
      return 1;
    }
    return 0;
  } catch (const AssetError& e) {
    std::cerr << who << e.what() << "\n";
    return 2;
  } catch (const ResultError& e) {
    std::cerr << who << (o.from.empty() ? "" : o.from + ": ") << e.what() << "\n";
    return 2;
  } catch (const InputLimitError& e) {
    std::cerr << who << o.from << ": " << e.what() << "\n";
    return 2;
  } catch (const CaseError& e) {
    std::cerr << who << "the corpus: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << who << e.what() << "\n";
    return 2;
  }
}

}  // namespace cullproof::app

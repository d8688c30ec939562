// `cullproof report`: the command the CLI (app/main.cpp) calls.
#include "cullproof/campaign.hpp"
#include "cullproof/case_view.hpp"
#include "cullproof/corpus.hpp"
#include "cullproof/case_io.hpp"
#include "cullproof/report_cli.hpp"
#include "cullproof/summary.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iostream>

namespace cullproof::report {

namespace {

/// A run's JSON: about 2 KiB per method and family; this is far past any real run.
constexpr std::uintmax_t kMaxResultBytes = std::uintmax_t(256) << 20;
constexpr int kMaxResultDepth = 16;

nlohmann::json read_result(const std::string& file) {
  const std::string text = read_file_limited(file, kMaxResultBytes, "a verify result");
  try {
    return parse_json_limited(text, kMaxResultDepth, "a verify result");
  } catch (const nlohmann::json::parse_error& e) {
    throw ResultError(fmt::format("{} is not JSON: {}", file, e.what()));
  }
}

std::string made_by(const ReportOptions& o) {
  std::string c = fmt::format("cullproof verify --cases {} --seed {}", o.cases, o.seed);
  for (const auto& d : o.distributions) c += " -d " + d;
  for (const auto& m : o.methods) c += " -m " + m;
  return c;
}

}  // namespace

int run_report_command(const ReportOptions& o) {
  const char* who = "cullproof report: ";
  try {
    // The scripts first: a missing bundle is reported before a long run, not after.
    const std::string report_js = load_web_asset("report.js");
    nlohmann::json result;
    PageInputs in;
    bool failed = false;
    if (!o.from.empty()) {
      result = read_result(o.from);
      in.made_by = "cullproof report --from " + o.from;
      summarize(result);  // refuses a malformed result naming the field, before anything is written
    } else {
      VerifyOptions v;
      v.cases = o.cases;
      v.seed = o.seed;
      v.methods = o.methods;
      v.threads = o.threads;
      v.progress = o.progress;
      if (!o.no_corpus) v.corpus = std::filesystem::path(o.corpus);
      if (!o.distributions.empty()) {
        v.distributions.clear();
        for (const std::string& d : o.distributions)
          for (gen::Distribution x : gen::parse_distributions(d))
            if (std::find(v.distributions.begin(), v.distributions.end(), x) == v.distributions.end()) v.distributions.push_back(x);
      }
      const VerifyResult r = run_verify(v);
      result = to_json(r);
      failed = r.claim_broken();
      in.made_by = made_by(o);
      if (!o.json.empty()) write_file_atomic(o.json, result.dump(2) + "\n");
    }
    if (!o.no_corpus && std::filesystem::is_directory(o.corpus)) {
      in.corpus_dir = o.corpus;
      for (const CorpusEntry& e : load_corpus(o.corpus)) in.corpus.push_back(case_view_json(e));
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

}  // namespace cullproof::report

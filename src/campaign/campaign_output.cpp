// A run's report: the Markdown tables of `cullproof verify` and the JSON of --json (see
// cullproof/campaign/campaign.hpp).
#include "cullproof/campaign/campaign.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <ostream>

namespace cullproof {

namespace {

std::string pct(double x) {
  if (x == 0.0) return "0";
  if (x < 1e-4) return fmt::format("{:.1e}", x * 100);
  return fmt::format("{:.3g}", x * 100);
}

std::string median_max(std::vector<double> v) {
  if (v.empty()) return "-";
  std::sort(v.begin(), v.end());
  return fmt::format("{:.2g} / {:.2g}", v[v.size() / 2], v.back());
}

std::string ns(double x) { return std::isfinite(x) ? fmt::format("{:.1f}", x) : "-"; }

// Under-insides over the truly inside volumes of the kinds the method answers three-way.
double under_inside_rate(const MethodStats& m) {
  return m.truth_inside_three_way ? double(m.under_inside) / double(m.truth_inside_three_way) : 0.0;
}

std::string kind_list(unsigned bits) {
  std::string s;
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) s += (s.empty() ? "" : " and ") + std::string(volume_kind_name(k));
  return s;
}

}  // namespace

void print_table(const DistributionResult& d, std::uint64_t seed, std::ostream& out) {
  const std::string cut = d.interrupted ? fmt::format(" INTERRUPTED: {} of {} cases judged;", d.cases, d.cases_asked) : "";
  out << fmt::format("\n## {} ({} cases:{} {}; {} float-exact; oracle fallback to exact LP {:.1f}%)\n\n",
                     gen::to_string(d.distribution), d.cases, cut, gen::describe(d.distribution), d.float_exact_cases,
                     d.oracle_calls ? 100.0 * double(d.oracle_fallbacks) / double(d.oracle_calls) : 0.0);
  out << "| method | origin | claim | cases | false rejects | false inside | false-intersect % (95% CI) | under-inside % "
         "| FI distance / scene (median / max) | set-up ns/frame | ns/test |\n";
  out << "|---|---|---|---:|---:|---:|---|---:|---|---:|---:|\n";
  for (const auto& m : d.methods) {
    const auto [lo, hi] = wilson95(m.false_intersect, m.truth_outside);
    std::string status = m.claim == Claim::none ? "none"
                         : m.refuted()          ? fmt::format("{} REFUTED ({}{})", to_string(m.claim), m.claim_violations,
                                                              m.float_exact_violations
                                                                  ? fmt::format("; {} float-exact", m.float_exact_violations)
                                                                  : std::string())
                         : m.fault              ? fmt::format("{} not refuted before the fault", to_string(m.claim))
                                                : fmt::format("{} held", to_string(m.claim));
    if (!m.three_way) status += ", two-way";
    else if (m.two_way_kinds) status += ", two-way on " + kind_list(m.two_way_kinds);
    if (m.fault)
      status += m.fault->index ? fmt::format("; FAULT on case {}", *m.fault->index) : std::string("; FAULT while timed");
    out << fmt::format("| {} | {} | {} | {} | {} | {} | {} ({}-{}) | {} | {} | {} | {}{}{} |\n", m.method,
                       to_string(m.origin), status, m.cases, m.false_reject, m.false_inside,
                       pct(m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0), pct(lo),
                       pct(hi),
                       m.three_way ? pct(under_inside_rate(m))
                                   : std::string("-"),
                       median_max(m.fi_distance), m.program.empty() ? ns(m.ns_setup_per_frame) : std::string("-"),
                       ns(m.ns_per_test), m.timed_batch ? " (batch)" : "",
                       std::isfinite(m.ns_per_test_own) ? fmt::format("; own {:.1f}", m.ns_per_test_own) : std::string());
  }
  for (const auto& m : d.methods)
    if (m.fault) out << "\nFAULT: " << m.fault->message(d.distribution, seed) << "\n";
}

void print_table_notes(const VerifyResult& r, std::ostream& out) {
  out << "\norigin: published = a text under test (a refuted claim is a finding); own = cullproof's, user = yours "
         "(a refuted claim fails the run).\n";
  out << "false-intersect % = false intersects / volumes truly outside; under-inside % = / volumes truly inside of "
         "the kinds the method answers three-way (two-way methods, or kinds, answer visible or outside: not charged).\n";
  out << "FI distance = the oracle's distance from a falsely kept volume to the frustum over the scene size; inf: the "
         "case's frustum, as its float values define it, is empty, so no distance to it is finite.\n";
  if (r.options.timing)
    out << fmt::format("cost: set-up = prepare, once per frame ('-' for a program's method: it prepares in its own "
                       "process, inside ns/test); ns/test = classify per volume, {} frames of {} volumes "
                       "per distribution (camera-path: {} consecutive frames of one path, {} volumes each), through "
                       "the method's array form where it has one (batch); own = what a program reports of its own "
                       "classification time over the same frames (docs/protocol.md); not timed ('-') after a fault "
                       "or an interruption.\n",
                       r.options.timing_frames, r.options.frame_size, r.options.timing_frames, gen::kPathObjects);
  if (r.faults() > 0)
    out << "FAULT: a method broke the method interface; it was not asked again in that distribution and its counts there "
           "are over the cases before its fault (the run fails).\n";
  if (r.interrupted) {
    std::size_t missing = r.options.distributions.size() - r.distributions.size();
    out << fmt::format("INTERRUPTED: the run was stopped; the counts are over the cases judged{}.\n",
                       missing ? fmt::format(", and {} distribution(s) were not run", missing) : std::string());
  }
  out << fmt::format("wall time {:.1f} s\n", r.wall_seconds);
}

void print_tables(const VerifyResult& r, std::ostream& out) {
  for (const auto& d : r.distributions) print_table(d, r.options.seed, out);
  print_table_notes(r, out);
}

namespace {

// A number, or one that is not finite by its name ("inf", "-inf", "nan"): JSON has none, and a
// shard's distances and ranks are read back in full (shards.cpp: number_or_name).
nlohmann::json number_or_name(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(fmt::format("{}", x)); }

nlohmann::json volume_names(unsigned bits) {
  nlohmann::json a = nlohmann::json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

}  // namespace

nlohmann::json fi_distance_histogram(const std::vector<double>& distances) {
  std::vector<std::uint64_t> counts(kFiHistogramLastDecade - kFiHistogramFirstDecade, 0);
  std::uint64_t below = 0, above = 0;
  for (const double x : distances) {
    // Decade k holds [10^k, 10^(k+1)); the bounds are compared with the exact powers of ten
    // as double rounds them, so a distance of exactly 10^k lands in decade k.
    if (!(x >= std::pow(10.0, kFiHistogramFirstDecade))) {
      ++below;
      continue;
    }
    if (x >= std::pow(10.0, kFiHistogramLastDecade)) {
      ++above;
      continue;
    }
    int k = int(std::floor(std::log10(x)));
    if (x < std::pow(10.0, k)) --k;  // log10 rounded up across a power of ten
    else if (x >= std::pow(10.0, k + 1)) ++k;
    k = std::clamp(k, kFiHistogramFirstDecade, kFiHistogramLastDecade - 1);
    ++counts[std::size_t(k - kFiHistogramFirstDecade)];
  }
  return {{"first_decade", kFiHistogramFirstDecade}, {"counts", counts}, {"below", below}, {"above", above}};
}

nlohmann::json to_json(const VerifyResult& r) {
  nlohmann::json j;
  j["seed"] = r.options.seed;
  j["cases_per_distribution"] = r.options.only_index ? 1 : r.options.cases;
  j["wall_seconds"] = r.wall_seconds;
  j["failed"] = r.failed();
  j["faults"] = r.faults();
  j["interrupted"] = r.interrupted;
  j["frame_size"] = r.options.frame_size;
  j["timing_frames"] = r.options.timing_frames;
  if (r.options.shard) {
    j["shard"] = {{"index", r.options.shard->index}, {"count", r.options.shard->count}};
    j["run"] = run_identity(r);
  }
  for (const auto& d : r.distributions) {
    nlohmann::json jd;
    jd["distribution"] = std::string(gen::to_string(d.distribution));
    jd["first_case"] = d.first_case;
    jd["cases"] = d.cases;
    jd["cases_asked"] = d.cases_asked;
    jd["interrupted"] = d.interrupted;
    jd["oracle_calls"] = d.oracle_calls;
    jd["oracle_fallbacks"] = d.oracle_fallbacks;
    jd["float_exact_cases"] = d.float_exact_cases;
    for (const auto& m : d.methods) {
      const auto [lo, hi] = wilson95(m.false_intersect, m.truth_outside);
      std::vector<double> dist = m.fi_distance;
      std::sort(dist.begin(), dist.end());
      nlohmann::json fault = nullptr;
      if (m.fault)
        fault = {{"problem", m.fault->problem},
                 {"index", m.fault->index ? nlohmann::json(*m.fault->index) : nlohmann::json(nullptr)},
                 {"reproduce", m.fault->index ? nlohmann::json(m.fault->reproduce) : nlohmann::json(nullptr)},
                 {"saved", m.fault->saved ? nlohmann::json(m.fault->saved->string()) : nlohmann::json(nullptr)},
                 {"where", m.fault->where},
                 {"case", m.fault->failing_case}};
      jd["methods"].push_back({{"method", m.method},
                               {"program", m.program.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.program)},
                               {"claim", std::string(to_string(m.claim))},
                               {"origin", std::string(to_string(m.origin))},
                               {"three_way", m.three_way},
                               {"refuted", m.refuted()},
                               {"claim_violations", m.claim_violations},
                               {"float_exact_violations", m.float_exact_violations},
                               {"first_violation", m.first_violation ? nlohmann::json(*m.first_violation) : nlohmann::json(nullptr)},
                               {"first_violation_reproduce", m.first_violation ? nlohmann::json(m.first_violation_reproduce) : nlohmann::json(nullptr)},
                               {"fault", fault},
                               {"cases", m.cases},
                               {"truth", {{"outside", m.truth_outside}, {"intersecting", m.truth_intersecting}, {"inside", m.truth_inside}}},
                               {"false_reject", m.false_reject},
                               {"false_inside", m.false_inside},
                               {"false_intersect", m.false_intersect},
                               {"under_inside", m.under_inside},
                               {"false_intersect_rate", m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0},
                               {"false_intersect_rate_ci95", {lo, hi}},
                               {"under_inside_rate", under_inside_rate(m)},
                               {"two_way_volumes", volume_names(m.two_way_kinds)},
                               {"fi_distance_median", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist[dist.size() / 2])},
                               {"fi_distance_max", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist.back())},
                               {"ns_per_test", std::isfinite(m.ns_per_test) ? nlohmann::json(m.ns_per_test) : nlohmann::json(nullptr)},
                               {"ns_setup_per_frame", std::isfinite(m.ns_setup_per_frame) ? nlohmann::json(m.ns_setup_per_frame) : nlohmann::json(nullptr)},
                               {"timed_batch", m.timed_batch},
                               {"ns_per_test_own", std::isfinite(m.ns_per_test_own) ? nlohmann::json(m.ns_per_test_own) : nlohmann::json(nullptr)},
                               {"fi_distance_histogram", fi_distance_histogram(m.fi_distance)},
                               {"volumes", volume_names(m.volumes)},
                               {"truth_inside_three_way", m.truth_inside_three_way},
                               {"corpus_written", m.corpus_written},
                               {"violation_ids", m.violation_ids}});
      if (r.options.shard) {  // in full, a distance that is not finite as its name ("inf": an empty frustum)
        nlohmann::json all = nlohmann::json::array();
        for (double x : dist) all.push_back(number_or_name(x));
        jd["methods"].back()["fi_distances"] = all;
        if (r.options.corpus) {  // the records it would write, for the merge to choose among
          nlohmann::json cs = nlohmann::json::array();
          for (const CorpusCandidate& c : m.corpus_candidates)
            cs.push_back({{"index", c.index},
                          {"class", to_string(c.error)},
                          {"violation", c.violation},
                          {"rank", number_or_name(c.rank)},
                          {"id", c.id},
                          {"file", c.file},
                          {"violates_claim", c.violates},
                          {"text", c.text}});
          jd["methods"].back()["corpus_candidates"] = std::move(cs);
        }
      }
    }
    j["distributions"].push_back(jd);
  }
  return j;
}

nlohmann::json run_identity(const VerifyResult& r) {
  nlohmann::json distributions = nlohmann::json::array(), methods = nlohmann::json::array();
  for (gen::Distribution d : r.options.distributions) distributions.push_back(std::string(gen::to_string(d)));
  if (!r.distributions.empty())
    for (const MethodStats& m : r.distributions.front().methods)
      methods.push_back({{"name", m.method}, {"claim", std::string(to_string(m.claim))},
                         {"origin", std::string(to_string(m.origin))}, {"program", m.program}});
  return {{"cullproof", CULLPROOF_VERSION},
          {"seed", r.options.seed},
          {"cases_per_distribution", r.options.cases},
          {"distributions", distributions},
          {"methods", methods},
          {"shards", r.options.shard ? r.options.shard->count : 1},
          {"timing", r.options.timing},
          {"frame_size", r.options.frame_size},
          {"timing_frames", r.options.timing_frames},
          {"corpus", r.options.corpus.has_value()},
          {"corpus_per_class", r.options.corpus_per_class},
          {"shrink_budget", r.options.shrink_budget}};
}

std::size_t VerifyResult::faults() const noexcept {
  std::size_t n = 0;
  for (const auto& d : distributions)
    for (const auto& m : d.methods) n += m.fault.has_value();
  return n;
}

bool VerifyResult::claim_broken() const noexcept {
  for (const auto& d : distributions)
    for (const auto& m : d.methods)
      if (m.origin != Origin::published && m.refuted()) return true;
  return false;
}

}  // namespace cullproof

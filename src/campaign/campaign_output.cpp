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

}  // namespace

void print_tables(const VerifyResult& r, std::ostream& out) {
  for (const auto& d : r.distributions) {
    out << fmt::format("\n## {} ({} cases: {}; {} float-exact; oracle fallback to exact LP {:.1f}%)\n\n",
                       gen::to_string(d.distribution), d.cases, gen::describe(d.distribution), d.float_exact_cases,
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
                                                  : fmt::format("{} held", to_string(m.claim));
      if (!m.three_way) status += ", two-way";
      out << fmt::format("| {} | {} | {} | {} | {} | {} | {} ({}-{}) | {} | {} | {} | {}{}{} |\n", m.method,
                         to_string(m.origin), status, m.cases, m.false_reject, m.false_inside,
                         pct(m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0), pct(lo),
                         pct(hi),
                         m.three_way ? pct(m.truth_inside ? double(m.under_inside) / double(m.truth_inside) : 0.0)
                                     : std::string("-"),
                         median_max(m.fi_distance), ns(m.ns_setup_per_frame), ns(m.ns_per_test),
                         m.timed_batch ? " (batch)" : "",
                         std::isfinite(m.ns_per_test_own) ? fmt::format("; own {:.1f}", m.ns_per_test_own) : std::string());
    }
  }
  out << "\norigin: published = a text under test (a refuted claim is a finding); own = cullproof's, user = yours "
         "(a refuted claim fails the run).\n";
  out << "false-intersect % = false intersects / volumes truly outside; under-inside % = / volumes truly inside "
         "(two-way methods answer visible or outside: not charged).\n";
  if (r.options.timing)
    out << fmt::format("cost: set-up = prepare, once per frame; ns/test = classify per volume, {} frames of {} volumes "
                       "per distribution (camera-path: {} consecutive frames of one path, {} volumes each), through "
                       "the method's array form where it has one (batch); own = what a program reports of its own "
                       "classification time over the same frames (docs/protocol.md).\n",
                       r.options.timing_frames, r.options.frame_size, r.options.timing_frames, gen::kPathObjects);
  out << fmt::format("wall time {:.1f} s\n", r.wall_seconds);
}

namespace {

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
  j["claim_broken"] = r.claim_broken();
  j["frame_size"] = r.options.frame_size;
  j["timing_frames"] = r.options.timing_frames;
  for (const auto& d : r.distributions) {
    nlohmann::json jd;
    jd["distribution"] = std::string(gen::to_string(d.distribution));
    jd["cases"] = d.cases;
    jd["oracle_calls"] = d.oracle_calls;
    jd["oracle_fallbacks"] = d.oracle_fallbacks;
    jd["float_exact_cases"] = d.float_exact_cases;
    for (const auto& m : d.methods) {
      const auto [lo, hi] = wilson95(m.false_intersect, m.truth_outside);
      std::vector<double> dist = m.fi_distance;
      std::sort(dist.begin(), dist.end());
      jd["methods"].push_back({{"method", m.method},
                               {"claim", std::string(to_string(m.claim))},
                               {"origin", std::string(to_string(m.origin))},
                               {"three_way", m.three_way},
                               {"refuted", m.refuted()},
                               {"claim_violations", m.claim_violations},
                               {"float_exact_violations", m.float_exact_violations},
                               {"first_violation", m.first_violation ? nlohmann::json(*m.first_violation) : nlohmann::json(nullptr)},
                               {"cases", m.cases},
                               {"truth", {{"outside", m.truth_outside}, {"intersecting", m.truth_intersecting}, {"inside", m.truth_inside}}},
                               {"false_reject", m.false_reject},
                               {"false_inside", m.false_inside},
                               {"false_intersect", m.false_intersect},
                               {"under_inside", m.under_inside},
                               {"false_intersect_rate", m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0},
                               {"false_intersect_rate_ci95", {lo, hi}},
                               {"under_inside_rate", m.truth_inside ? double(m.under_inside) / double(m.truth_inside) : 0.0},
                               {"fi_distance_median", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist[dist.size() / 2])},
                               {"fi_distance_max", dist.empty() ? nlohmann::json(nullptr) : nlohmann::json(dist.back())},
                               {"ns_per_test", std::isfinite(m.ns_per_test) ? nlohmann::json(m.ns_per_test) : nlohmann::json(nullptr)},
                               {"ns_setup_per_frame", std::isfinite(m.ns_setup_per_frame) ? nlohmann::json(m.ns_setup_per_frame) : nlohmann::json(nullptr)},
                               {"timed_batch", m.timed_batch},
                               {"ns_per_test_own", std::isfinite(m.ns_per_test_own) ? nlohmann::json(m.ns_per_test_own) : nlohmann::json(nullptr)},
                               {"fi_distance_histogram", fi_distance_histogram(m.fi_distance)},
                               {"volumes", volume_names(m.volumes)},
                               {"corpus_written", m.corpus_written},
                               {"violation_ids", m.violation_ids}});
    }
    j["distributions"].push_back(jd);
  }
  return j;
}

bool VerifyResult::claim_broken() const noexcept {
  for (const auto& d : distributions)
    for (const auto& m : d.methods)
      if (m.origin != Origin::published && m.refuted()) return true;
  return false;
}

}  // namespace cullproof

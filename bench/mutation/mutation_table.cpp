// cullproof_mutation_table [--seeds N]: the verifier measured as testing tools are measured. For
// every planted-bug culler (tests/mutants) and seed 1..N:
//  - the default `cullproof verify` (the generic distributions in order, 100,000 cases each, no
//    corpus, no timing): the family whose cases first break the claim, the cases drawn until then
//    (the distributions before it in full, and its cases up to the first failure), and the
//    seconds those cases take (measured: the earlier distributions run in full, then the
//    failing one up to its first failure);
//  - the test helper's default budget (every distribution in order, 2,000 cases each): the same;
//  - the claim-breaking cases that budget writes to a corpus on seed 1, shrunk: how far each lies
//    from the verdict it was given (error_distance) in units of its allowance, the smallest, and
//    how far from the frustum's boundary, the smallest (an allowance measured to the boundary
//    would forgive a case whose boundary distance is within it).
// Medians over the seeds; a mutant that survives a seed is counted as surviving. Controls are run
// the same way and must never be flagged. Prints the markdown table of docs/mutation.md.
#include "mutants.hpp"

#include "cullproof/campaign/campaign.hpp"
#include "cullproof/corpus/corpus.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <limits>
#include <unistd.h>
#include <iostream>
#include <string>
#include <vector>

using namespace cullproof;

namespace {

struct FirstFailure {
  bool found = false;
  std::string family;
  std::uint64_t cases = 0;
  double seconds = 0.0;
};

VerifyOptions base(std::uint64_t seed, std::uint64_t cases) {
  VerifyOptions o;
  o.seed = seed;
  o.cases = cases;
  o.progress = false;
  o.timing = false;
  o.corpus.reset();
  return o;
}

double timed(const VerifyOptions& o, const Method& m, VerifyResult* out = nullptr) {
  const auto t0 = std::chrono::steady_clock::now();
  VerifyResult r = run_verify(o, {m});
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (out) *out = std::move(r);
  return s;
}

// First failures of every culler on one seed: one campaign per distribution with all of them (the
// oracle's work shared), then, per culler that failed, its seconds measured alone: the earlier
// distributions in full and the failing one up to its first failure.
std::vector<FirstFailure> first_failures(const std::vector<Method>& ms, std::uint64_t seed,
                                         const std::vector<gen::Distribution>& order, std::uint64_t per) {
  std::vector<FirstFailure> f(ms.size());
  std::vector<bool> done(ms.size(), false);
  for (gen::Distribution d : order) {
    VerifyOptions o = base(seed, per);
    o.distributions = {d};
    const VerifyResult r = run_verify(o, ms);
    for (std::size_t k = 0; k < ms.size(); ++k) {
      if (done[k]) continue;
      const MethodStats& s = r.distributions[0].methods[k];
      if (!s.first_violation) {
        f[k].cases += per;
        continue;
      }
      done[k] = true;
      f[k].found = true;
      f[k].family = std::string(gen::to_string(d));
      f[k].cases += *s.first_violation + 1;
      double secs = 0.0;
      for (gen::Distribution e : order) {
        VerifyOptions one = base(seed, per);
        one.distributions = {e};
        if (e == d) {
          one.cases = *s.first_violation + 1;
          secs += timed(one, ms[k]);
          break;
        }
        secs += timed(one, ms[k]);
      }
      f[k].seconds = secs;
    }
  }
  return f;
}


template <class T>
T median(std::vector<T> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string summary(const std::vector<FirstFailure>& runs) {
  std::size_t caught = 0;
  std::vector<std::string> families;
  std::vector<std::uint64_t> cases;
  std::vector<double> secs;
  for (const FirstFailure& f : runs) {
    if (!f.found) continue;
    ++caught;
    families.push_back(f.family);
    cases.push_back(f.cases);
    secs.push_back(f.seconds);
  }
  if (caught == 0) return "SURVIVED | - | -";
  std::sort(families.begin(), families.end());
  std::string fam;
  for (std::size_t i = 0; i < families.size(); ++i)
    if (i == 0 || families[i] != families[i - 1]) fam += (fam.empty() ? "" : ", ") + families[i];
  std::string head = caught == runs.size() ? fam : fmt::format("{} ({} of {} seeds)", fam, caught, runs.size());
  return fmt::format("{} | {} | {:.3f}", head, median(cases), median(secs));
}


// The shrunk claim-breaking cases of every culler (the test helper's budget, seed 1, with a corpus):
// per culler, "N, K float-exact, J from forgiven errors: median M, fewest F (family, F0 as found) /
// B": over the violations found (not float-exact; not an error the claim forgave, kept as an
// example, that shrank into one it does not), the median and the fewest allowances from the
// verdict given (and how many the fewest was before shrinking), the fewest from the boundary, and
// how many were shrunk below the size found (none, unless the shrinker loses an error's size).
std::vector<std::string> shrunk_sizes(const std::vector<Method>& ms, const std::vector<gen::Distribution>& order) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-mutation-table-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o = base(1, 2000);
  o.distributions = order;
  o.corpus = dir;
  run_verify(o, ms);
  std::vector<std::string> out;
  const std::vector<CorpusEntry> corpus = load_corpus(dir);
  for (const Method& m : ms) {
    std::size_t n = 0, exact = 0;
    std::vector<double> ratios;
    double fewest = std::numeric_limits<double>::infinity(), boundary = fewest, fewest_found = fewest;
    std::size_t lowered = 0, from_forgiven = 0;
    std::string fewest_family;
    for (const CorpusEntry& e : corpus) {
      const auto& x = e.c.extra;
      if (e.method != m.name || !x.value("violates_claim", false)) continue;
      ++n;
      const double allowance = x.value("allowance", 0.0);
      if (!(allowance > 0.0)) {
        ++exact;
        continue;
      }
      const auto number = [&](const char* k) {
        return x.contains(k) && x[k].is_number() ? x[k].get<double>() : std::numeric_limits<double>::infinity();
      };
      const double r = number("verdict_distance") / allowance;
      // The case as drawn, before shrinking: how many allowances beyond it was (the shrinker keeps
      // at least that many, up to 1,000). A case recorded with its camera path was not shrunk.
      double found = r;
      if (!e.path) {
        const gen::GenCase g = gen::draw_case(gen::parse_distributions(e.distribution).at(0),
                                              x.at("seed").get<std::uint64_t>(), x.at("index").get<std::uint64_t>());
        const Answer v = checked_classify(m, g.frustum, g.volume);
        const double a = m.tolerance * gen::case_scale(g.frustum, g.volume);
        found = v && a > 0.0 && !gen::float_exact(g.frustum, g.volume) ? error_distance(g.frustum, g.volume, *v) / a
                                                                          : std::numeric_limits<double>::infinity();
      }
      // An error the claim forgave, kept as an example, may shrink into one it does not: counted
      // apart, the rest are the violations found.
      if (!(found > 1.0)) {
        ++from_forgiven;
        continue;
      }
      ratios.push_back(r);
      boundary = std::min(boundary, number("distance") / allowance);
      if (r < std::min(found, 1000.0) * (1 - 1e-9)) ++lowered;
      if (r < fewest) fewest = r, fewest_found = found, fewest_family = e.distribution;
    }
    const std::string apart = (exact ? fmt::format(", {} float-exact", exact) : "") +
                              (from_forgiven ? fmt::format(", {} from forgiven errors", from_forgiven) : "");
    if (n == 0) out.push_back("-");
    else if (ratios.empty()) out.push_back(fmt::format("{}{}", n, apart));
    else
      out.push_back(fmt::format("{}{}: median {:.3g}, fewest {:.3g} ({}, {:.3g} as found) / {:.3g}{}", n, apart,
                                median(ratios), fewest, fewest_family, fewest_found, boundary,
                                lowered ? fmt::format("; {} shrunk below the size found", lowered) : ""));
  }
  std::filesystem::remove_all(dir);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  int seeds = 5;
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], "--seeds") == 0 && i + 1 < argc) seeds = std::max(1, std::atoi(argv[++i]));
  const std::vector<gen::Distribution> verify_order = gen::generic_distributions();
  const std::vector<gen::Distribution> helper_order = gen::no_overflow_distributions();
  std::cout << "| culler | defect | default `cullproof verify`: caught by | cases to first failure | seconds | "
               "test helper: caught by | cases | seconds | shrunk cases (seed 1): allowances from the verdict / fewest from the boundary |\n"
               "|---|---|---|---:|---:|---|---:|---:|---|\n";
  std::size_t mutants = 0, refuted = 0, controls_flagged = 0;
  const std::vector<mutants::Mutant> all = mutants::all();
  std::vector<Method> ms;
  for (const mutants::Mutant& m : all) ms.push_back(m.method);
  std::vector<std::vector<FirstFailure>> v(all.size()), h(all.size());
  for (int s = 1; s <= seeds; ++s) {
    const auto fv = first_failures(ms, std::uint64_t(s), verify_order, 100000);
    const auto fh = first_failures(ms, std::uint64_t(s), helper_order, 2000);
    for (std::size_t k = 0; k < all.size(); ++k) v[k].push_back(fv[k]), h[k].push_back(fh[k]);
    std::cerr << "seed " << s << " done\n";
  }
  const std::vector<std::string> shrunk = shrunk_sizes(ms, helper_order);
  for (std::size_t k = 0; k < all.size(); ++k) {
    const mutants::Mutant& m = all[k];
    bool all_v = true, all_h = true, any = false;
    for (const auto& f : v[k]) all_v = all_v && f.found, any = any || f.found;
    for (const auto& f : h[k]) all_h = all_h && f.found, any = any || f.found;
    const std::string name = m.control ? "control `" + m.method.name + "`" : "`" + m.method.name + "`";
    std::cout << fmt::format("| {} | {} | {} | {} | {} |\n", name, m.defect,
                             m.control && !any ? "never flagged | - | -" : summary(v[k]),
                             m.control && !any ? "never flagged | - | -" : summary(h[k]), shrunk[k]);
    if (m.control) {
      controls_flagged += any;
    } else {
      ++mutants;
      refuted += all_v && all_h;
    }
  }
  std::cout << fmt::format("\nmutation score {} / {} (refuted on every seed by both); controls flagged: {}; seeds 1..{}\n",
                           refuted, mutants, controls_flagged, seeds);
  return refuted == mutants && controls_flagged == 0 ? 0 : 1;
}

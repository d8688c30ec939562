// Every method's claim (docs/semantics.md "Claims"), checked as stated against the exact oracle, on
// every distribution: certified claims with no exception, conservative/exact claims with errors
// allowed only within the method's documented tolerance (the oracle's exact distance decides).
// A published method whose claim the corpus already refutes is reported, not failed: its
// refuting cases live in corpus/ and test_corpus checks that they still refute it. A new
// refutation of any other method fails here with the exact counterexample.
#include "cullproof/arbitrary.hpp"
#include "cullproof/campaign.hpp"
#include "cullproof/corpus.hpp"
#include "cullproof/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <set>

using namespace cullproof;

namespace {

// Published methods with a committed claim-violating corpus case.
const std::set<std::string>& refuted_in_corpus() {
  static const std::set<std::string> s = [] {
    std::set<std::string> out;
    for (const CorpusEntry& e : load_corpus(CULLPROOF_CORPUS_DIR)) {
      const auto v = e.c.extra.find("violates_claim");
      const Method* m = find_builtin(e.method);
      if (m && m->origin == Origin::published && v != e.c.extra.end() && v->is_boolean() && v->get<bool>()) out.insert(e.method);
    }
    return out;
  }();
  return s;
}

class Claims : public ::testing::TestWithParam<gen::Distribution> {};

TEST_P(Claims, HoldAgainstTheOracle) {
  const gen::Distribution d = GetParam();
  const auto& refuted = refuted_in_corpus();
  std::map<std::string, int> reported;
  const bool ok = rc::check(std::string("claims hold on ") + std::string(gen::to_string(d)), [&] {
    const gen::GenCase g = *gen::case_of(d);
    const Visibility truth = oracle::truth(g.frustum, g.volume);
    for (const Method& m : builtin_methods()) {
      if (!m.takes(g.volume)) continue;
      const auto v = m.classify(g.frustum, g.volume);
      if (!v) continue;
      const ErrorClass cls = error_class(*v, truth, m.three_way);
      if (cls == ErrorClass::correct || m.claim == Claim::none) continue;
      const oracle::Result r = oracle::classify(g.frustum, g.volume, {true, true, false});
      const double scale = gen::case_scale(g.frustum, g.volume);
      const double dist = error_distance(g.frustum, g.volume, cls, r.distance);
      if (!violates_claim(m.claim, cls, dist, m.tolerance, scale, gen::float_exact(g.frustum, g.volume))) continue;
      if (refuted.count(m.name)) {
        ++reported[m.name];  // known: the corpus holds the evidence
        continue;
      }
      RC_FAIL(m.name + " (claim " + std::string(to_string(m.claim)) + ") says " + std::string(to_string(*v)) +
              ", truth " + std::string(to_string(truth)) + " (" + std::string(to_string(cls)) + "), exact distance " +
              std::to_string(r.distance) + ", backward distance " + std::to_string(dist) + ", tolerance " + std::to_string(m.tolerance * scale));
    }
  });
  EXPECT_TRUE(ok);
  for (const auto& [name, n] : reported)
    std::cout << "[claim refuted, known from the corpus] " << name << ": " << n << " more refuting case(s) on "
              << gen::to_string(d) << "\n";
}

std::vector<gen::Distribution> all_distributions() { return gen::parse_distributions("all"); }

std::string distribution_name(const ::testing::TestParamInfo<gen::Distribution>& p) {
  std::string s(gen::to_string(p.param));
  for (char& ch : s)
    if (ch == '-') ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(AllDistributions, Claims, ::testing::ValuesIn(all_distributions()), distribution_name);

}  // namespace

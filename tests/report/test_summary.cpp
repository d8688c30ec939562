// The summary of a run: the Pareto front, the distance histogram, the summary read from a
// hand-made result (pooled rates, median cost, groups by volume kinds, refuted claims with their
// corpus cases), a malformed result refused naming the field, and a campaign run whose
// claim-breaking cases are named again on a second run that writes nothing new.
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/report/summary.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <sstream>

using namespace cullproof;
using report::CostPoint;
using nlohmann::json;

TEST(ParetoFront, KeepsTheCheapestForEachRate) {
  // a: cheap and wasteful; b: dominated by a (dearer, as wasteful); c: dearer, better;
  // d: dominated by c; e: the dearest and exact; f: equal to c (the first of equals is kept).
  const std::vector<CostPoint> p = {{2.0, 0.08}, {3.0, 0.08}, {10.0, 0.02}, {12.0, 0.03}, {100.0, 0.0}, {10.0, 0.02}};
  EXPECT_EQ(report::pareto_front(p), (std::vector<std::size_t>{0, 2, 4}));
  EXPECT_TRUE(report::pareto_front({}).empty());
  // Equal cost: the lower rate alone is on the front.
  EXPECT_EQ(report::pareto_front({{5.0, 0.5}, {5.0, 0.1}}), (std::vector<std::size_t>{1}));
}

TEST(Median, OddEvenAndUnmeasured) {
  EXPECT_EQ(report::median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(report::median({4.0, 1.0, 2.0, 3.0}), 2.5);
  EXPECT_FALSE(report::median({}).has_value());
  EXPECT_EQ(report::median({std::nan(""), 7.0}), 7.0);
}

TEST(FiDistanceHistogram, DecadesIncludeTheirLowerBound) {
  const json h = fi_distance_histogram({0.0, 1e-17, 1e-16, 0.5, 0.999, 1.0, 99.0, 100.0, 1e9});
  EXPECT_EQ(h["first_decade"], kFiHistogramFirstDecade);
  const auto counts = h["counts"].get<std::vector<std::uint64_t>>();
  ASSERT_EQ(counts.size(), std::size_t(kFiHistogramLastDecade - kFiHistogramFirstDecade));
  auto at = [&](int decade) { return counts[std::size_t(decade - kFiHistogramFirstDecade)]; };
  EXPECT_EQ(h["below"], 2u);  // 0 and 1e-17
  EXPECT_EQ(at(-16), 1u);     // exactly 1e-16
  EXPECT_EQ(at(-1), 2u);      // 0.5, 0.999
  EXPECT_EQ(at(0), 1u);       // exactly 1
  EXPECT_EQ(at(1), 1u);       // 99
  EXPECT_EQ(h["above"], 2u);  // 100 and 1e9
}

namespace {

json method_json(const std::string& name, const std::string& claim, std::vector<std::string> volumes, std::uint64_t outside,
                 std::uint64_t fi, std::uint64_t violations, json ns, std::vector<std::string> ids = {}) {
  return {{"method", name},
          {"claim", claim},
          {"origin", "own"},
          {"three_way", true},
          {"refuted", violations > 0},
          {"claim_violations", violations},
          {"float_exact_violations", 0},
          {"first_violation", violations ? json(17) : json(nullptr)},
          {"first_violation_reproduce",
           violations ? json("cullproof verify --seed 5 --distribution uniform --index 17 --method " + name) : json(nullptr)},
          {"fault", nullptr},
          {"cases", outside * 2},
          {"truth", {{"outside", outside}, {"intersecting", outside / 2}, {"inside", outside / 2}}},
          {"false_reject", violations},
          {"false_inside", 0},
          {"false_intersect", fi},
          {"under_inside", 0},
          {"ns_per_test", ns},
          {"ns_per_test_own", nullptr},
          {"volumes", volumes},
          {"violation_ids", ids}};
}

json two_families() {
  json r = {{"seed", 5}, {"cases_per_distribution", 100}, {"failed", true}, {"interrupted", false}};
  r["distributions"] = json::array();
  r["distributions"].push_back(
      {{"distribution", "uniform"},
       {"methods",
        {method_json("cheap", "conservative", {"aabb"}, 100, 10, 0, 2.0),
         method_json("exact-box", "exact", {"aabb"}, 100, 0, 0, 50.0),
         method_json("slow-and-wasteful", "conservative", {"aabb"}, 100, 20, 0, 60.0),
         method_json("broken", "conservative", {"aabb"}, 100, 0, 3, 1.0, {"broken-false-reject-000000000001"}),
         method_json("ball", "conservative", {"sphere"}, 100, 5, 0, 1.5),
         method_json("guess", "none", {"sphere"}, 100, 0, 0, 0.5)}}});
  r["distributions"].push_back(
      {{"distribution", "corner"},
       {"methods",
        {method_json("cheap", "conservative", {"aabb"}, 300, 70, 0, 4.0),
         method_json("exact-box", "exact", {"aabb"}, 300, 1, 0, 70.0),
         method_json("slow-and-wasteful", "conservative", {"aabb"}, 300, 90, 0, 80.0),
         method_json("broken", "conservative", {"aabb"}, 300, 0, 0, 1.0),
         method_json("ball", "conservative", {"sphere"}, 300, 5, 0, nullptr),
         method_json("guess", "none", {"sphere"}, 300, 0, 0, 0.5)}}});
  return r;
}

}  // namespace

TEST(Summary, AFaultedMethodIsListedWithItsReproduceLineAndKeptOffTheFront) {
  json r = two_families();
  r["distributions"][1]["methods"][0]["fault"] = {
      {"problem", "external program 'x': exited (signal 6) before answering frame 9 (1 volume(s) for method 'cheap')"},
      {"index", 33},
      {"reproduce", "cullproof verify --seed 5 --distribution corner --index 33 --external cheap -- x"},
      {"saved", nullptr},
      {"case", json::object()}};
  const report::Summary s = report::summarize(r);
  ASSERT_EQ(s.faults.size(), 1u);
  EXPECT_EQ(s.faults[0].method, "cheap");
  EXPECT_EQ(s.faults[0].family, "corner");
  EXPECT_EQ(s.faults[0].index, 33u);
  EXPECT_TRUE(s.methods[0].faulted);
  for (const report::VolumeGroup& g : s.cheapest)
    for (const report::FrontStep& f : g.front) EXPECT_NE(f.method, "cheap") << "its counts stop at the fault";
  std::ostringstream out;
  report::print_summary(s, out);
  EXPECT_NE(out.str().find("faults: 1"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("cheap on corner, case 33: external program 'x': exited (signal 6)"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("reproduce: cullproof verify --seed 5 --distribution corner --index 33 --external cheap -- x"),
            std::string::npos)
      << out.str();
  // A fault that is not an object is refused, naming the field.
  r["distributions"][1]["methods"][0]["fault"] = "crashed";
  try {
    report::summarize(r);
    ADD_FAILURE() << "a malformed fault was read";
  } catch (const report::ResultError& e) {
    EXPECT_EQ(std::string(e.what()), "result.distributions[1].methods[0].fault: expected an object or null");
  }
}

TEST(Summary, PoolsFamiliesAndFindsTheFrontPerVolumeKinds) {
  const report::Summary s = report::summarize(two_families());
  EXPECT_EQ(s.seed, 5u);
  EXPECT_EQ(s.families, (std::vector<std::string>{"uniform", "corner"}));
  ASSERT_EQ(s.methods.size(), 6u);
  const report::MethodOverall& cheap = s.methods[0];
  EXPECT_EQ(cheap.truth_outside, 400u);
  EXPECT_EQ(cheap.false_intersect, 80u);
  EXPECT_DOUBLE_EQ(cheap.fi_rate, 0.2);  // pooled: (10 + 70) / (100 + 300), not the mean of rates
  EXPECT_EQ(cheap.ns_per_test, 3.0);     // median of 2 and 4
  EXPECT_EQ(s.methods[4].ns_per_test, 1.5);  // a family where it was not timed takes no part

  ASSERT_EQ(s.broken.size(), 1u);
  EXPECT_EQ(s.broken[0].method, "broken");
  ASSERT_EQ(s.broken[0].families.size(), 1u);  // only where it broke
  EXPECT_EQ(s.broken[0].families[0].family, "uniform");
  EXPECT_EQ(s.broken[0].families[0].corpus_ids, (std::vector<std::string>{"broken-false-reject-000000000001"}));
  EXPECT_EQ(s.broken[0].families[0].reproduce, "cullproof verify --seed 5 --distribution uniform --index 17 --method broken");

  // Groups in the fixed kind order; the refuted method, though cheapest, is on no front, nor the
  // one that promises nothing, though cheaper and better.
  ASSERT_EQ(s.cheapest.size(), 2u);
  EXPECT_EQ(s.cheapest[0].volumes, (std::vector<std::string>{"sphere"}));
  ASSERT_EQ(s.cheapest[0].front.size(), 1u);
  EXPECT_EQ(s.cheapest[0].front[0].method, "ball");
  EXPECT_EQ(s.cheapest[1].volumes, (std::vector<std::string>{"aabb"}));
  ASSERT_EQ(s.cheapest[1].front.size(), 2u);
  EXPECT_EQ(s.cheapest[1].front[0].method, "cheap");
  EXPECT_EQ(s.cheapest[1].front[1].method, "exact-box");
  EXPECT_EQ(s.cheapest[1].front[1].ns_per_test, 60.0);
  EXPECT_EQ(s.cheapest[1].methods, 3u);

  std::ostringstream out;
  report::print_summary(s, out);
  const std::string text = out.str();
  EXPECT_NE(text.find("claims refuted: 1 of 6 methods"), std::string::npos) << text;
  EXPECT_NE(text.find("broken (own, claims conservative): 3 cases on uniform"), std::string::npos) << text;
  EXPECT_NE(text.find("corpus broken-false-reject-000000000001"), std::string::npos) << text;
  EXPECT_NE(text.find("false intersects 20% (95%"), std::string::npos) << text;
  EXPECT_EQ(text.find("slow-and-wasteful"), std::string::npos) << text;  // dominated
}

TEST(Summary, AMalformedResultIsRefusedNamingTheField) {
  json r = two_families();
  r["distributions"][1]["methods"][3].erase("false_intersect");
  ASSERT_EQ(r["distributions"][1]["methods"][3]["method"], "broken");
  try {
    report::summarize(r);
    FAIL() << "accepted a result without false_intersect";
  } catch (const report::ResultError& e) {
    EXPECT_EQ(std::string(e.what()), "result.distributions[1].methods[3].false_intersect: missing");
  }
  r = two_families();
  r["distributions"][0]["methods"][0]["cases"] = -4;
  EXPECT_THROW(report::summarize(r), report::ResultError);
  EXPECT_THROW(report::summarize(json::array()), report::ResultError);
}

TEST(Summary, ARunNamesTheCorpusCasesOfABrokenClaimAgainWhenTheyExistAlready) {
  // A box culler that forgets the far plane: conservative claimed, refuted on boxes beyond it.
  MethodInfo info;
  info.name = "no-far-plane";
  info.claim = Claim::conservative;
  info.tolerance = 1e-5;
  const Method m = make_method(info, [](const CaseFrustum& f, const Aabb& b) {
    Visibility v = Visibility::inside;
    for (int i = 0; i < 5; ++i) {
      const Plane& p = f.planes[i];
      const glm::vec3 pv(p.n.x >= 0 ? b.max.x : b.min.x, p.n.y >= 0 ? b.max.y : b.min.y, p.n.z >= 0 ? b.max.z : b.min.z);
      const glm::vec3 nv(p.n.x >= 0 ? b.min.x : b.max.x, p.n.y >= 0 ? b.min.y : b.max.y, p.n.z >= 0 ? b.min.z : b.max.z);
      if (glm::dot(p.n, pv) + p.d < 0) return Visibility::outside;
      if (glm::dot(p.n, nv) + p.d < 0) v = Visibility::intersecting;
    }
    return v;
  });
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-summary-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o;
  o.cases = 400;
  o.distributions = {gen::Distribution::uniform};
  o.threads = 2;
  o.progress = false;
  o.timing = false;
  o.corpus = dir;
  const VerifyResult first = run_verify(o, {m});
  const VerifyResult second = run_verify(o, {m});
  const auto& a = first.distributions.at(0).methods.at(0);
  const auto& b = second.distributions.at(0).methods.at(0);
  ASSERT_TRUE(a.refuted());
  EXPECT_FALSE(a.violation_ids.empty());
  EXPECT_EQ(a.violation_ids, b.violation_ids);  // named again
  EXPECT_TRUE(b.corpus_written.empty());        // though nothing new was written
  const std::vector<CorpusEntry> entries = load_corpus(dir);
  for (const std::string& id : b.violation_ids) {
    const auto e = std::find_if(entries.begin(), entries.end(), [&](const CorpusEntry& x) { return x.c.id == id; });
    ASSERT_NE(e, entries.end()) << id;
    EXPECT_TRUE(e->c.extra.at("violates_claim").get<bool>()) << id;
  }
  const report::Summary s = report::summarize(to_json(second));
  ASSERT_EQ(s.broken.size(), 1u);
  EXPECT_EQ(s.broken[0].families.at(0).corpus_ids, b.violation_ids);
  std::filesystem::remove_all(dir);
}

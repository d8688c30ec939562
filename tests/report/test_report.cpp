// The report's page: the charts' specifications from a hand-made run (one point per timed method,
// rates of 0 on a floor below every measured rate, the Pareto front flagged; heat-map cells per
// method and family that applies; distance cells per decade), and the text put into the page made
// safe for HTML and for <script>.
#include "cullproof/report.hpp"
#include "cullproof/summary.hpp"

#include <gtest/gtest.h>

using namespace cullproof;
using nlohmann::json;

namespace {

json method_json(const std::string& name, const std::string& claim, std::uint64_t outside, std::uint64_t fi, std::uint64_t violations,
                 json ns, std::vector<std::uint64_t> histogram_counts = {}) {
  std::vector<std::uint64_t> counts(18, 0);
  for (std::size_t i = 0; i < histogram_counts.size(); ++i) counts[i] = histogram_counts[i];
  return {{"method", name}, {"claim", claim}, {"origin", "own"}, {"three_way", true}, {"refuted", violations > 0},
          {"claim_violations", violations}, {"float_exact_violations", 0}, {"first_violation", violations ? json(3) : json(nullptr)},
          {"cases", outside ? outside * 2 : 0}, {"truth", {{"outside", outside}, {"intersecting", 0}, {"inside", 0}}},
          {"false_reject", violations}, {"false_inside", 1}, {"false_intersect", fi}, {"under_inside", 0},
          {"ns_per_test", ns}, {"ns_per_test_own", nullptr}, {"volumes", {"aabb"}}, {"violation_ids", json::array()},
          {"fi_distance_histogram", {{"first_decade", -16}, {"counts", counts}, {"below", 0}, {"above", 0}}}};
}

json run() {
  json r = {{"seed", 1}, {"cases_per_distribution", 1000}, {"claim_broken", false}, {"wall_seconds", 1.0}};
  r["distributions"] = json::array(
      {{{"distribution", "uniform"},
        {"methods",
         {method_json("fast", "conservative", 1000, 50, 0, 2.0, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 10, 40}),
          method_json("exact", "exact", 1000, 0, 0, 100.0),
          method_json("flawed", "exact", 1000, 3, 2, 30.0, {0, 0, 0, 0, 0, 0, 0, 0, 0, 3}),
          method_json("untimed", "conservative", 1000, 10, 0, nullptr)}}},
       {{"distribution", "corner"},
        {"methods",
         {method_json("fast", "conservative", 500, 100, 0, 4.0),
          method_json("exact", "exact", 500, 1, 0, 120.0, {0, 0, 0, 0, 0, 0, 0, 0, 1}),
          method_json("flawed", "exact", 0, 0, 0, 30.0),  // applies to no case here
          method_json("untimed", "conservative", 500, 10, 0, nullptr)}}}});
  return r;
}

const json& layer_data(const json& spec) { return spec.at("data").at("values"); }

}  // namespace

TEST(ReportCharts, AccuracyCostHasOnePointPerTimedMethodAndAFloorForZero) {
  const json spec = report::accuracy_cost_spec(run(), "");
  const json& v = layer_data(spec);
  ASSERT_EQ(v.size(), 3u);  // "untimed" is named in the subtitle instead
  EXPECT_NE(spec.at("title").at("subtitle").get<std::string>().find("not timed: untimed"), std::string::npos);
  const double floor = spec.at("usermeta").at("floor");
  EXPECT_LT(floor, 1.0 / 1500);  // below any rate one false intersect in 1,500 outside volumes gives
  for (const json& p : v) {
    if (p.at("method") == "exact") {
      EXPECT_DOUBLE_EQ(p.at("rate").get<double>(), 1.0 / 1500);
      EXPECT_TRUE(p.at("front").get<bool>());
    }
    if (p.at("method") == "fast") {
      EXPECT_EQ(p.at("ns"), 3.0);  // median over the two families
      EXPECT_TRUE(p.at("front").get<bool>());
    }
    if (p.at("method") == "flawed") {
      EXPECT_EQ(p.at("status"), "REFUTED");
      EXPECT_FALSE(p.at("front").get<bool>());
    }
    EXPECT_GE(p.at("y_lo").get<double>(), floor);
  }
  // In uniform "exact" found none: its point sits on the floor.
  const json fam = report::accuracy_cost_spec(run(), "uniform");
  for (const json& p : layer_data(fam))
    if (p.at("method") == "exact") {
      EXPECT_EQ(p.at("rate"), 0.0);
      EXPECT_EQ(p.at("y"), fam.at("usermeta").at("floor"));
    }
  // "flawed" applies to no case of corner: no point there.
  EXPECT_EQ(layer_data(report::accuracy_cost_spec(run(), "corner")).size(), 2u);
}

TEST(ReportCharts, HeatMapHasACellPerMethodAndFamilyThatApplies) {
  const json spec = report::claims_heatmap_spec(run());
  const json& v = spec.at("data").at("values");
  EXPECT_EQ(v.size(), 7u);  // 4 + 3: "flawed" takes no case of corner
  for (const json& c : v)
    if (c.at("method") == "flawed") {
      EXPECT_EQ(c.at("false_reject"), 2u);
      EXPECT_EQ(c.at("fr_text"), "flawed, uniform: 2 false rejects");
    }
}

TEST(ReportCharts, DistanceCellsPerDecadeWithTheFamiliesPooled) {
  const json spec = report::distance_spec(run());
  std::map<std::string, std::uint64_t> all;
  for (const json& c : spec.at("data").at("values"))
    if (c.at("family") == "all families") all[c.at("method").get<std::string>() + " " + c.at("bin").get<std::string>()] = c.at("count");
  EXPECT_EQ(all.size(), 4u);
  EXPECT_EQ(all["fast 1e-2"], 10u);   // counts[14] is [1e-2, 1e-1)
  EXPECT_EQ(all["fast 1e-1"], 40u);
  EXPECT_EQ(all["flawed 1e-7"], 3u);
  EXPECT_EQ(all["exact 1e-8"], 1u);
  json bad = run();
  bad["distributions"][0]["methods"][0]["fi_distance_histogram"]["counts"].erase(0);
  EXPECT_THROW(report::distance_spec(bad), report::ResultError);
}

TEST(ReportPage, TextIsMadeSafeForHtmlAndScripts) {
  EXPECT_EQ(report::html_escape("<a href=\"x\">&'</a>"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;&lt;/a&gt;");
  const json j = {{"note", "</script><script>alert(1)</script>"}};
  const std::string text = report::script_json(j);
  EXPECT_EQ(text.find("</"), std::string::npos);
  EXPECT_EQ(json::parse(text), j);  // reads back the same
  EXPECT_EQ(report::script_text("var s = '</script>'; var t = '</SCRIPT'"), "var s = '<\\/script>'; var t = '<\\/SCRIPT'");
}

TEST(ReportPage, ThePageHoldsTheSummaryTheChartsAndTheScript) {
  const std::string page = report::report_html(run(), {}, "window.marker = 1;");
  EXPECT_NE(page.find("<section id=\"summary\">"), std::string::npos);
  EXPECT_NE(page.find("id=\"chart-all\""), std::string::npos);
  EXPECT_NE(page.find("id=\"chart-family-corner\""), std::string::npos);
  EXPECT_NE(page.find("id=\"heatmap\""), std::string::npos);
  EXPECT_NE(page.find("<script>window.marker = 1;</script>"), std::string::npos);
  EXPECT_EQ(page.find("id=\"corpus\""), std::string::npos);  // no corpus given
  EXPECT_EQ(page.find("http://"), std::string::npos);
}

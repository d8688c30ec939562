// The report's page: the charts' specifications from a hand-made run (one point per timed method,
// rates of 0 on a floor below every measured rate, the Pareto front flagged; heat-map cells per
// method and family that applies; distance cells per decade), and the text put into the page made
// safe for HTML and for <script>.
#include "cullproof/report/report.hpp"
#include "cullproof/report/summary.hpp"

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
          {"first_violation_reproduce", violations ? json("cullproof verify --seed 1 --distribution uniform --index 3 --method " + name) : json(nullptr)},
          {"fault", nullptr},
          {"cases", outside ? outside * 2 : 0}, {"truth", {{"outside", outside}, {"intersecting", 0}, {"inside", 0}}},
          {"false_reject", violations}, {"false_inside", 1}, {"false_intersect", fi}, {"under_inside", 0},
          {"ns_per_test", ns}, {"ns_per_test_own", nullptr}, {"volumes", {"aabb"}}, {"violation_ids", json::array()},
          {"fi_distance_histogram", {{"first_decade", -16}, {"counts", counts}, {"below", 0}, {"above", 0}}}};
}

json run() {
  json r = {{"seed", 1}, {"cases_per_distribution", 1000}, {"failed", false}, {"interrupted", false}, {"wall_seconds", 1.0}};
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

TEST(ReportPage, AFaultIsShownAsAFaultNeverAsHeld) {
  json r = run();
  r["failed"] = true;
  r["distributions"][1]["methods"][0]["fault"] = {{"problem", "method 'fast' threw: out of memory"},
                                                  {"index", 12},
                                                  {"reproduce", "cullproof verify --seed 1 --distribution corner --index 12 --method fast"},
                                                  {"saved", nullptr},
                                                  {"case", json::object()}};
  const std::string page = report::report_html(r, {}, "");
  EXPECT_NE(page.find("<table id=\"faults\">"), std::string::npos);
  EXPECT_NE(page.find("FAULT: method &#39;fast&#39; threw: out of memory"), std::string::npos);
  EXPECT_NE(page.find("cullproof verify --seed 1 --distribution corner --index 12 --method fast"), std::string::npos);
  const json spec = report::accuracy_cost_spec(r, "");
  bool found = false;
  for (const json& p : layer_data(spec)) {
    if (p.at("method") != "fast") continue;
    found = true;
    EXPECT_EQ(p.at("claim_text"), "conservative not refuted before the fault; FAULT: the counts stop at it");
  }
  EXPECT_TRUE(found);
}

// ---- the corpus drawn ----------------------------------------------------------------------

#include "cullproof/report/case_view.hpp"
#include "cullproof/core/frustum_build.hpp"

namespace {

// The unit cube [-1, 1]^3 as six planes (left, right, bottom, top, near, far), not normalised.
CaseFrustum cube_frustum() {
  Frustum f;
  f[kLeft] = {{2, 0, 0}, 2};
  f[kRight] = {{-2, 0, 0}, 2};
  f[kBottom] = {{0, 1, 0}, 1};
  f[kTop] = {{0, -1, 0}, 1};
  f[kNear] = {{0, 0, 1}, 1};
  f[kFar] = {{0, 0, -1}, 1};
  return frustum_spec(f);
}

CorpusEntry entry(const Volume& v, ErrorClass e, Visibility verdict, Visibility truth) {
  CorpusEntry x;
  x.c.id = "drawn";
  x.c.frustum = cube_frustum();
  x.c.volume = v;
  x.c.truth = truth;
  x.method = "some-method";
  x.error = e;
  x.verdict = verdict;
  x.distribution = "uniform";
  x.c.extra = {{"distance", 0.25}, {"witness", {{"kind", "separating_plane"}, {"plane_approx", {1, 0, 0, -1}}}}};
  return x;
}

}  // namespace

TEST(CaseView, TruthPlanesOfAMatrixAreTheRowSums) {
  const glm::mat4 m = off_axis_projection(-1.0f, 1.0f, -0.5f, 0.5f, 1.0f, 10.0f);
  const auto p = report::truth_planes(frustum_spec(m, DepthConvention{}));
  const Frustum f = frustum_from_matrix(m);  // every row sum here is exact in float too
  for (int j = 0; j < 6; ++j) {
    EXPECT_EQ(p[std::size_t(j)][0], double(f[j].n.x)) << j;
    EXPECT_EQ(p[std::size_t(j)][3], double(f[j].d)) << j;
  }
}

TEST(CaseView, TheFaultPlaneIsTheOneNearestToMakingTheVerdictRight) {
  const auto planes = report::truth_planes(cube_frustum());
  // A box beyond the right plane (x from 1.25): kept although outside (a false intersect); the
  // right plane is the one it is furthest outside of.
  const Aabb beyond{{1.25f, -0.5f, -0.5f}, {1.5f, 0.5f, 0.5f}};
  EXPECT_EQ(report::fault_plane(planes, beyond, ErrorClass::false_intersect, {}), kRight);
  const auto r = report::plane_ranges(planes, beyond);
  EXPECT_DOUBLE_EQ(r[kRight][1], -0.25);  // normalised: the plane's normal has length 2
  // A box through the top face, called inside: the top plane is the one it crosses.
  const Aabb through{{-0.5f, 0.5f, -0.5f}, {0.5f, 1.5f, 0.5f}};
  EXPECT_EQ(report::fault_plane(planes, through, ErrorClass::false_inside, {}), kTop);
  EXPECT_EQ(report::fault_plane(planes, through, ErrorClass::correct, {}), -1);
  // A sphere touching the near plane (z = -1) from inside, called intersecting.
  EXPECT_EQ(report::fault_plane(planes, Sphere{{0, 0, -0.75f}, 0.25f}, ErrorClass::under_inside, {}), kNear);
}

TEST(CaseView, TheViewFocusesOnTheErrorAndTheDrawingHasThreePanels) {
  const CorpusEntry e = entry(Aabb{{1.25f, -0.5f, -0.5f}, {1.5f, 0.5f, 0.5f}}, ErrorClass::false_intersect, Visibility::intersecting,
                              Visibility::outside);
  const json v = report::case_view_json(e);
  EXPECT_EQ(v.at("fault_plane"), kRight);
  EXPECT_EQ(v.at("focus").at(0), 1.25);  // the box's face nearest the frustum
  EXPECT_EQ(v.at("error_width"), 0.25);   // its distance
  EXPECT_EQ(v.at("witness").at("kind"), "separating_plane");
  EXPECT_EQ(v.at("scene").at("frustum_corners"), 8);
  for (const bool zoom : {false, true}) {
    const std::string svg = report::case_svg(v, zoom);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u);
    for (const char* name : {">front<", ">top<", ">side<"}) EXPECT_NE(svg.find(name), std::string::npos) << name;
    EXPECT_EQ(svg.find("nan"), std::string::npos);
    EXPECT_EQ(svg.find("inf"), std::string::npos);
    EXPECT_NE(svg.find("#b2182b"), std::string::npos);  // the volume's edges are drawn
  }
  EXPECT_NE(report::case_svg(v, true).find("magnified"), std::string::npos);
}

TEST(CaseView, AnInfiniteFarPlaneLeavesTheFrustumOpen) {
  CorpusEntry e = entry(Point{0, 0, 5}, ErrorClass::under_inside, Visibility::intersecting, Visibility::inside);
  Frustum f = e.c.frustum.planes;
  f[kFar] = {{0, 0, 0}, 1};  // all space
  e.c.frustum = frustum_spec(f);
  const json v = report::case_view_json(e);
  EXPECT_EQ(v.at("scene").at("frustum_corners"), 4);  // the near ones
  EXPECT_NE(report::case_svg(v, false).find("dashed edges: it goes on beyond the drawing"), std::string::npos);
}

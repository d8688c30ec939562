// The report's charts as Vega-Lite specifications (see cullproof/report/report.hpp). Each chart carries
// its data inline; the page only hands the specification to vega-embed.
#include "cullproof/report/report.hpp"
#include "cullproof/report/summary.hpp"

#include "cullproof/campaign/campaign.hpp"

#include "show.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace cullproof::report {

namespace {

using nlohmann::json;

const char* kSchema = "https://vega.github.io/schema/vega-lite/v6.json";  // an identifier: never fetched

// Claims from the strongest promise to none, and their colours (ColorBrewer, colour-blind safe).
const std::vector<std::string> kClaims = {"certified-exact", "certified-conservative", "exact", "conservative", "none"};
const std::vector<std::string> kClaimColours = {"#00441b", "#41ab5d", "#08519c", "#6baed6", "#969696"};

// One point of an accuracy-cost chart.
struct CostRow {
  std::string method, claim, origin, volumes;
  bool refuted = false;
  bool faulted = false;  // its counts stop at a fault
  std::optional<double> ns, ns_own;
  double rate = 0, lo = 0, hi = 0;
  std::uint64_t outside = 0, cases = 0, fr = 0, fi = 0, fint = 0, ui = 0, violations = 0;
};

std::vector<CostRow> cost_rows(const json& verify, const std::string& family, const Summary& s) {
  std::vector<CostRow> rows;
  if (family.empty()) {
    for (const MethodOverall& m : s.methods) {
      CostRow r;
      r.method = m.method;
      r.claim = m.claim;
      r.origin = m.origin;
      r.volumes = show::join(m.volumes, " + ");
      r.refuted = m.refuted;
      r.faulted = m.faulted;
      r.ns = m.ns_per_test;
      r.ns_own = m.ns_per_test_own;
      r.rate = m.fi_rate;
      r.lo = m.fi_low;
      r.hi = m.fi_high;
      r.outside = m.truth_outside;
      r.cases = m.cases;
      r.fr = m.false_reject;
      r.fi = m.false_inside;
      r.fint = m.false_intersect;
      r.ui = m.under_inside;
      r.violations = m.claim_violations;
      rows.push_back(r);
    }
    return rows;
  }
  for (const json& d : verify.at("distributions")) {
    if (d.at("distribution") != family || !d.contains("methods")) continue;
    for (const json& j : d.at("methods")) {
      CostRow r;
      r.method = j.at("method");
      r.claim = j.at("claim");
      r.origin = j.at("origin");
      r.volumes = show::join(j.at("volumes").get<std::vector<std::string>>(), " + ");
      r.refuted = j.at("claim_violations").get<std::uint64_t>() > 0;
      r.faulted = !j.at("fault").is_null();
      if (j.at("ns_per_test").is_number()) r.ns = j.at("ns_per_test").get<double>();
      if (j.at("ns_per_test_own").is_number()) r.ns_own = j.at("ns_per_test_own").get<double>();
      r.outside = j.at("truth").at("outside");
      r.cases = j.at("cases");
      r.fr = j.at("false_reject");
      r.fi = j.at("false_inside");
      r.fint = j.at("false_intersect");
      r.ui = j.at("under_inside");
      r.violations = j.at("claim_violations");
      r.rate = r.outside ? double(r.fint) / double(r.outside) : 0.0;
      std::tie(r.lo, r.hi) = wilson95(r.fint, r.outside);
      if (r.cases) rows.push_back(r);
    }
  }
  return rows;
}

json tooltip_field(const char* field, const char* title, const char* type = "nominal") {
  return {{"field", field}, {"title", title}, {"type", type}};
}

}  // namespace

json accuracy_cost_spec(const json& verify, const std::string& family) {
  const Summary s = summarize(verify);
  const std::vector<CostRow> rows = cost_rows(verify, family, s);

  // The lowest rate shown: below every measured rate and interval, so that a rate of 0 (none
  // found: no point on a log axis) sits on a floor of its own, marked as such.
  double smallest = 1.0;
  std::uint64_t most_outside = 1, most_outside_seen = 0;
  for (const CostRow& r : rows) {
    if (!r.ns) continue;
    most_outside = std::max(most_outside, r.outside);
    most_outside_seen = std::max(most_outside_seen, r.outside);
    // (An interval's lower end for no false intersect is 0 up to rounding: only found ones count.)
    if (r.fint > 0) smallest = std::min({smallest, r.lo, r.rate});
  }
  smallest = std::min(smallest, 0.5 / double(most_outside));
  const double floor = std::pow(10.0, std::floor(std::log10(smallest)));

  // The Pareto front of each set of volume kinds, among methods that make a claim and held it.
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CostRow& r = rows[i];
    MethodOverall m;
    m.claim = r.claim;
    m.refuted = r.refuted;
    m.ns_per_test = r.ns;
    m.truth_outside = r.outside;
    if (on_front(m)) groups[r.volumes].push_back(i);
  }
  std::vector<bool> front(rows.size(), false);
  for (const auto& [kinds, members] : groups) {
    std::vector<CostPoint> pts;
    for (const std::size_t i : members) pts.push_back({*rows[i].ns, rows[i].rate});
    for (const std::size_t k : pareto_front(pts)) front[members[k]] = true;
  }

  json values = json::array();
  std::vector<std::string> untimed;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CostRow& r = rows[i];
    if (!r.ns) {
      untimed.push_back(r.method);
      continue;
    }
    const std::string status = r.claim == "none" ? "no claim" : r.refuted ? "REFUTED" : "held";
    values.push_back({
        {"method", r.method},
        {"claim", r.claim},
        {"status", status},
        {"claim_text", (r.claim == "none" ? std::string("none")
                        : r.claim + (r.refuted   ? fmt::format(" REFUTED ({} cases)", r.violations)
                                     : r.faulted ? std::string(" not refuted before the fault")
                                                 : std::string(" held"))) +
                           (r.faulted ? "; FAULT: the counts stop at it" : "")},
        {"origin", r.origin},
        {"volumes", r.volumes},
        {"ns", *r.ns},
        {"ns_own", r.ns_own ? json(*r.ns_own) : json(nullptr)},
        {"rate", r.rate},
        {"y", std::max(r.rate, floor)},
        {"y_lo", std::max(r.lo, floor)},
        {"y_hi", std::max(r.hi, floor)},
        {"rate_text", r.outside ? fmt::format("{} (95% {} to {}): {} of {}", show::percent(r.rate), show::percent(r.lo), show::percent(r.hi), r.fint, r.outside)
                                : std::string("no truly outside volume")},
        {"false_reject", r.fr},
        {"false_inside", r.fi},
        {"under_inside", r.ui},
        {"cases", r.cases},
        {"front", front[i]},
        {"refuted", r.refuted},
        {"label", r.refuted ? r.method + " REFUTED" : r.method},
    });
  }

  // The overall chart carries the legends and names the methods on a front; the per-family ones,
  // drawn small, name only refuted methods.
  const bool overall = family.empty();
  const std::string x_title = overall ? "ns per test, set-up hoisted (median over families; log)"
                                             : "ns per test, set-up hoisted (log)";
  const json x = {{"field", "ns"}, {"type", "quantitative"}, {"title", x_title},
                  {"scale", {{"type", "log"}, {"nice", true}}}, {"axis", {{"grid", true}}}};
  json decades = json::array();
  for (double t = floor; t <= 1.0000001; t *= 10) decades.push_back(t);
  const json y = {{"field", "y"}, {"type", "quantitative"},
                  {"title", "false intersects / truly outside volumes (log; 95% interval)"},
                  {"scale", {{"type", "log"}, {"domainMin", floor}, {"nice", true}}},
                  // Ticks at the powers of ten; the floor reads 0: rates of 0 sit on it.
                  {"axis", {{"values", decades}, {"labelExpr", fmt::format("datum.value <= {:.17g} ? '0' : format(datum.value, '~%')", floor * 1.000001)}}}};
  json colour = {{"field", "claim"}, {"type", "nominal"}, {"title", "claim"},
                 {"scale", {{"domain", kClaims}, {"range", kClaimColours}}}};
  if (!overall) colour["legend"] = nullptr;
  const json tooltip = json::array({tooltip_field("method", "method"), tooltip_field("claim_text", "claim"),
                                    tooltip_field("origin", "origin"), tooltip_field("volumes", "volumes"),
                                    {{"field", "ns"}, {"title", "ns/test"}, {"type", "quantitative"}, {"format", ".3~r"}},
                                    {{"field", "ns_own"}, {"title", "own ns/test (reported)"}, {"type", "quantitative"}, {"format", ".3~r"}},
                                    tooltip_field("rate_text", "false intersects"),
                                    tooltip_field("false_reject", "false rejects", "quantitative"),
                                    tooltip_field("false_inside", "false insides", "quantitative"),
                                    tooltip_field("under_inside", "under-insides", "quantitative"),
                                    tooltip_field("cases", "cases", "quantitative")});

  json layers = json::array();
  // The 95% intervals.
  layers.push_back({{"mark", {{"type", "rule"}, {"strokeWidth", 1.5}, {"opacity", 0.55}}},
                    {"encoding", {{"x", x}, {"y", {{"field", "y_lo"}, {"type", "quantitative"}}}, {"y2", {{"field", "y_hi"}}}, {"color", colour}}}});
  // The Pareto fronts: at each cost, the lowest rate a method whose claim held reaches for it.
  // (A layer is drawn only when it has data: an empty one leaves its scales without extent.)
  bool any_front = false, any_refuted = false, any_front_unrefuted = false;
  for (const json& v : values) {
    any_front = any_front || v.at("front").get<bool>();
    any_refuted = any_refuted || v.at("refuted").get<bool>();
    any_front_unrefuted = any_front_unrefuted || (v.at("front").get<bool>() && !v.at("refuted").get<bool>());
  }
  json dash = {{"field", "volumes"}, {"type", "nominal"}, {"title", "Pareto front (volume kinds)"}};
  if (!overall) dash["legend"] = nullptr;
  if (any_front)
    layers.push_back({{"transform", json::array({{{"filter", "datum.front"}}})},
                      {"mark", {{"type", "line"}, {"interpolate", "step-after"}, {"color", "#444"}, {"strokeWidth", 1.2}}},
                      {"encoding", {{"x", x}, {"y", y}, {"strokeDash", dash}, {"order", {{"field", "ns"}, {"type", "quantitative"}}}}}});
  json shape = {{"field", "status"}, {"type", "nominal"}, {"title", "claim in this run"},
               {"scale", {{"domain", {"held", "REFUTED", "no claim"}}, {"range", {"circle", "cross", "diamond"}}}}};
  if (!overall) shape["legend"] = nullptr;
  // One point per method.
  layers.push_back({{"name", "methods"},
                    {"mark", {{"type", "point"}, {"filled", true}, {"size", 80}, {"opacity", 0.95}, {"strokeWidth", 2.5}}},
                    {"encoding", {{"x", x}, {"y", y}, {"color", colour},
                                  {"shape", shape},
                                  {"tooltip", tooltip},
                                  {"description", {{"field", "method"}}}}}});
  // Names of the methods on a front, and of every refuted one.
  const json label_colour = {{"condition", {{"test", "datum.refuted"}, {"value", "#b2182b"}}}, {"value", "#222"}};
  // Names above the points on a front, below the refuted ones (apart where both are near).
  if (any_front_unrefuted && overall)
    layers.push_back({{"transform", json::array({{{"filter", "datum.front && !datum.refuted"}}})},
                      {"mark", {{"type", "text"}, {"align", "left"}, {"dx", 7}, {"dy", -7}, {"fontSize", 10}}},
                      {"encoding", {{"x", x}, {"y", y}, {"text", {{"field", "label"}}}, {"color", label_colour}}}});
  if (any_refuted)
    layers.push_back({{"transform", json::array({{{"filter", "datum.refuted"}}})},
                      {"mark", {{"type", "text"}, {"align", "left"}, {"dx", 7}, {"dy", 11}, {"fontSize", 10}, {"fontWeight", "bold"}}},
                      {"encoding", {{"x", x}, {"y", y}, {"text", {{"field", "label"}}}, {"color", label_colour}}}});
  // The floor where rates of 0 sit.
  layers.push_back({{"data", {{"values", json::array({{{"y", floor}, {"text", "0: none found"}}})}}},
                    {"mark", {{"type", "rule"}, {"strokeDash", {2, 2}}, {"color", "#999"}}},
                    {"encoding", {{"y", {{"field", "y"}, {"type", "quantitative"}}}}}});

  const std::string title = family.empty() ? "All families" : family;
  std::string subtitle = family.empty() ? fmt::format("{} methods over {} families; points on the dashed floor found no false intersect",
                                                      values.size(), s.families.size())
                                        : fmt::format("{} methods", values.size());
  if (most_outside_seen == 0) subtitle += "; no truly outside volume here: no rate to show";
  if (!untimed.empty()) subtitle += "; not timed: " + show::join(untimed, ", ");
  return {{"$schema", kSchema},
          {"title", {{"text", title}, {"subtitle", subtitle}, {"anchor", "start"}}},
          {"width", overall ? 720 : 270},
          {"height", overall ? 440 : 210},
          {"data", {{"values", values}}},
          {"layer", layers},
          {"usermeta", {{"family", family.empty() ? "all" : family}, {"methods", values.size()}, {"floor", floor}}}};
}

json claims_heatmap_spec(const json& verify) {
  const Summary s = summarize(verify);
  std::vector<std::string> methods;
  for (const MethodOverall& m : s.methods) methods.push_back(m.method);
  json values = json::array();
  for (const json& d : verify.at("distributions")) {
    if (!d.contains("methods")) continue;
    const std::string family = d.at("distribution");
    for (const json& j : d.at("methods")) {
      if (j.at("cases").get<std::uint64_t>() == 0) continue;  // the method does not apply here
      const std::string method = j.at("method");
      const std::uint64_t fr = j.at("false_reject"), fi = j.at("false_inside"), v = j.at("claim_violations");
      values.push_back({{"method", method},
                        {"family", family},
                        {"claim", j.at("claim")},
                        {"false_reject", fr},
                        {"false_inside", fi},
                        {"violations", v},
                        {"cases", j.at("cases")},
                        {"broke", v ? fmt::format("claim {} broke on {} cases here", j.at("claim").get<std::string>(), v)
                                    : std::string("claim held here")},
                        {"fr_text", fmt::format("{}, {}: {} false rejects", method, family, fr)},
                        {"fi_text", fmt::format("{}, {}: {} false insides", method, family, fi)}});
    }
  }
  auto panel = [&](const char* key, const char* name, const char* text, const char* scheme) {
    // Counts on the darker half of the colour scale (symlog: about a third of the largest) in white.
    std::uint64_t largest = 0;
    for (const json& v : values) largest = std::max(largest, v.at(key).get<std::uint64_t>());
    const double dark = std::max(1.0, std::pow(double(largest), 0.6));
    const json x = {{"field", "family"}, {"type", "ordinal"}, {"sort", s.families}, {"title", nullptr},
                    {"axis", {{"labelAngle", -40}, {"orient", "top"}}}};
    const json y = {{"field", "method"}, {"type", "ordinal"}, {"sort", methods}, {"title", nullptr}};
    const json tooltip = json::array({tooltip_field("method", "method"), tooltip_field("family", "family"),
                                      tooltip_field(key, fmt::format("{}", name).c_str(), "quantitative"),
                                      tooltip_field("cases", "cases", "quantitative"), tooltip_field("broke", "claim")});
    const std::string test_broke = fmt::format("datum.violations > 0 && datum['{}'] > 0", key);
    return json{
        {"title", {{"text", name}, {"anchor", "start"}}},
        {"width", {{"step", 46}}},
        {"height", {{"step", 17}}},
        {"encoding", {{"x", x}, {"y", y}}},
        {"layer",
         json::array(
             {{{"name", fmt::format("cells_{}", key)},
               {"mark", {{"type", "rect"}, {"strokeWidth", 2.5}}},
               {"encoding",
                {{"color", {{"condition", {{"test", fmt::format("datum['{}'] == 0", key)}, {"value", "#f4f4f4"}}},
                            {"field", key}, {"type", "quantitative"}, {"title", name},
                            {"scale", {{"type", "symlog"}, {"scheme", scheme}}}, {"legend", nullptr}}},
                 {"stroke", {{"condition", {{"test", test_broke}, {"value", "#000"}}}, {"value", nullptr}}},
                 {"tooltip", tooltip},
                 {"description", {{"field", text}}}}}},
              {{"mark", {{"type", "text"}, {"fontSize", 9}}},
               {"encoding",
                {{"text", {{"field", key}, {"type", "quantitative"}}},
                 {"color", {{"condition", json::array({{{"test", fmt::format("datum['{}'] == 0", key)}, {"value", "#bbb"}},
                                                       {{"test", fmt::format("datum['{}'] >= {:.17g}", key, dark)}, {"value", "#fff"}}})},
                            {"value", "#000"}}}}}}})}};
  };
  return {{"$schema", kSchema},
          {"data", {{"values", values}}},
          {"hconcat", json::array({panel("false_reject", "false rejects", "fr_text", "orangered"),
                                   panel("false_inside", "false insides", "fi_text", "purples")})},
          {"resolve", {{"scale", {{"color", "independent"}}}}},
          {"usermeta", {{"cells", values.size()}}}};
}

json distance_spec(const json& verify) {
  const Summary s = summarize(verify);
  std::vector<std::string> methods;
  for (const MethodOverall& m : s.methods) methods.push_back(m.method);
  // Decade labels, lowest first: below the first decade, each decade, the last and above.
  const int first = kFiHistogramFirstDecade, last = kFiHistogramLastDecade;
  std::vector<std::string> bins;
  bins.push_back(fmt::format("< 1e{}", first));
  for (int k = first; k < last; ++k) bins.push_back(fmt::format("1e{}", k));
  bins.push_back(fmt::format(">= 1e{}", last));
  auto range_text = [&](std::size_t b) {
    if (b == 0) return fmt::format("below 1e{}", first);
    if (b == bins.size() - 1) return fmt::format("1e{} or more", last);
    const int k = first + int(b) - 1;
    return fmt::format("[1e{}, 1e{})", k, k + 1);
  };
  // counts[family][method][bin], "all families" pooled.
  const std::string all = "all families";
  std::map<std::string, std::map<std::string, std::vector<std::uint64_t>>> counts;
  for (std::size_t family_index = 0; family_index < verify.at("distributions").size(); ++family_index) {
    const json& d = verify.at("distributions")[family_index];
    if (!d.contains("methods")) continue;
    const std::string family = d.at("distribution");
    for (std::size_t mi = 0; mi < d.at("methods").size(); ++mi) {
      const json& j = d.at("methods")[mi];
      const std::string w = fmt::format("result.distributions[{}].methods[{}].fi_distance_histogram", family_index, mi);
      const json& h = field(j, "fi_distance_histogram", w.substr(0, w.rfind('.')));
      const json& hc = field(h, "counts", w);
      auto count = [&](const json& x, const std::string& where) {
        if (!x.is_number_unsigned() && !(x.is_number_integer() && x.get<std::int64_t>() >= 0))
          throw ResultError(where + ": expected a count (a non-negative integer)");
        return x.get<std::uint64_t>();
      };
      if (field(h, "first_decade", w) != first || !hc.is_array() || hc.size() != std::size_t(last - first))
        throw ResultError(fmt::format("{}: other decades than this program's (first 1e{}, {} counts)", w, first, last - first));
      std::vector<std::uint64_t> c;
      c.push_back(count(field(h, "below", w), w + ".below"));
      for (std::size_t b = 0; b < hc.size(); ++b) c.push_back(count(hc[b], fmt::format("{}.counts[{}]", w, b)));
      c.push_back(count(field(h, "above", w), w + ".above"));
      const std::string method = j.at("method");
      counts[family][method] = c;
      auto& pooled = counts[all][method];
      pooled.resize(c.size(), 0);
      for (std::size_t b = 0; b < c.size(); ++b) pooled[b] += c[b];
    }
  }
  json values = json::array();
  for (const auto& [family, per_method] : counts)
    for (const auto& [method, c] : per_method) {
      std::uint64_t total = 0;
      for (const auto x : c) total += x;
      for (std::size_t b = 0; b < c.size(); ++b) {
        if (!c[b]) continue;
        values.push_back({{"family", family}, {"method", method}, {"bin", bins[b]}, {"range", range_text(b)},
                          {"count", c[b]}, {"share", double(c[b]) / double(total)}, {"total", total}});
      }
    }
  std::vector<std::string> options = {all};
  for (const auto& f : s.families) options.push_back(f);
  const json tooltip = json::array({tooltip_field("method", "method"), tooltip_field("family", "family"),
                                    tooltip_field("range", "distance / scene size"),
                                    tooltip_field("count", "false intersects", "quantitative"),
                                    {{"field", "share"}, {"title", "share of the method's"}, {"type", "quantitative"}, {"format", ".1%"}},
                                    tooltip_field("total", "false intersects in all", "quantitative")});
  return {{"$schema", kSchema},
          {"params", json::array({{{"name", "family"}, {"value", all},
                                   {"bind", {{"input", "select"}, {"options", options}, {"name", "family "}}}}})},
          {"data", {{"values", values}}},
          {"transform", json::array({{{"filter", "datum.family == family"}}})},
          {"width", {{"step", 30}}},
          {"height", {{"step", 17}}},
          {"name", "distance_cells"},
          {"mark", {{"type", "rect"}}},
          {"encoding",
           {{"x", {{"field", "bin"}, {"type", "ordinal"}, {"sort", bins}, {"scale", {{"domain", bins}}},
                   {"title", "distance of a false intersect from the frustum / scene size (decades)"},
                   {"axis", {{"labelAngle", -40}}}}},
            {"y", {{"field", "method"}, {"type", "ordinal"}, {"sort", methods}, {"scale", {{"domain", methods}}}, {"title", nullptr}}},
            {"color", {{"field", "share"}, {"type", "quantitative"}, {"title", "share of its false intersects"},
                       {"scale", {{"scheme", "blues"}, {"domain", {0, 1}}}}, {"legend", {{"format", "%"}, {"titleLimit", 260}}}}},
            {"tooltip", tooltip}}}};
}

}  // namespace cullproof::report

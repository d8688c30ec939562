// The report page (see cullproof/report/report.hpp): the summary as HTML, the charts' specifications and
// the corpus as JSON, and the bundled scripts, all in one file.
#include "cullproof/report/report.hpp"
#include "cullproof/report/summary.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/limits.hpp"

#include "cullproof/campaign/campaign.hpp"

#include "show.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <system_error>

#ifndef CULLPROOF_WEB_BUILD_DIR
#define CULLPROOF_WEB_BUILD_DIR ""
#endif

namespace cullproof::report {

namespace {

using nlohmann::json;

/// The bundles are a few MiB; anything past this is not ours.
constexpr std::uintmax_t kMaxScriptBytes = std::uintmax_t(64) << 20;

const char* kStyle = R"css(
body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; color: #1a1a1a; margin: 0 auto; max-width: 1280px; padding: 0 24px 48px; }
h1 { font-size: 26px; margin: 24px 0 2px; } h2 { font-size: 20px; margin: 36px 0 6px; border-bottom: 1px solid #ddd; padding-bottom: 4px; }
h3 { font-size: 15px; margin: 18px 0 6px; }
.made-by { color: #555; margin: 0 0 12px; } code { font: 12.5px ui-monospace, SFMono-Regular, Menlo, monospace; background: #f4f4f4; padding: 1px 4px; border-radius: 3px; }
p.lead { max-width: 900px; color: #333; }
table { border-collapse: collapse; margin: 6px 0 12px; } th, td { text-align: left; padding: 3px 10px 3px 0; vertical-align: top; border-bottom: 1px solid #eee; }
th { font-weight: 600; color: #444; } td.num { text-align: right; font-variant-numeric: tabular-nums; }
.refuted { color: #b2182b; font-weight: 600; } .held { color: #1b7837; font-weight: 600; }
.grid { display: flex; flex-wrap: wrap; gap: 12px 24px; } .grid > .chart { flex: 0 0 auto; }
.chart { min-height: 60px; } .chart-error { color: #b2182b; white-space: pre-wrap; }
a.case-link { font: 12px ui-monospace, monospace; margin-right: 6px; white-space: nowrap; }
#broken-claims td:nth-child(6) { max-width: 520px; }
)css";

// A duration in seconds (cull_seconds, judge_seconds of `cullproof systems --json`).
double seconds_field(const json& obj, const char* key, const std::string& where) {
  const std::optional<double> v = measure_field(obj, key, where);
  if (!v || *v < 0) throw ResultError(where + "." + key + ": expected a duration (seconds, not negative)");
  return *v;
}

// The culling systems' section: per system, per family, what `cullproof systems` printed.
std::string systems_html(const json& js, const std::string& from, std::set<std::string>& shown_cases) {
  const json& systems = field(js, "systems", "systems");
  if (!systems.is_array()) throw ResultError("systems.systems: expected an array");
  std::string h = fmt::format(
      "<section id=\"systems\"><h2>Culling systems</h2>\n<p class=\"lead\">From <code>{}</code> (seed {}): each "
      "system built over the scenes of each family, told which objects moved, culled frame by frame, and every object of "
      "every frame judged exactly. Broken: object-frames that break the system's claim; the false-intersect rate is of "
      "the object-frames truly outside, with its 95% Wilson interval; nanoseconds per object-frame culling (build, "
      "updates, culls) and judging.</p>\n",
      html_escape(from), count_field(js, "seed", "systems"));
  for (std::size_t i = 0; i < systems.size(); ++i) {
    const json& sys = systems[i];
    const std::string where = fmt::format("systems.systems[{}]", i);
    const std::string name = text_field(sys, "system", where);
    const std::uint64_t broken = count_field(sys, "claim_broken", where);
    h += fmt::format("<h3>{} <span class=\"{}\">{}</span></h3>\n<p>{}, claim {}.</p>\n", html_escape(name),
                     broken ? "refuted" : "held", broken ? "claim broken" : "claim held", html_escape(text_field(sys, "origin", where)),
                     html_escape(text_field(sys, "claim", where)));
    h += "<table class=\"systems-table\" data-system=\"" + html_escape(name) +
         "\">\n<tr><th>family</th><th>runs</th><th>object-frames</th><th>broken</th><th>false rejects</th><th>false "
         "insides</th><th>false-intersect %</th><th>cull ns</th><th>judge ns</th></tr>\n";
    const json& fams = field(sys, "families", where);
    if (!fams.is_array()) throw ResultError(where + ".families: expected an array");
    for (std::size_t k = 0; k < fams.size(); ++k) {
      const json& f = fams[k];
      const std::string w = fmt::format("{}.families[{}]", where, k);
      const std::uint64_t judged = count_field(f, "object_frames", w), outside = count_field(f, "truth_outside", w),
                          fi = count_field(f, "false_intersect", w), b = count_field(f, "claim_broken", w);
      const std::string rate = percent_ci95(fi, outside);
      const auto per = [&](double sec) { return judged ? fmt::format("{:.0f}", sec * 1e9 / double(judged)) : std::string("-"); };
      h += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num{}\">{}</td>"
                       "<td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>"
                       "<td class=\"num\">{}</td></tr>\n",
                       html_escape(text_field(f, "family", w)), count_field(f, "runs", w), judged, b ? " refuted" : "", b,
                       count_field(f, "false_reject", w), count_field(f, "false_inside", w), rate, per(seconds_field(f, "cull_seconds", w)),
                       per(seconds_field(f, "judge_seconds", w)));
    }
    h += "</table>\n";
    if (sys.contains("record")) {
      const std::string record = text_field(sys, "record", where);
      const std::string id = std::filesystem::path(record).stem().string();
      h += fmt::format("<p>The record of its first failing run: <code>{}</code>{}.</p>\n", html_escape(record),
                       shown_cases.count(id) ? fmt::format(" (<a class=\"case-link\" href=\"#case={}\">in 3D below</a>)", html_escape(id)) : "");
    }
  }
  return h + "</section>\n";
}

std::string summary_html(const Summary& s, const std::set<std::string>& shown_cases) {
  std::string h;
  h += "<section id=\"summary\"><h2>Summary</h2>\n";
  if (s.broken.empty() && !s.faults.empty()) {
    h += fmt::format("<p id=\"claims-verdict\">No claim was refuted ({} methods), the faulted methods' only up to their "
                     "faults.</p>\n",
                     s.methods.size());
  } else if (s.broken.empty()) {
    h += fmt::format("<p class=\"held\" id=\"claims-verdict\">Every claim held ({} methods).</p>\n", s.methods.size());
  } else {
    h += fmt::format("<p id=\"claims-verdict\"><span class=\"refuted\">{} of {} methods' claims were refuted.</span>{}</p>\n",
                     s.broken.size(), s.methods.size(),
                     s.own_claim_broken() ? " A claim of one of cullproof's own methods or of a user's method broke: the run failed."
                                    : " All of them are published methods under test: findings, not failures.");
    h += "<table id=\"broken-claims\"><tr><th>method</th><th>origin</th><th>claim</th><th>family</th>"
         "<th>claim-breaking cases</th><th>corpus cases</th><th>rerun the first</th></tr>\n";
    for (const BrokenClaim& b : s.broken)
      for (const FamilyBreak& f : b.families) {
        std::string ids;
        for (const std::string& id : f.corpus_ids)
          ids += shown_cases.count(id) ? fmt::format("<a class=\"case-link\" href=\"#case={0}\">{0}</a> ", html_escape(id))
                                       : fmt::format("<code>{}</code> ", html_escape(id));
        if (ids.empty()) ids = "none recorded";
        h += fmt::format(
            "<tr><td><b>{}</b></td><td>{}</td><td class=\"refuted\">{} REFUTED</td><td>{}</td><td class=\"num\">{}{}</td>"
            "<td>{}</td><td><code>{}</code></td></tr>\n",
            html_escape(b.method), html_escape(b.origin), html_escape(b.claim), html_escape(f.family), f.violations,
            f.float_exact_violations ? fmt::format(" ({} float-exact)", f.float_exact_violations) : "", ids,
            html_escape(f.reproduce));
      }
    h += "</table>\n";
  }
  if (!s.faults.empty()) {
    h += fmt::format("<p id=\"faults-verdict\"><span class=\"refuted\">{} fault{}:</span> a faulted method was not asked again "
                     "in that family, and its counts there stop at the fault; the run failed.</p>\n",
                     s.faults.size(), s.faults.size() == 1 ? "" : "s");
    h += "<table id=\"faults\"><tr><th>method</th><th>family</th><th>case</th><th>problem</th><th>reproduce</th></tr>\n";
    for (const FaultLine& f : s.faults)
      h += fmt::format("<tr><td><b>{}</b></td><td>{}</td><td class=\"num\">{}</td><td class=\"refuted\">FAULT: {}</td>"
                       "<td><code>{}</code></td></tr>\n",
                       html_escape(f.method), html_escape(f.family), f.index ? std::to_string(*f.index) : "while timed",
                       html_escape(f.problem), html_escape(f.reproduce));
    h += "</table>\n";
  }
  if (s.interrupted)
    h += "<p id=\"interrupted\" class=\"refuted\">The run was interrupted: its counts are over the cases judged before it "
         "was stopped.</p>\n";
  h += "<h3>The cheapest method for each level of accuracy</h3>\n"
       "<p class=\"lead\">Among methods that make a claim and held it, compared with those that take the same volume "
       "kinds (so over the same cases): each row is the cheapest method whose false-intersect rate is at most its "
       "own (the Pareto front of the chart below). False intersects are pooled over every family; the cost is the "
       "median ns/test over families, with the per-frame set-up hoisted out.</p>\n";
  h += "<table id=\"cheapest\"><tr><th>volume kinds</th><th>ns/test</th><th>false intersects (95% interval)</th>"
       "<th>method</th><th>claim</th></tr>\n";
  for (const VolumeGroup& g : s.cheapest) {
    const std::string kinds = show::join(g.volumes, " + ");
    if (g.front.empty()) {
      h += fmt::format("<tr><td>{}</td><td colspan=\"4\">no method that held its claim was timed on truly outside volumes</td></tr>\n",
                       html_escape(kinds));
      continue;
    }
    for (std::size_t i = 0; i < g.front.size(); ++i) {
      const FrontStep& f = g.front[i];
      h += fmt::format("<tr><td>{}</td><td class=\"num\">{}</td><td class=\"num\">{} ({} to {})</td><td><b>{}</b></td><td>{}</td></tr>\n",
                       i == 0 ? html_escape(kinds) + fmt::format(" <small>({} compared)</small>", g.methods) : "",
                       show::nanoseconds(f.ns_per_test), show::percent(f.fi_rate), show::percent(f.fi_low), show::percent(f.fi_high), html_escape(f.method),
                       html_escape(f.claim));
    }
  }
  h += "</table>\n</section>\n";
  return h;
}

}  // namespace

std::string html_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  return out;
}

std::string script_json(const json& j) {
  // "</" occurs in JSON text only inside strings, where "<\/" reads back the same.
  std::string text = j.dump(-1, ' ', false, json::error_handler_t::strict);
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] == '<' && i + 1 < text.size() && text[i + 1] == '/') out += '\\';
  }
  return out;
}

std::string script_text(std::string js) {
  // Inside a string or a regular expression "<\/script" means "</script"; the bundler writes no
  // such sequence elsewhere.
  for (std::size_t at = js.find("</script"); at != std::string::npos; at = js.find("</script", at + 2)) js.insert(at + 1, "\\");
  for (std::size_t at = js.find("</SCRIPT"); at != std::string::npos; at = js.find("</SCRIPT", at + 2)) js.insert(at + 1, "\\");
  return js;
}

std::vector<std::filesystem::path> web_asset_dirs() {
  std::vector<std::filesystem::path> dirs;
  if (const char* env = std::getenv("CULLPROOF_WEB_DIR"); env && *env) dirs.emplace_back(env);
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back((exe.parent_path() / ".." / "share" / "cullproof" / "web").lexically_normal());
  if (*CULLPROOF_WEB_BUILD_DIR) dirs.emplace_back(CULLPROOF_WEB_BUILD_DIR);
  return dirs;
}

std::string load_web_asset(const std::string& name) {
  std::string looked;
  for (const std::filesystem::path& dir : web_asset_dirs()) {
    looked += (looked.empty() ? "" : ", ") + dir.string();
    if (!std::filesystem::is_regular_file(dir / name)) continue;
    try {
      return read_file_limited(dir / name, kMaxScriptBytes, "a page script");
    } catch (const std::exception& e) {
      throw AssetError(fmt::format("the page script {} cannot be read: {}", (dir / name).string(), e.what()));
    }
  }
  throw AssetError(fmt::format(
      "the page script {} is missing: looked in {}. The page scripts are bundled from web/ at build time: run "
      "scripts/install-deps (it runs npm ci in web/), then configure and build again (target cullproof_web), or "
      "point CULLPROOF_WEB_DIR at a folder that holds them",
      name, looked.empty() ? "no folder" : looked));
}

void check_systems_result(const json& systems) {
  std::set<std::string> none;
  systems_html(systems, "", none);
}

std::string report_html(const json& verify, const PageInputs& in, const std::string& report_js) {
  const Summary s = summarize(verify);
  std::set<std::string> shown_cases;
  for (const json& c : in.corpus) shown_cases.insert(c.at("id").get<std::string>());

  json charts = json::array();
  charts.push_back({{"id", "chart-all"}, {"spec", accuracy_cost_spec(verify, "")}});
  std::string family_divs;
  for (const std::string& f : s.families) {
    const std::string id = "chart-family-" + f;
    charts.push_back({{"id", id}, {"spec", accuracy_cost_spec(verify, f)}});
    family_divs += fmt::format("<div class=\"chart\" id=\"{}\"></div>\n", html_escape(id));
  }
  charts.push_back({{"id", "heatmap"}, {"spec", claims_heatmap_spec(verify)}});
  charts.push_back({{"id", "distances"}, {"spec", distance_spec(verify)}});
  const json data = {{"charts", charts}, {"corpus", in.corpus}, {"corpus_dir", in.corpus_dir}};

  const double wall = verify.value("wall_seconds", 0.0);
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += fmt::format("<title>{}</title>\n<style>{}</style>\n</head>\n<body>\n", html_escape(in.title), kStyle);
  h += fmt::format("<h1>{}</h1>\n<p class=\"made-by\">Seed {}, {} cases per family, {} families, {} methods{}.{}</p>\n",
                   html_escape(in.title), s.seed, s.cases_per_distribution, s.families.size(), s.methods.size(),
                   wall > 0 ? fmt::format(", {:.1f} s", wall) : "",
                   in.made_by.empty() ? "" : " Made by <code>" + html_escape(in.made_by) + "</code>.");
  h += summary_html(s, shown_cases);
  h += "<section id=\"accuracy-cost\"><h2>What accuracy costs</h2>\n"
       "<p class=\"lead\">Each point is a method: across, what one test costs (ns per volume, the per-frame set-up hoisted "
       "out, as <code>cullproof verify</code> times it); up, the share of truly outside volumes it fails to cull, with its "
       "95% Wilson interval. Both axes are logarithmic. Colour is the claim; a cross marks a claim this run refuted. "
       "The dashed staircases are the Pareto fronts, one per set of volume kinds: at each cost, the lowest rate a method "
       "that made and held its claim reaches. Hover over a point for its numbers.</p>\n"
       "<div class=\"chart\" id=\"chart-all\"></div>\n<h3>Per family</h3>\n<div class=\"grid\">\n";
  h += family_divs;
  h += "</div>\n</section>\n";
  h += "<section id=\"where-claims-break\"><h2>Where claims break</h2>\n"
       "<p class=\"lead\">False rejects (visible geometry culled) and false insides (a volume reported inside that is "
       "not), per method and family. An outlined cell is one where the method's claim broke (an error its claim "
       "forbids, beyond its rounding allowance); other counts there are within the allowance. An empty cell: the "
       "method takes none of that family's volumes.</p>\n<div class=\"chart\" id=\"heatmap\"></div>\n</section>\n";
  h += "<section id=\"distances-section\"><h2>How far from the boundary the waste is</h2>\n"
       "<p class=\"lead\">Every false intersect is a truly outside volume kept; here is how far it lies from the frustum "
       "(the oracle's exact distance over the scene size), per method, by decade. Waste at 1e-7 is rounding; waste at "
       "1e-1 is a test too coarse for the geometry. Choose a family below the chart.</p>\n"
       "<div class=\"chart\" id=\"distances\"></div>\n</section>\n";
  if (!in.systems.is_null()) h += systems_html(in.systems, in.systems_from, shown_cases);
  if (!in.corpus.empty())
    h += fmt::format("<section id=\"corpus\"><h2>The corpus in 3D</h2>\n<p class=\"lead\">{} cases from <code>{}</code>.</p>\n"
                     "<div id=\"corpus-view\"></div>\n</section>\n",
                     in.corpus.size(), html_escape(in.corpus_dir));
  h += "<script type=\"application/json\" id=\"cullproof-data\">" + script_json(data) + "</script>\n";
  h += "<script>" + script_text(report_js) + "</script>\n</body>\n</html>\n";
  return h;
}

}  // namespace cullproof::report

// `cullproof report`: one self-contained HTML page that shows what a verification run found.
//
//  - the summary (cullproof/report/summary.hpp) at the top;
//  - the accuracy-cost chart, per family and over all of them: per method its cost per test
//    (ns/test with the set-up hoisted, as `cullproof verify` times it; over all families the
//    median) against its false-intersect rate with its 95% Wilson interval, both axes
//    logarithmic, coloured by claim, refuted claims marked, the Pareto front of each set of
//    volume kinds drawn;
//  - the methods x families heat maps of false rejects and false insides, cells where the claim
//    broke outlined;
//  - the false-intersect distances per method, per decade of the distance over the scene size;
//  - the corpus in 3D (cullproof/report/case_view.hpp).
//
// The charts are Vega-Lite specifications written here, drawn in the page by vega-embed; the
// scripts (vega, vega-lite, vega-embed, three.js, bundled from web/ at build time) are inlined,
// so the page opens offline.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace cullproof::report {

/// The bundled page scripts are missing or unreadable; what() names where they were looked for
/// and what to run.
class AssetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where the page scripts (bundled from web/ at build time) are looked for, in order:
/// $CULLPROOF_WEB_DIR when set; beside the program, ../share/cullproof/web (the build tree and
/// an installed tree alike); the build tree's folder.
std::vector<std::filesystem::path> web_asset_dirs();
/// The text of page script `name` ("report.js": the report page; "case.js": one corpus case in
/// 3D) from the first folder of web_asset_dirs() that holds it; throws AssetError naming the
/// folders and what to run.
std::string load_web_asset(const std::string& name);

/// Vega-Lite specification of the accuracy-cost chart of `family` ("" for all families of the run).
nlohmann::json accuracy_cost_spec(const nlohmann::json& verify, const std::string& family);
/// Vega-Lite specification of the methods x families heat maps of false rejects and false insides.
nlohmann::json claims_heatmap_spec(const nlohmann::json& verify);
/// Vega-Lite specification of the false-intersect distances per method and decade (a family chosen
/// in the chart, all of them pooled by default).
nlohmann::json distance_spec(const nlohmann::json& verify);

/// What goes into the page besides the run.
struct PageInputs {
  std::string title = "cullproof report";
  std::string made_by;  ///< the command that made the run, shown under the title
  /// The corpus cases to show in 3D (case_view_json of each), empty for none.
  nlohmann::json corpus = nlohmann::json::array();
  std::string corpus_dir;  ///< where they were read from, shown with them
  /// The results of `cullproof systems --json` (a section: a table per system), null for none;
  /// a malformed one is refused with a ResultError naming the field.
  nlohmann::json systems;
  std::string systems_from;  ///< the file they were read from
};

/// Refuses a malformed `cullproof systems --json` result with a ResultError naming the field
/// (what report_html would refuse), before a run is made or a page written.
void check_systems_result(const nlohmann::json& systems);

/// The whole page. Throws ResultError (cullproof/report/summary.hpp) for a malformed run.
/// `report_js`: load_web_asset("report.js").
std::string report_html(const nlohmann::json& verify, const PageInputs& in, const std::string& report_js);

/// `text` made safe inside an HTML element or a double-quoted attribute.
std::string html_escape(const std::string& text);
/// JSON text made safe inside a <script> element (no "</" sequence).
std::string script_json(const nlohmann::json& j);
/// A script made safe inside a <script> element: every "</script" written "<\/script".
std::string script_text(std::string js);

}  // namespace cullproof::report

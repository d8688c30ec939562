// A corpus case drawn: what the 3D view (web/src/viewer.js, three.js) and the three-view drawings
// (SVG, for documents) need to know of it.
//
// The frustum is drawn from the planes the truth is computed on: the planes as given, or for a
// matrix case the Gribb–Hartmann rows of the float matrix summed in double (CONVENTIONS
// "Matrices"). The plane that made the method err is the frustum plane nearest to making its
// verdict right:
//  - false reject, false intersect (the method kept a volume outside, or culled one that is
//    not): the plane over which the volume reaches least far inside, min_j max_{x in B} s_j(x);
//  - false inside, under-inside: the plane the volume comes nearest to crossing,
//    min_j min_{x in B} s_j(x) (for a false inside, the oracle's violated plane when it names one);
// with s_j the signed distance to the normalised plane j, in double.
#pragma once

#include "cullproof/corpus/corpus.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace cullproof::report {

/// A plane (a, b, c, d) in double: inside where a x + b y + c z + d >= 0.
using Plane4 = std::array<double, 4>;
/// The six planes the truth of `f` is computed on, in double (see above).
std::array<Plane4, 6> truth_planes(const CaseFrustum& f);

/// Over the volume, the smallest and largest signed distance to each normalised plane, in double
/// ({0, 0} for a plane with a zero normal).
std::array<std::array<double, 2>, 6> plane_ranges(const std::array<Plane4, 6>& planes, const Volume& v);

/// The index of the plane that made the method err (see above), or -1 for a correct verdict.
int fault_plane(const std::array<Plane4, 6>& planes, const Volume& v, ErrorClass e, const nlohmann::json& witness);

/// What the viewer draws of one corpus entry: ids and verdicts, the planes in double, the volume
/// (exact float values), the oracle's witness (approximate), the fault plane and its reason, the
/// error's distance, and the case as text. Numbers as JSON doubles.
nlohmann::json case_view_json(const CorpusEntry& e);

/// The page of one case in 3D (`cullproof corpus show ID --html`): `case_js` is
/// load_web_asset("case.js").
std::string case_html(const CorpusEntry& e, const std::string& case_js);

/// What the viewer draws of a culling system's failure: case_view_json(failing) with the frame's
/// other objects (`others`) and `system` (name, claim, family, index, seed, objects, frames,
/// motion, frame, camera, object).
nlohmann::json system_view_json(const CorpusEntry& failing, const std::vector<Volume>& others, const nlohmann::json& system);

/// The page of a culling system's failure in 3D (`cullproof corpus show NAME --html` for a
/// system record): `view` is system_view_json's, `case_js` load_web_asset("case.js").
std::string system_html(const std::string& title, const CorpusEntry& failing, const nlohmann::json& view,
                        const std::string& case_js);

/// The three-view drawing of a case for documents (front: looking down -z; top: looking down -y;
/// side: looking down -x), one SVG with the three side by side: the frustum's bounded part and
/// where it leaves the drawing, the volume, the witness, the fault plane highlighted. `zoom`:
/// magnified around the error as the 3D view's "zoom to the error" is (see web/src/viewer.js).
std::string case_svg(const nlohmann::json& view, bool zoom);

/// Writes case_svg(view, false) to `svg_file` and case_svg(view, true) to `zoom_svg_file`, each
/// when given, and says where on stdout.
void write_case_drawings(const nlohmann::json& view, const std::string& svg_file, const std::string& zoom_svg_file);

/// `cullproof corpus show ID --html FILE [--svg FILE] [--zoom-svg FILE]`: finds case `id` under
/// `dir` and writes the page (and the drawings). Returns 0, or 2 with a message on stderr when the
/// case is not there or the page scripts are missing.
int write_case_files(const std::filesystem::path& dir, const std::string& id, const std::string& html_file,
                     const std::string& svg_file, const std::string& zoom_svg_file);

}  // namespace cullproof::report

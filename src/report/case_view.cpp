// A corpus case drawn (see cullproof/report/case_view.hpp).
#include "cullproof/report/case_view.hpp"

#include "cullproof/core/frustum_build.hpp"
#include "cullproof/report/report.hpp"
#include "cullproof/io/files.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

namespace cullproof::report {

namespace {

using nlohmann::json;
using V3 = std::array<double, 3>;

V3 v3(const glm::vec3& v) { return {double(v.x), double(v.y), double(v.z)}; }
double dot3(const Plane4& p, const V3& x) { return p[0] * x[0] + p[1] * x[1] + p[2] * x[2]; }
double norm3(const Plane4& p) { return std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]); }

// The corners of a box volume in double, exactly from its float values (an AABB's min and max; an
// OBB's c ± h_i u_i, each product and sum in double).
std::vector<V3> corners(const Volume& v) {
  std::vector<V3> out;
  if (const auto* a = std::get_if<Aabb>(&v)) {
    for (int k = 0; k < 8; ++k)
      out.push_back({double(k & 1 ? a->max.x : a->min.x), double(k & 2 ? a->max.y : a->min.y), double(k & 4 ? a->max.z : a->min.z)});
  } else if (const auto* o = std::get_if<Obb>(&v)) {
    for (int k = 0; k < 8; ++k) {
      V3 p = v3(o->center);
      for (int i = 0; i < 3; ++i) {
        const double s = (k >> i & 1 ? 1.0 : -1.0) * double(o->half[i]);
        for (int c = 0; c < 3; ++c) p[std::size_t(c)] += s * double(o->axes[i][c]);
      }
      out.push_back(p);
    }
  } else if (const auto* p = std::get_if<Point>(&v)) {
    out.push_back(v3(*p));
  }
  return out;
}

json vec_json(const V3& v) { return json::array({v[0], v[1], v[2]}); }

json volume_json(const Volume& v) {
  if (const auto* a = std::get_if<Aabb>(&v)) return {{"kind", "aabb"}, {"min", vec_json(v3(a->min))}, {"max", vec_json(v3(a->max))}};
  if (const auto* o = std::get_if<Obb>(&v))
    return {{"kind", "obb"}, {"center", vec_json(v3(o->center))},
            {"axes", json::array({vec_json(v3(o->axes[0])), vec_json(v3(o->axes[1])), vec_json(v3(o->axes[2]))})},
            {"half", vec_json(v3(o->half))}};
  if (const auto* s = std::get_if<Sphere>(&v)) return {{"kind", "sphere"}, {"center", vec_json(v3(s->center))}, {"radius", double(s->radius)}};
  return {{"kind", "point"}, {"point", vec_json(v3(std::get<Point>(v)))}};
}

// The point where three planes meet, when they do in one point (planes_meet, its cut-off).
std::optional<V3> meet(const Plane4& a, const Plane4& b, const Plane4& c) {
  auto v4 = [](const Plane4& p) { return glm::dvec4(p[0], p[1], p[2], p[3]); };
  const std::optional<glm::dvec3> x = planes_meet(v4(a), v4(b), v4(c));
  if (!x) return std::nullopt;
  return V3{x->x, x->y, x->z};
}

// The spacing of floats at magnitude x (x > 0): what one rounding of a coordinate there moves.
double float_spacing(double x) {
  if (!(x > 0)) return std::numeric_limits<float>::denorm_min();
  int e = 0;
  std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1)
  return std::ldexp(1.0, e - 24);
}

}  // namespace

std::array<Plane4, 6> truth_planes(const CaseFrustum& f) {
  std::array<Plane4, 6> out{};
  if (!f.matrix) {
    for (int i = 0; i < 6; ++i) {
      const Plane& p = f.planes[i];
      out[std::size_t(i)] = {double(p.n.x), double(p.n.y), double(p.n.z), double(p.d)};
    }
    return out;
  }
  Plane4 r[4];
  for (int i = 0; i < 4; ++i) {
    const glm::vec4 row = matrix_row(*f.matrix, i);
    r[i] = {double(row.x), double(row.y), double(row.z), double(row.w)};
  }
  auto add = [](const Plane4& a, const Plane4& b, double s) { return Plane4{a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2], a[3] + s * b[3]}; };
  out[kLeft] = add(r[3], r[0], 1);
  out[kRight] = add(r[3], r[0], -1);
  out[kBottom] = add(r[3], r[1], 1);
  out[kTop] = add(r[3], r[1], -1);
  const Plane4 lower = f.depth.range == DepthRange::negative_one_to_one ? add(r[3], r[2], 1) : r[2];
  const Plane4 upper = add(r[3], r[2], -1);
  out[kNear] = f.depth.reversed_z ? upper : lower;
  out[kFar] = f.depth.reversed_z ? lower : upper;
  return out;
}

std::array<std::array<double, 2>, 6> plane_ranges(const std::array<Plane4, 6>& planes, const Volume& v) {
  std::array<std::array<double, 2>, 6> out{};
  const std::vector<V3> pts = corners(v);
  for (std::size_t j = 0; j < 6; ++j) {
    const double len = norm3(planes[j]);
    if (len == 0) continue;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    if (const auto* s = std::get_if<Sphere>(&v)) {
      const double c = (dot3(planes[j], v3(s->center)) + planes[j][3]) / len;
      lo = c - double(s->radius);
      hi = c + double(s->radius);
    } else {
      for (const V3& p : pts) {
        const double x = (dot3(planes[j], p) + planes[j][3]) / len;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
      }
    }
    out[j] = {lo, hi};
  }
  return out;
}

int fault_plane(const std::array<Plane4, 6>& planes, const Volume& v, ErrorClass e, const json& witness) {
  if (e == ErrorClass::correct) return -1;
  if (e == ErrorClass::false_inside && witness.is_object() && witness.contains("violated_plane") &&
      witness["violated_plane"].is_number_integer()) {
    const int j = witness["violated_plane"].get<int>();
    if (j >= 0 && j < 6) return j;
  }
  const auto r = plane_ranges(planes, v);
  const bool by_reach = e == ErrorClass::false_reject || e == ErrorClass::false_intersect;
  int best = -1;
  for (int j = 0; j < 6; ++j) {
    if (norm3(planes[std::size_t(j)]) == 0) continue;
    const double x = r[std::size_t(j)][by_reach ? 1 : 0];
    if (best < 0 || x < r[std::size_t(best)][by_reach ? 1 : 0]) best = j;
  }
  return best;
}

namespace {

// The scene: the frustum's bounded part (its corners that exist: three planes meeting inside the
// other three) and the volume, as far as it reaches within three times the frustum's extent (a
// rod a hundred times longer than the frustum would leave it a speck), and never less than the
// volume's point nearest the frustum's centre. vlo, vhi: the volume's own bounds.
struct Scene {
  V3 center{}, vlo{}, vhi{};
  double radius = 1.0;
  int frustum_corners = 0;
};

Scene scene_of(const std::array<Plane4, 6>& planes, const Volume& volume) {
  const double inf = std::numeric_limits<double>::infinity();
  V3 lo = {inf, inf, inf}, hi = {-inf, -inf, -inf};
  auto grow = [&](const V3& p) {
    for (std::size_t i = 0; i < 3; ++i) {
      lo[i] = std::min(lo[i], p[i]);
      hi[i] = std::max(hi[i], p[i]);
    }
  };
  Scene out;
  for (int k = 0; k < 8; ++k) {
    const auto p = meet(planes[k & 1 ? kRight : kLeft], planes[k & 2 ? kTop : kBottom], planes[k & 4 ? kFar : kNear]);
    if (!p) continue;
    bool inside = true;
    for (const Plane4& q : planes) {
      const double len = norm3(q);
      if (len > 0 && (dot3(q, *p) + q[3]) / len < -1e-9 * (1 + std::abs((*p)[0]) + std::abs((*p)[1]) + std::abs((*p)[2]))) inside = false;
    }
    if (!inside) continue;
    grow(*p);
    ++out.frustum_corners;
  }
  std::vector<V3> vol = corners(volume);
  if (const auto* s = std::get_if<Sphere>(&volume)) {
    const V3 ctr = v3(s->center);
    const double r = s->radius;
    vol = {{ctr[0] - r, ctr[1] - r, ctr[2] - r}, {ctr[0] + r, ctr[1] + r, ctr[2] + r}};
  }
  V3& vlo = out.vlo;
  V3& vhi = out.vhi;
  vlo = {inf, inf, inf}, vhi = {-inf, -inf, -inf};
  for (const V3& p : vol)
    for (std::size_t i = 0; i < 3; ++i) {
      vlo[i] = std::min(vlo[i], p[i]);
      vhi[i] = std::max(vhi[i], p[i]);
    }
  if (out.frustum_corners > 0) {
    V3 fc, reach_lo, reach_hi, nearest;
    for (std::size_t i = 0; i < 3; ++i) {
      fc[i] = 0.5 * (lo[i] + hi[i]);
      const double ext = std::max(hi[i] - lo[i], 1e-300);
      reach_lo[i] = std::max(vlo[i], fc[i] - 1.5 * ext * 3);
      reach_hi[i] = std::min(vhi[i], fc[i] + 1.5 * ext * 3);
      nearest[i] = std::clamp(fc[i], vlo[i], vhi[i]);
    }
    grow(nearest);
    bool overlaps = true;
    for (std::size_t i = 0; i < 3; ++i) overlaps = overlaps && reach_lo[i] <= reach_hi[i];
    if (overlaps) {
      grow(reach_lo);
      grow(reach_hi);
    }
  } else {
    grow(vlo);
    grow(vhi);
  }
  double radius = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    out.center[i] = 0.5 * (lo[i] + hi[i]);
    radius += (hi[i] - lo[i]) * (hi[i] - lo[i]);
  }
  radius = 0.5 * std::sqrt(radius);
  out.radius = radius > 0 ? radius : 1.0;
  return out;
}

// The volume's point reaching furthest inside plane q (furthest_inside) or furthest beyond it;
// `fallback` when the volume has no corners.
V3 extreme_point(const Volume& volume, const Plane4& q, bool furthest_inside, const V3& fallback) {
  V3 best_p = fallback;
  double best = furthest_inside ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  if (const auto* s = std::get_if<Sphere>(&volume)) {
    const double len = norm3(q), sign = furthest_inside ? 1.0 : -1.0;
    for (std::size_t i = 0; i < 3; ++i) best_p[i] = double(s->center[int(i)]) + sign * double(s->radius) * q[i] / len;
    return best_p;
  }
  for (const V3& p : corners(volume)) {
    const double value = dot3(q, p) + q[3];
    if (furthest_inside ? value > best : value < best) {
      best = value;
      best_p = p;
    }
  }
  return best_p;
}

// An exact rational coordinate ("p/q") to the nearest double or so: a drawing needs no more. A
// numerator or denominator past double's range leaves the point unread.
bool exact_point(const json& j, V3& out) {
  if (!j.is_array() || j.size() != 3) return false;
  V3 p{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!j[i].is_string()) return false;
    const std::string t = j[i].get<std::string>();
    const auto slash = t.find('/');
    try {
      p[i] = slash == std::string::npos ? std::stod(t) : std::stod(t.substr(0, slash)) / std::stod(t.substr(slash + 1));
    } catch (const std::exception&) {
      return false;
    }
    if (!std::isfinite(p[i])) return false;
  }
  out = p;
  return true;
}

// Where the error is. A false reject: the oracle's point of B ∩ F (a vertex of it, on the
// boundary). A false intersect: the volume's point reaching furthest over the fault plane. A
// false inside: the oracle's corner beyond the plane it crosses, else the volume's point furthest
// beyond the fault plane. An under-inside: the volume's point nearest to crossing the fault plane.
V3 error_focus(const CorpusEntry& e, const std::array<Plane4, 6>& planes, const json& witness, int fault, const V3& center) {
  V3 focus = center;
  if (e.error == ErrorClass::false_reject && witness.value("kind", "") == "point" && witness.contains("point_approx")) {
    for (std::size_t i = 0; i < 3; ++i) focus[i] = witness["point_approx"][i].get<double>();
  } else if (e.error == ErrorClass::false_inside && witness.contains("outside_corner") && exact_point(witness["outside_corner"], focus)) {
    // the corner the oracle names
  } else if (fault >= 0) {
    focus = extreme_point(e.c.volume, planes[std::size_t(fault)], e.error == ErrorClass::false_intersect, center);
  }
  return focus;
}

// How wide the error is: its distance (the smaller of the boundary's and the verdict's), never
// below a few float spacings at the focus. A distance of 0 is a contact, with no gap to resolve at
// any magnification: then the view is sized to the volume, to show what touches what.
double error_width(const json& x, const V3& focus, const Scene& scene) {
  double width = std::numeric_limits<double>::infinity();
  bool contact = false;
  for (const char* key : {"distance", "verdict_distance", "backward_distance"})
    if (x.contains(key) && x[key].is_number()) {
      const double d = x[key].get<double>();
      if (d > 0) width = std::min(width, d);
      if (d == 0) contact = true;
    }
  const V3 &vlo = scene.vlo, &vhi = scene.vhi;
  if (contact) width = std::max({vhi[0] - vlo[0], vhi[1] - vlo[1], vhi[2] - vlo[2]}) / 3;
  const double spacing = float_spacing(std::max({std::abs(focus[0]), std::abs(focus[1]), std::abs(focus[2])}));
  return std::max(std::isfinite(width) ? width : 0.0, 8 * spacing);
}

}  // namespace

json case_view_json(const CorpusEntry& e) {
  const Case& c = e.c;
  const json& x = c.extra;
  const auto planes = truth_planes(c.frustum);
  const json witness = x.value("witness", json::object());
  const int fault = fault_plane(planes, c.volume, e.error, witness);
  const auto ranges = plane_ranges(planes, c.volume);
  const Scene scene = scene_of(planes, c.volume);
  const V3 focus = error_focus(e, planes, witness, fault, scene.center);
  const double width = error_width(x, focus, scene);

  json pl = json::array(), rg = json::array();
  for (std::size_t j = 0; j < 6; ++j) {
    pl.push_back(json::array({planes[j][0], planes[j][1], planes[j][2], planes[j][3]}));
    rg.push_back(norm3(planes[j]) == 0 ? json(nullptr) : json::array({ranges[j][0], ranges[j][1]}));
  }
  const char* fault_reason =
      e.error == ErrorClass::false_reject || e.error == ErrorClass::false_intersect
          ? "the plane over which the volume reaches least far inside (the nearest to culling it)"
      : e.error == ErrorClass::false_inside && witness.contains("violated_plane")
          ? "a plane the volume crosses (the oracle's witness)"
          : "the plane the volume comes nearest to crossing";
  json w = {{"kind", witness.value("kind", "none")}};
  if (witness.contains("point_approx")) w["point"] = witness["point_approx"];
  if (witness.contains("plane_approx")) w["plane"] = witness["plane_approx"];
  return {{"id", c.id},
          {"method", e.method},
          {"class", to_string(e.error)},
          {"family", e.distribution},
          {"verdict", std::string(to_string(e.verdict))},
          {"truth", c.truth ? json(std::string(to_string(*c.truth))) : json(nullptr)},
          {"claim", x.value("claim", "")},
          {"violates_claim", x.value("violates_claim", false)},
          {"float_exact", x.value("float_exact", false)},
          {"distance", x.contains("distance") ? x["distance"] : json(nullptr)},
          {"distance_kind", x.value("distance_kind", "")},
          {"verdict_distance", x.contains("verdict_distance") ? x["verdict_distance"] : json(nullptr)},
          {"verdict_distance_kind", x.value("verdict_distance_kind", "")},
          {"allowance", x.contains("allowance") ? x["allowance"] : json(nullptr)},
          {"backward_distance", x.contains("backward_distance") ? x["backward_distance"] : json(nullptr)},
          {"reproduce", x.value("reproduce", "")},
          {"note", c.note},
          {"on_path", e.path.has_value()},
          {"verdicts", x.value("verdicts", json::object())},
          {"planes", pl},
          {"plane_ranges", rg},
          {"matrix", c.frustum.matrix.has_value()},
          {"volume", volume_json(c.volume)},
          {"witness", w},
          {"fault_plane", fault},
          {"fault_reason", fault >= 0 ? fault_reason : ""},
          {"scene", {{"center", vec_json(scene.center)}, {"radius", scene.radius}, {"frustum_corners", scene.frustum_corners}}},
          {"focus", vec_json(focus)},
          {"error_width", width},
          {"frustum_text", format_frustum(c.frustum)},
          {"volume_text", format_volume(c.volume)}};
}

namespace {

// The page around a view: a title, a note, the 3D view, the case as text, and the data and script.
std::string view_page(const std::string& title, const std::string& note, const std::string& case_text,
                      const json& view, const std::string& case_js) {
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  h += fmt::format("<title>{} — cullproof corpus</title>\n", html_escape(title));
  h += "<style>body { font: 14px/1.45 system-ui, sans-serif; margin: 0 auto; max-width: 1280px; padding: 0 24px 32px; color: #1a1a1a; }"
       " h1 { font-size: 20px; margin: 18px 0 4px; } code, pre { font: 12px ui-monospace, monospace; }"
       " pre { background: #f6f6f6; padding: 8px; overflow-x: auto; white-space: pre-wrap; word-break: break-all; }</style>\n";
  h += "</head>\n<body>\n";
  h += fmt::format("<h1>{}</h1>\n<p>{}</p>\n<div id=\"case-view\"></div>\n", html_escape(title), html_escape(note));
  h += fmt::format("<h2 style=\"font-size:15px\">The case</h2>\n<pre>{}</pre>\n", html_escape(case_text));
  h += "<script type=\"application/json\" id=\"cullproof-data\">" + script_json({{"case", view}}) + "</script>\n";
  h += "<script>" + script_text(case_js) + "</script>\n</body>\n</html>\n";
  return h;
}

}  // namespace

std::string case_html(const CorpusEntry& e, const std::string& case_js) {
  return view_page(e.c.id, e.c.note, format_case(e.c, true), case_view_json(e), case_js);
}

json system_view_json(const CorpusEntry& failing, const std::vector<Volume>& others, const json& system) {
  json view = case_view_json(failing);
  view["others"] = json::array();
  for (const Volume& v : others) view["others"].push_back(volume_json(v));
  view["system"] = system;
  return view;
}

std::string system_html(const std::string& title, const CorpusEntry& failing, const json& view, const std::string& case_js) {
  return view_page(title, failing.c.note, format_case(failing.c, true), view, case_js);
}

void write_case_drawings(const json& view, const std::string& svg_file, const std::string& zoom_svg_file) {
  if (!svg_file.empty()) {
    write_file_atomic(svg_file, case_svg(view, false));
    std::cout << "drawing: " << svg_file << "\n";
  }
  if (!zoom_svg_file.empty()) {
    write_file_atomic(zoom_svg_file, case_svg(view, true));
    std::cout << "drawing, magnified around the error: " << zoom_svg_file << "\n";
  }
}

int write_case_files(const std::filesystem::path& dir, const std::string& id, const std::string& html_file,
                     const std::string& svg_file, const std::string& zoom_svg_file) {
  try {
    const std::string js = html_file.empty() ? std::string() : load_web_asset("case.js");
    for (const CorpusEntry& e : load_corpus(dir)) {
      if (e.c.id != id) continue;
      if (!html_file.empty()) {
        write_file_atomic(html_file, case_html(e, js));
        std::cout << "page: " << html_file << "\n";
      }
      write_case_drawings(case_view_json(e), svg_file, zoom_svg_file);
      return 0;
    }
    std::cerr << "cullproof corpus show: no case with id '" << id << "' under " << dir.string() << "\n";
    return 2;
  } catch (const AssetError& e) {
    std::cerr << "cullproof corpus show: " << e.what() << "\n";
    return 2;
  }
}

}  // namespace cullproof::report

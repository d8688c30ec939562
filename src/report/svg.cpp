// Three-view drawings of a corpus case (see cullproof/report/case_view.hpp): every face of the frustum
// and of the volume is a convex polygon, clipped in double to a cube around what is drawn (the
// scene, or the error magnified), then projected orthographically three times.
#include "cullproof/report/case_view.hpp"
#include "cullproof/report/report.hpp"

#include <fmt/format.h>

#include <cmath>

namespace cullproof::report {

namespace {

using nlohmann::json;
using V3 = std::array<double, 3>;

/// A vertex of a polygon, and what bounds the edge from it to the next one: a frustum plane
/// (0..5), a face of the drawing's cube (kCube), or the volume's own edge (kVolume).
struct Vertex {
  V3 p;
  int edge;
};
constexpr int kCube = 100, kVolume = 200;
using Polygon = std::vector<Vertex>;

double eval(const Plane4& q, const V3& p) { return q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[3]; }

// Keeps the part of `poly` where q >= 0 (Sutherland–Hodgman); the new edge along q is labelled `label`.
Polygon clip(const Polygon& poly, const Plane4& q, int label) {
  Polygon out;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vertex& a = poly[i];
    const Vertex& b = poly[(i + 1) % n];
    const double sa = eval(q, a.p), sb = eval(q, b.p);
    const bool ina = sa >= 0, inb = sb >= 0;
    auto cut = [&] {
      const double t = sa / (sa - sb);
      return V3{a.p[0] + t * (b.p[0] - a.p[0]), a.p[1] + t * (b.p[1] - a.p[1]), a.p[2] + t * (b.p[2] - a.p[2])};
    };
    if (ina) out.push_back(a);
    if (ina && !inb) out.push_back({cut(), label});
    if (!ina && inb) out.push_back({cut(), a.edge});
  }
  return out.size() >= 3 ? out : Polygon{};
}

// The six faces of the cube centred on c with half-width h, as inward planes.
std::array<Plane4, 6> cube(const V3& c, double h) {
  std::array<Plane4, 6> out{};
  for (int i = 0; i < 3; ++i) {
    Plane4 lo{0, 0, 0, 0}, hi{0, 0, 0, 0};
    lo[std::size_t(i)] = 1;
    lo[3] = -(c[std::size_t(i)] - h);
    hi[std::size_t(i)] = -1;
    hi[3] = c[std::size_t(i)] + h;
    out[std::size_t(2 * i)] = lo;
    out[std::size_t(2 * i + 1)] = hi;
  }
  return out;
}

// A square on plane q around the point of q nearest to c, large enough to cover the cube.
Polygon plane_square(const Plane4& q, const V3& c, double h) {
  const double len2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
  const double t = eval(q, c) / len2;
  const V3 o = {c[0] - t * q[0], c[1] - t * q[1], c[2] - t * q[2]};
  const double len = std::sqrt(len2);
  const V3 n = {q[0] / len, q[1] / len, q[2] / len};
  // Two unit vectors spanning the plane.
  const V3 a = std::abs(n[0]) < 0.9 ? V3{1, 0, 0} : V3{0, 1, 0};
  V3 u = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
  const double ul = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& x : u) x /= ul;
  const V3 v = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
  const double s = 4 * h;
  Polygon p;
  for (const auto& [su, sv] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}})
    p.push_back({{o[0] + s * (su * u[0] + sv * v[0]), o[1] + s * (su * u[1] + sv * v[1]), o[2] + s * (su * u[2] + sv * v[2])}, kCube});
  return p;
}

std::array<Plane4, 6> planes_of(const json& view) {
  std::array<Plane4, 6> out{};
  for (std::size_t j = 0; j < 6; ++j)
    for (std::size_t k = 0; k < 4; ++k) out[j][k] = view.at("planes")[j][k].get<double>();
  return out;
}

V3 vec(const json& j) { return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()}; }

// The volume's faces as polygons (a box), or nothing (a sphere or a point: drawn as circles).
std::vector<Polygon> volume_faces(const json& v) {
  std::array<V3, 8> c{};
  const std::string kind = v.at("kind");
  if (kind == "aabb") {
    const V3 lo = vec(v.at("min")), hi = vec(v.at("max"));
    for (int k = 0; k < 8; ++k) c[std::size_t(k)] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]};
  } else if (kind == "obb") {
    const V3 ctr = vec(v.at("center")), h = vec(v.at("half"));
    for (int k = 0; k < 8; ++k) {
      V3 p = ctr;
      for (std::size_t i = 0; i < 3; ++i) {
        const V3 u = vec(v.at("axes")[i]);
        const double s = (k >> i & 1 ? 1.0 : -1.0) * h[i];
        for (std::size_t d = 0; d < 3; ++d) p[d] += s * u[d];
      }
      c[std::size_t(k)] = p;
    }
  } else {
    return {};
  }
  static const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  std::vector<Polygon> out;
  for (const auto& q : quads) {
    Polygon p;
    for (int i : q) p.push_back({c[std::size_t(i)], kVolume});
    out.push_back(p);
  }
  return out;
}

struct View {
  const char* name;
  const char* axes;
  int u, v;        // world axes shown across and up
  double su, sv;   // their signs
};
constexpr View kViews[3] = {{"front", "x across, y up; looking down -z", 0, 1, 1, 1},
                            {"top", "x across, -z up; looking down -y", 0, 2, 1, -1},
                            {"side", "-z across, y up; looking down -x", 2, 1, -1, 1}};
constexpr double kPanel = 300;  // px per panel side
constexpr double kGap = 24;

std::string fmt_num(double x) {
  if (x == 0) return "0";
  const double a = std::abs(x);
  return a >= 1e4 || a < 1e-3 ? fmt::format("{:.3g}", x) : fmt::format("{:.4g}", x);
}

}  // namespace

std::string case_svg(const json& view, bool zoom) {
  const auto planes = planes_of(view);
  const V3 center = zoom ? vec(view.at("focus")) : vec(view.at("scene").at("center"));
  const double half = zoom ? 4 * view.at("error_width").get<double>() : 1.15 * view.at("scene").at("radius").get<double>();
  const double magnification = view.at("scene").at("radius").get<double>() * 1.15 / half;
  const auto box = cube(center, half);
  const int fault = view.at("fault_plane").get<int>();

  auto in_box = [&](Polygon p) {
    for (int b = 0; b < 6 && !p.empty(); ++b) p = clip(p, box[std::size_t(b)], kCube);
    return p;
  };
  // The frustum's faces: each plane's square cut by the cube and by the other planes.
  std::vector<std::pair<int, Polygon>> faces;
  bool open = false;
  for (int j = 0; j < 6; ++j) {
    const Plane4& q = planes[std::size_t(j)];
    if (q[0] == 0 && q[1] == 0 && q[2] == 0) continue;
    Polygon p = in_box(plane_square(q, center, half));
    for (int k = 0; k < 6 && !p.empty(); ++k)
      if (k != j && !(planes[std::size_t(k)][0] == 0 && planes[std::size_t(k)][1] == 0 && planes[std::size_t(k)][2] == 0))
        p = clip(p, planes[std::size_t(k)], k);
    if (p.empty()) continue;
    for (const Vertex& x : p) open = open || x.edge == kCube;
    faces.emplace_back(j, p);
  }
  Polygon fault_whole;
  if (fault >= 0) fault_whole = in_box(plane_square(planes[std::size_t(fault)], center, half));
  std::vector<Polygon> volume;
  for (Polygon& p : volume_faces(view.at("volume")))
    if (Polygon c = in_box(p); !c.empty()) volume.push_back(c);
  Polygon witness_plane;
  const json& w = view.at("witness");
  if (w.value("kind", "") == "separating_plane" && w.contains("plane"))
    witness_plane = in_box(plane_square({w["plane"][0].get<double>(), w["plane"][1].get<double>(), w["plane"][2].get<double>(),
                                         w["plane"][3].get<double>()},
                                        center, half));

  const double width = 3 * kPanel + 2 * kGap, height = 44 + kPanel + 68;
  std::string s = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n",
      width, height);
  const std::string truth = view.at("truth").is_string() ? view.at("truth").get<std::string>() : "?";
  s += fmt::format("<text x=\"0\" y=\"15\" font-weight=\"bold\">{}</text>\n", html_escape(view.at("id").get<std::string>()));
  s += fmt::format("<text x=\"0\" y=\"32\">{} says {}, the truth is {} ({}); {}</text>\n", html_escape(view.at("method").get<std::string>()),
                   html_escape(view.at("verdict").get<std::string>()), html_escape(truth), html_escape(view.at("class").get<std::string>()),
                   zoom ? fmt::format("magnified {}x around the error: each panel is {} units wide", fmt_num(magnification), fmt_num(2 * half))
                        : fmt::format("each panel is {} units wide", fmt_num(2 * half)));
  const double top = 44;
  for (int k = 0; k < 3; ++k) {
    const View& vw = kViews[k];
    const double ox = k * (kPanel + kGap);
    auto px = [&](const V3& p) {
      const double u = vw.su * (p[std::size_t(vw.u)] - center[std::size_t(vw.u)]);
      const double v = vw.sv * (p[std::size_t(vw.v)] - center[std::size_t(vw.v)]);
      return std::pair{ox + kPanel / 2 + u / half * kPanel / 2, top + kPanel / 2 - v / half * kPanel / 2};
    };
    auto path = [&](const Polygon& p) {
      std::string d;
      for (std::size_t i = 0; i < p.size(); ++i) {
        const auto [x, y] = px(p[i].p);
        d += fmt::format("{}{:.2f},{:.2f}", i ? " L" : "M", x, y);
      }
      return d + " Z";
    };
    auto edge = [&](const Polygon& p, std::size_t i) {
      const auto [x0, y0] = px(p[i].p);
      const auto [x1, y1] = px(p[(i + 1) % p.size()].p);
      return fmt::format("M{:.2f},{:.2f} L{:.2f},{:.2f}", x0, y0, x1, y1);
    };
    s += fmt::format("<g><clipPath id=\"panel{0}\"><rect x=\"{1}\" y=\"{2}\" width=\"{3}\" height=\"{3}\"/></clipPath>\n", k, ox, top, kPanel);
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#fbfbfb\" stroke=\"#ccc\"/>\n", ox, top, kPanel, kPanel);
    s += fmt::format("<g clip-path=\"url(#panel{})\">\n", k);
    for (const auto& [j, p] : faces)
      s += fmt::format("<path d=\"{}\" fill=\"{}\" fill-opacity=\"{}\" stroke=\"none\"/>\n", path(p), j == fault ? "#e6ab02" : "#4292c6",
                       j == fault ? 0.35 : 0.07);
    if (!fault_whole.empty())
      s += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"#b8860b\" stroke-width=\"1\" stroke-dasharray=\"6,3\"/>\n", path(fault_whole));
    if (!witness_plane.empty())
      s += fmt::format("<path d=\"{}\" fill=\"#1b9e77\" fill-opacity=\"0.08\" stroke=\"#1b9e77\" stroke-dasharray=\"2,3\"/>\n", path(witness_plane));
    for (const Polygon& p : volume) {
      s += fmt::format("<path d=\"{}\" fill=\"#d6604d\" fill-opacity=\"0.18\" stroke=\"none\"/>\n", path(p));
      for (std::size_t i = 0; i < p.size(); ++i)
        if (p[i].edge == kVolume) s += fmt::format("<path d=\"{}\" stroke=\"#b2182b\" stroke-width=\"1.3\"/>\n", edge(p, i));
    }
    const json& v = view.at("volume");
    if (v.at("kind") == "sphere") {
      const auto [x, y] = px(vec(v.at("center")));
      s += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"{:.2f}\" fill=\"#d6604d\" fill-opacity=\"0.18\" stroke=\"#b2182b\" stroke-width=\"1.3\"/>\n", x, y,
                       v.at("radius").get<double>() / half * kPanel / 2);
    } else if (v.at("kind") == "point") {
      const auto [x, y] = px(vec(v.at("point")));
      s += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3.5\" fill=\"#b2182b\"/>\n", x, y);
    }
    // Frustum edges: each once (from the face of the lower plane), dashed where the drawing cuts
    // the frustum rather than a plane bounding it.
    for (const auto& [j, p] : faces)
      for (std::size_t i = 0; i < p.size(); ++i) {
        const int e = p[i].edge;
        if (e == kCube) s += fmt::format("<path d=\"{}\" stroke=\"#2171b5\" stroke-width=\"1\" stroke-dasharray=\"3,3\"/>\n", edge(p, i));
        else if (e > j && e < 6) s += fmt::format("<path d=\"{}\" stroke=\"#08306b\" stroke-width=\"1.4\"/>\n", edge(p, i));
      }
    if (w.value("kind", "") == "point" && w.contains("point")) {
      const auto [x, y] = px(vec(w.at("point")));
      s += fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"4\" fill=\"#1b9e77\" stroke=\"#fff\" stroke-width=\"1.5\"/>\n", x, y);
    }
    s += "</g>\n";
    s += fmt::format("<text x=\"{}\" y=\"{}\" font-weight=\"bold\">{}</text><text x=\"{}\" y=\"{}\" fill=\"#555\"> {}</text></g>\n", ox,
                     top + kPanel + 16, vw.name, ox + 40, top + kPanel + 16, vw.axes);
  }
  // The legend, in two rows.
  const double ly = top + kPanel + 32;
  const std::string wk = w.value("kind", "");
  s += fmt::format(
      "<g font-size=\"11\"><rect x=\"0\" y=\"{0}\" width=\"14\" height=\"10\" fill=\"#4292c6\" fill-opacity=\"0.3\" stroke=\"#08306b\"/>"
      "<text x=\"20\" y=\"{1}\">frustum{2}</text>"
      "<rect x=\"{5}\" y=\"{0}\" width=\"14\" height=\"10\" fill=\"#e6ab02\" fill-opacity=\"0.5\" stroke=\"#b8860b\" stroke-dasharray=\"3,2\"/>"
      "<text x=\"{6}\" y=\"{1}\">{3}</text>"
      "<rect x=\"0\" y=\"{4}\" width=\"14\" height=\"10\" fill=\"#d6604d\" fill-opacity=\"0.4\" stroke=\"#b2182b\"/>"
      "<text x=\"20\" y=\"{7}\">volume ({8})</text>",
      ly, ly + 9, open ? " (dashed edges: it goes on beyond the drawing)" : "",
      fault >= 0 ? fmt::format("plane {} ({}), where the method erred; dashed: the whole plane", fault, plane_name(fault))
                 : std::string("no fault plane"),
      ly + 18, width / 2, width / 2 + 20, ly + 27, html_escape(view.at("volume").at("kind").get<std::string>()));
  if (wk == "point")
    s += fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"4\" fill=\"#1b9e77\"/><text x=\"{}\" y=\"{}\">witness: a point of both the volume and "
                     "the frustum (the oracle's)</text>",
                     width / 2 + 7, ly + 23, width / 2 + 20, ly + 27);
  else if (wk == "separating_plane")
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"14\" height=\"10\" fill=\"#1b9e77\" fill-opacity=\"0.2\" stroke=\"#1b9e77\" "
                     "stroke-dasharray=\"2,2\"/><text x=\"{}\" y=\"{}\">witness: a plane separating the volume from the frustum (the "
                     "oracle's)</text>",
                     width / 2, ly + 18, width / 2 + 20, ly + 27);
  s += "</g>\n";
  s += "</svg>\n";
  return s;
}

}  // namespace cullproof::report

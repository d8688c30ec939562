// Reproduction of Assarsson & Möller 2000, §4 Table 1: speedup of the
// view-frustum culler over the perspective-transform baseline (DirectModel), per model and path.
//
// Procedure: for each model scene and each of the four path kinds (the scene's camera settings,
// only the kind replaced), (1) one verification pass (simulate(): sampled oracle checks, plane
// tests, culled fraction), (2) `repetitions` timed runs of every configuration over the same
// precomputed frames, configurations interleaved within a repetition so machine noise spreads
// over all of them, each run from fresh state (coherence caches empty at frame 0). A run's time
// covers exactly what a culler does per frame: its per-frame set-up (plane selection, octant
// set-up, TR frame) and the traversal with the visible list. The median run is reported;
// speedup = median(baseline) / median(configuration), A&M's time1/time2 (footnote 2).
#include "cullproof/sim/simulate.hpp"

#include "clock.hpp"


#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ostream>

namespace cullproof::sim {

using nlohmann::json;

namespace {

// Paper values, Table 1: [row][path-1][model-1]. Rows: basic, pc+octant, pc+tr, pc+octant+tr.
constexpr double kPaper[4][4][3] = {
    {{2.8, 1.9, 3.9}, {2.2, 2.0, 3.1}, {3.9, 2.5, 4.3}, {3.1, 2.2, 3.7}},
    {{4.0, 2.4, 5.1}, {2.8, 2.6, 3.9}, {4.8, 3.5, 5.6}, {3.3, 3.0, 5.1}},
    {{3.8, 2.0, 4.0}, {2.5, 2.2, 3.0}, {5.0, 2.8, 4.4}, {8.3, 3.1, 11.0}},
    {{3.7, 2.2, 4.5}, {2.6, 2.4, 3.6}, {5.1, 3.0, 4.8}, {8.0, 3.3, 9.0}},
};
constexpr PathKind kPaths[4] = {PathKind::navigation, PathKind::translation_rotation, PathKind::rotation,
                                PathKind::translation};
constexpr Config kTimed[6] = {Config::perspective_transform, Config::basic_np, Config::pc_octant,
                              Config::pc_tr,                 Config::pc_octant_tr, Config::masking};
constexpr const char* kPaperSize[3] = {"184,000 polygons, 3800 nodes", "167,000 polygons, 188 nodes",
                                       "52,000 polygons, 1274 nodes"};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace

Table1Result run_table1(const SimulateOptions& opt) {
  const double t0 = now_ns();
  Table1Result t;
  t.repetitions = std::max(1, opt.repetitions);
  std::vector<std::string> files = opt.scenes;
  if (files.empty())
    files = {"corpus/scenes/table1-model1.json", "corpus/scenes/table1-model2.json", "corpus/scenes/table1-model3.json"};
  const std::filesystem::path mesh_dir = opt.mesh_dir.empty() ? default_mesh_dir() : std::filesystem::path(opt.mesh_dir);
  const int total = static_cast<int>(files.size()) * 4;
  int done = 0;
  for (std::size_t m = 0; m < files.size(); ++m) {
    const SceneDesc base = load_scene(files[m]);
    World world = build_world(base, mesh_dir);
    for (int p = 0; p < 4; ++p) {
      SceneDesc scene = base;
      scene.camera.kind = kPaths[p];
      if (opt.frames > 0) scene.camera.frames = opt.frames;
      if (opt.progress)
        std::fprintf(stderr, "\rtable1: model %zu path %d (%d/%d)            ", m + 1, p + 1, done + 1, total), std::fflush(stderr);
      // (1) verification pass and counters
      SimulateOptions vo = opt;
      vo.progress = false;
      vo.frames = scene.camera.frames;
      vo.csv.clear();
      vo.json.clear();
      const SimResult sr = simulate(scene, world, vo);
      if (p == 0) {
        t.models.push_back(sr);
        t.models.back().records.clear();
      }
      // (2) timing
      const std::vector<CameraFrame> path = camera_path(scene, world);
      std::vector<std::vector<View>> views;
      views.reserve(path.size());
      for (const CameraFrame& f : path) views.push_back(frame_views(scene.projection, f));
      Table1Cell cell;
      cell.model = static_cast<int>(m) + 1;
      cell.path = kPaths[p];
      cell.frames = static_cast<int>(path.size());
      std::vector<std::vector<double>> times(std::size(kTimed));
      std::vector<std::vector<CullView>> cull_views(views.size());
      for (std::size_t f = 0; f < views.size(); ++f)
        for (const View& v : views[f]) cull_views[f].push_back(cull_view(v));
      std::vector<std::vector<HierarchyCuller>> cullers(std::size(kTimed));
      for (std::size_t ci = 0; ci < std::size(kTimed); ++ci)
        for (std::size_t v = 0; v < views.front().size(); ++v) cullers[ci].emplace_back(kTimed[ci], world.bvh);
      VisibleSet out;
      // One configuration over the whole path, from a first frame (the caches reset untimed).
      const auto reset = [&](std::size_t ci) {
        for (HierarchyCuller& c : cullers[ci]) c.reset();
      };
      const auto run_path = [&](std::size_t ci) {
        for (std::size_t f = 0; f < cull_views.size(); ++f)
          for (std::size_t v = 0; v < cull_views[f].size(); ++v) cullers[ci][v].cull(cull_views[f][v], out);
      };
      // Warm-up (untimed): caches, and the oracle's worker threads idle again before timing.
      for (std::size_t ci = 0; ci < std::size(kTimed); ++ci) {
        reset(ci);
        run_path(ci);
      }
      for (int rep = 0; rep < t.repetitions; ++rep) {
        for (std::size_t ci = 0; ci < std::size(kTimed); ++ci) {
          reset(ci);
          const double a = now_ns();
          run_path(ci);
          times[ci].push_back(now_ns() - a);
        }
      }
      for (std::size_t ci = 0; ci < std::size(kTimed); ++ci) {
        cell.configs.push_back(kTimed[ci]);
        cell.median_ns.push_back(median(times[ci]));
        const auto it = std::find(sr.configs.begin(), sr.configs.end(), kTimed[ci]);
        const Counters& c = sr.totals[static_cast<std::size_t>(it - sr.configs.begin())];
        cell.plane_tests_per_node.push_back(c.nodes_visited ? double(c.plane_tests) / double(c.nodes_visited) : 0.0);
        cell.culled_fraction.push_back(c.leaves ? double(c.leaves - c.visible) / double(c.leaves) : 0.0);
        cell.visited_per_frame.push_back(double(c.nodes_visited) / std::max(1, sr.frames * sr.views_per_frame));
      }
      for (const Counters& c : sr.totals) {
        cell.checked += c.checked;
        cell.forbidden += c.false_reject + c.false_inside;
        cell.false_intersects += c.false_intersect;
      }
      t.cells.push_back(cell);
      ++done;
    }
  }
  if (opt.progress) std::fprintf(stderr, "\rtable1: done (%d cells)                         \n", done);
  t.wall_seconds = (now_ns() - t0) * 1e-9;
  return t;
}

void print_table1(const Table1Result& t, std::ostream& out) {
  out << "Assarsson & Moller 2000, Table 1, reproduced: speedup over the perspective-transform baseline (DirectModel)\n";
  out << "  ours: median of " << t.repetitions << " timed runs per configuration; paper: double PentiumII 200 MHz\n";
  for (std::size_t m = 0; m < t.models.size(); ++m) {
    const SimResult& s = t.models[m];
    out << fmt::format("  model {}: {} polygons ({} triangles), {} nodes, {} leaves of <= {} triangles, {} instances  "
                       "[paper: {}]\n",
                       m + 1, s.polygons, s.triangles, s.nodes, s.leaves, s.leaf_triangles, s.instances,
                       m < 3 ? kPaperSize[m] : "-");
  }
  auto cell_of = [&](int path, int model) -> const Table1Cell* {
    for (const Table1Cell& c : t.cells)
      if (c.path == kPaths[path] && c.model == model + 1) return &c;
    return nullptr;
  };
  const int models = static_cast<int>(t.models.size());
  out << fmt::format("{:<38}", "path");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) out << fmt::format("{:>12}", p + 1);
  out << "\n" << fmt::format("{:<38}", "model");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) out << fmt::format("{:>12}", m + 1);
  out << "\n";
  const char* rows[5] = {"basic n/p", "plane-coherency + octant", "plane-coherency + TR", "pc + octant + TR", "plane masking"};
  for (int row = 0; row < 5; ++row) {
    out << fmt::format("{:<38}", rows[row]);
    for (int p = 0; p < 4; ++p)
      for (int m = 0; m < models; ++m) {
        const Table1Cell* c = cell_of(p, m);
        std::string s = "-";
        if (c && c->median_ns[static_cast<std::size_t>(row + 1)] > 0)
          s = fmt::format("{:.2f}", c->median_ns[0] / c->median_ns[static_cast<std::size_t>(row + 1)]);
        if (row < 4 && m < 3) s += fmt::format(" ({:.1f})", kPaper[row][p][m]);
        out << fmt::format("{:>12}", s);
      }
    out << "\n";
  }
  out << fmt::format("{:<38}", "masking over basic n/p");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) {
      const Table1Cell* c = cell_of(p, m);
      out << fmt::format("{:>12}", c && c->median_ns[5] > 0 ? fmt::format("{:+.0f}%", 100.0 * (c->median_ns[1] / c->median_ns[5] - 1.0)) : "-");
    }
  out << "\n";
  out << "  (paper values in parentheses; the paper gives no numbers for masking: \"not competitive\"; Cesium measured\n"
         "   masking 15-34% faster than basic hierarchical culling)\n";
  out << fmt::format("{:<38}", "baseline frame time (us)");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) {
      const Table1Cell* c = cell_of(p, m);
      out << fmt::format("{:>12.2f}", c ? c->median_ns[0] / c->frames * 1e-3 : 0.0);
    }
  out << "\n";
  for (int row = 0; row < 5; ++row) {
    out << fmt::format("{:<38}", std::string(rows[row]) + " us/frame");
    for (int p = 0; p < 4; ++p)
      for (int m = 0; m < models; ++m) {
        const Table1Cell* c = cell_of(p, m);
        out << fmt::format("{:>12.2f}", c ? c->median_ns[static_cast<std::size_t>(row + 1)] / c->frames * 1e-3 : 0.0);
      }
    out << "\n";
  }
  for (int row = 0; row < 5; ++row) {
    out << fmt::format("{:<38}", std::string(rows[row]) + " tests/node");
    for (int p = 0; p < 4; ++p)
      for (int m = 0; m < models; ++m) {
        const Table1Cell* c = cell_of(p, m);
        out << fmt::format("{:>12.2f}", c ? c->plane_tests_per_node[static_cast<std::size_t>(row + 1)] : 0.0);
      }
    out << "\n";
  }
  for (int row = -1; row < 5; ++row) {
    out << fmt::format("{:<38}", std::string(row < 0 ? "baseline" : rows[row]) + " ns/node");
    for (int p = 0; p < 4; ++p)
      for (int m = 0; m < models; ++m) {
        const Table1Cell* c = cell_of(p, m);
        const double nodes = c ? c->visited_per_frame[static_cast<std::size_t>(row + 1)] * c->frames : 0.0;
        out << fmt::format("{:>12.1f}", nodes > 0 ? c->median_ns[static_cast<std::size_t>(row + 1)] / nodes : 0.0);
      }
    out << "\n";
  }
  out << fmt::format("{:<38}", "nodes visited / frame");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) {
      const Table1Cell* c = cell_of(p, m);
      out << fmt::format("{:>12.0f}", c ? c->visited_per_frame[1] : 0.0);
    }
  out << "\n" << fmt::format("{:<38}", "leaves culled (%)");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) {
      const Table1Cell* c = cell_of(p, m);
      out << fmt::format("{:>12.1f}", c ? 100.0 * c->culled_fraction[1] : 0.0);
    }
  out << "\n" << fmt::format("{:<38}", "frames");
  for (int p = 0; p < 4; ++p)
    for (int m = 0; m < models; ++m) {
      const Table1Cell* c = cell_of(p, m);
      out << fmt::format("{:>12}", c ? c->frames : 0);
    }
  out << "\n";
  std::uint64_t checked = 0, forbidden = 0, fx = 0;
  for (const Table1Cell& c : t.cells) {
    checked += c.checked;
    forbidden += c.forbidden;
    fx += c.false_intersects;
  }
  out << fmt::format("verification: {} leaf verdicts checked against the oracle, {} false rejects + false insides, {} "
                     "false intersects\n",
                     checked, forbidden, fx);
  out << fmt::format("wall time {:.1f} s\n", t.wall_seconds);
}

json to_json(const Table1Result& t) {
  json j;
  j["repetitions"] = t.repetitions;
  j["wall_seconds"] = t.wall_seconds;
  j["models"] = json::array();
  for (const SimResult& s : t.models)
    j["models"].push_back({{"scene", s.scene}, {"polygons", s.polygons}, {"triangles", s.triangles}, {"nodes", s.nodes},
                           {"leaves", s.leaves}, {"leaf_triangles", s.leaf_triangles}});
  j["cells"] = json::array();
  for (const Table1Cell& c : t.cells) {
    json cj = {{"model", c.model}, {"path", to_string(c.path)}, {"frames", c.frames}, {"checked", c.checked},
               {"forbidden_errors", c.forbidden}, {"false_intersects", c.false_intersects}};
    for (std::size_t i = 0; i < c.configs.size(); ++i)
      cj["configs"][to_string(c.configs[i])] = {{"median_ns", c.median_ns[i]},
                                                {"speedup", c.median_ns[i] > 0 ? c.median_ns[0] / c.median_ns[i] : 0.0},
                                                {"plane_tests_per_node", c.plane_tests_per_node[i]},
                                                {"culled_fraction", c.culled_fraction[i]},
                                                {"visited_per_frame", c.visited_per_frame[i]}};
    j["cells"].push_back(cj);
  }
  return j;
}

}  // namespace cullproof::sim

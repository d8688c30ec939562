// Frame-by-frame simulation with verification against the exact oracle.
//
// Each frame: the declared moving objects move (move_objects), the camera takes its pose on the
// path, every configuration culls every view of the frame with the state it kept from earlier
// frames. Verification: each configuration's visible set implies a verdict for every leaf
// (culled: outside; reported: inside or intersecting); the oracle's exact truth for the leaf's
// box against the frame's float planes (docs/semantics.md "The truth") classifies it (campaign.hpp
// error_class). Checked leaves: all of them with --exhaustive, else `samples` random leaves per
// frame and view plus every leaf on which two configurations disagree. The perspective-transform
// baseline works on the clip matrix: a leaf it gets "wrong" against the float planes is judged
// again end to end against the matrix (frustum_spec(matrix)). A false reject or false inside is a
// mismatch: it is written to the corpus with the scene, the frame, the deciding node and the
// cached state (plane-coherency cache, TR state) that produced it.
#include "cullproof/sim/simulate.hpp"

#include "clock.hpp"

#include "cullproof/judge/judge.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/oracle/oracle.hpp"
#include "cullproof/core/splitmix.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <set>

#include <unistd.h>

namespace cullproof::sim {

using nlohmann::json;

void Counters::add(const Counters& o) {
  nodes_visited += o.nodes_visited;
  plane_tests += o.plane_tests;
  leaves += o.leaves;
  visible += o.visible;
  inside += o.inside;
  checked += o.checked;
  false_reject += o.false_reject;
  false_inside += o.false_inside;
  false_intersect += o.false_intersect;
  under_inside += o.under_inside;
  tr_frames += o.tr_frames;
  octant_frames += o.octant_frames;
  time_ns += o.time_ns;
}

std::uint64_t SimResult::forbidden_errors() const noexcept {
  std::uint64_t n = 0;
  for (const Counters& c : totals) n += c.false_reject + c.false_inside;
  return n;
}

namespace {

struct Progress {
  bool on;
  int total;
  std::string label;
  int last = -1;
  void update(int done) {
    if (!on || total <= 0) return;
    if (!isatty(2)) {  // a log, not a terminal: one line at the end
      if (done >= total) std::fprintf(stderr, "%s: %d frames done\n", label.c_str(), total);
      return;
    }
    const int pct = static_cast<int>(100.0 * done / total);
    if (pct == last) return;
    last = pct;
    const int w = 30, fill = pct * w / 100;
    std::fprintf(stderr, "\r%s [%s%s] %3d%% (%d/%d)", label.c_str(), std::string(static_cast<std::size_t>(fill), '#').c_str(),
                 std::string(static_cast<std::size_t>(w - fill), '.').c_str(), pct, done, total);
    if (done >= total) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
};

json box_json(const Aabb& b) {
  return json{{"min", {format_float(b.min.x), format_float(b.min.y), format_float(b.min.z)}},
              {"max", {format_float(b.max.x), format_float(b.max.y), format_float(b.max.z)}}};
}

}  // namespace

std::vector<Optimisation> decide_optimisations(const SceneDesc& scene, const World& world,
                                               const std::vector<CameraFrame>& path) {
  std::vector<Optimisation> out;
  out.push_back({"plane-coherency", "enabled", "valid for every frustum: it only reorders the six plane tests (A&M §3.2)"});
  out.push_back({"masking", "enabled", "valid for every frustum: a child's box lies in its parent's (A&M §3.4)"});
  // Octant: ask the culler itself, frame by frame.
  int refused = 0;
  std::string why;
  for (const CameraFrame& f : path) {
    for (const View& v : frame_views(scene.projection, f)) {
      double d1 = 0.0;
      const std::string w = octant_decision(v.proj, v.depth, &d1);
      if (!w.empty()) {
        ++refused;
        if (why.empty()) why = w;
      }
    }
  }
  const int views = static_cast<int>(path.size()) * (scene.projection.kind == ProjectionKind::stereo ? 2 : 1);
  const std::string proj(to_string(scene.projection.kind));
  if (refused == 0)
    out.push_back({"octant", "enabled", "every projection of the path is bounded and symmetric (" + proj + "; decided once per projection, verdicts checked every frame)"});
  else
    out.push_back({"octant", refused == views ? "disabled" : "partly",
                   fmt::format("{} projection: OctantCuller refuses {} of {} views ({}); plane coherency alone instead", proj, refused,
                               views, why)});
  // TR coherency.
  int still = 0, trans = 0, rot = 0, general = 0, zoom = 0, rot_about_x = 0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    if (path[i].motion == FrameMotion::rotation) {
      // About the camera's x axis (pitch): the axis through both eyes of a stereo rig.
      const glm::dmat3 rel = glm::transpose(path[i - 1].axes) * path[i].axes;
      if (std::abs(rel[0][0] - 1.0) < 1e-9 && std::abs(rel[0][1]) < 1e-9 && std::abs(rel[0][2]) < 1e-9) ++rot_about_x;
    }
    if (path[i].fovy_deg != path[i - 1].fovy_deg) {
      ++zoom;
      continue;
    }
    switch (path[i].motion) {
      case FrameMotion::still: ++still; break;
      case FrameMotion::translation: ++trans; break;
      case FrameMotion::rotation: ++rot; break;
      default: ++general; break;
    }
  }
  std::size_t moving_nodes = 0, moving_instances = 0;
  for (const Instance& in : world.instances)
    if (in.moving) {
      ++moving_instances;
      moving_nodes += in.node_end - in.root;
    }
  const std::string moving = moving_instances == 0
                                 ? std::string("no moving objects declared")
                                 : fmt::format("never for the {} nodes of the {} moving instances, nor their refitted ancestors "
                                               "(full test every frame they move)",
                                               moving_nodes, moving_instances);
  const std::string zooms = zoom ? fmt::format("; not in {} frames whose projection changed (zoom)", zoom) : "";
  const bool always_zoom = zoom > 0 && zoom + 1 == static_cast<int>(path.size());
  const std::string zoom_all =
      fmt::format("the projection changes in every frame (zoom: fovy {} to {} degrees), which moves the side planes "
                  "independently of the camera",
                  scene.projection.fovy_deg, scene.projection.zoom_fovy_end.value_or(scene.projection.fovy_deg));
  if (always_zoom)
    out.push_back({"tr-translation", "disabled", zoom_all});
  else if (trans + still == 0)
    out.push_back({"tr-translation", "disabled", "the path has no pure translation or still frames" + zooms});
  else
    out.push_back({"tr-translation", "enabled",
                   fmt::format("in {} translation and {} still frames of {}; {}{}", trans, still, path.size(), moving, zooms)});
  if (scene.projection.kind == ProjectionKind::orthographic)
    out.push_back({"tr-rotation", "disabled",
                   "orthographic projection: the side planes do not pass through an eye, rotation coherency needs a "
                   "perspective pose (A&M §3.5 fig. 7a)"});
  else if (always_zoom)
    out.push_back({"tr-rotation", "disabled", zoom_all});
  else if (scene.projection.kind == ProjectionKind::stereo && scene.projection.eye_separation > 0.0 && rot > 0)
    out.push_back({"tr-rotation", rot_about_x > 0 ? "partly" : "disabled",
                   fmt::format("stereo pair: in {} of the {} pure rotation frames the rig turns about an axis other than "
                               "the one through both eyes, so each eye also moves sideways (rotation + translation per "
                               "eye), which TR coherency cannot answer (the culler detects it per eye: plane coherency "
                               "decides); in the other {} (pitch, about the eyes' axis) each eye only rotates: enabled{}",
                               rot - rot_about_x, rot, rot_about_x, zooms)});
  else if (rot == 0)
    out.push_back({"tr-rotation", "disabled",
                   fmt::format("the path has no pure rotation frames ({} general frames: translation and rotation together){}",
                               general, zooms)});
  else
    out.push_back({"tr-rotation", "enabled",
                   fmt::format("in the {} pure rotation frames (single camera axis detected per frame by the culler); {}{}",
                               rot, moving, zooms)});
  if (moving_instances > 0)
    out.push_back({"tr-moving-nodes", "disabled",
                   fmt::format("TR coherency {}; they and every refitted ancestor lose their TR state and get a full "
                               "test (plane coherency, octant and masking stay valid: they hold no distances)",
                               moving)});
  if (general > 0)
    out.push_back({"tr-general", "disabled",
                   fmt::format("{} frames move and turn the camera at once: TR coherency cannot answer, plane coherency "
                               "(and the octant) decide",
                               general)});
  return out;
}

namespace {

// One simulation run: every configuration over every view of every frame, its verdicts checked
// against the oracle, the mismatches recorded (and, up to a budget per configuration, written).
class Simulation {
 public:
  Simulation(const SceneDesc& scene, World& world, const SimulateOptions& opt, SimResult& r)
      : scene_(scene), world_(world), opt_(opt), r_(r), cullers_(r.configs.size()), outs_(r.configs.size()),
        node_verdicts_(r.configs.size()),
        leafv_(r.configs.size()), written_(r.configs.size(), 0), L_(world.leaf_count()) {}

  void frame(int f, const CameraFrame& cam, const std::vector<std::uint32_t>& moved) {
    const std::vector<View> views = frame_views(scene_.projection, cam);
    for (int v = 0; v < static_cast<int>(views.size()); ++v) {
      const View& view = views[static_cast<std::size_t>(v)];
      for (std::size_t ci = 0; ci < r_.configs.size(); ++ci) run_config(ci, f, v, cam, view, moved);
      if (opt_.verify) check_view(f, v, cam, view);
    }
  }

 private:
  // The configuration's traversal of one view, timed, recorded, and its verdicts kept per leaf.
  void run_config(std::size_t ci, int f, int v, const CameraFrame& cam, const View& view,
                  const std::vector<std::uint32_t>& moved) {
    const Config c = r_.configs[ci];
    VisibleSet& out = outs_[ci];
    HierarchyCuller& culler = culler_of(ci, v);
    const CullView cv = cull_view(view);
    const double t0 = now_ns();
    if (!moved.empty()) culler.moved(moved);
    culler.cull(cv, out, &node_verdicts_[ci]);
    const double t1 = now_ns();
    FrameRecord rec;
    rec.frame = f;
    rec.view = v;
    rec.motion = cam.motion;
    rec.config = c;
    rec.moved_nodes = static_cast<std::uint32_t>(moved.size());
    const HierarchyFrame& st = culler.frame();
    rec.tr_used = st.tr_used;
    rec.octant_used = st.octant_used;
    rec.c.nodes_visited = st.visited;
    rec.c.plane_tests = st.tests;
    rec.c.leaves = L_;
    rec.c.visible = out.indices.size();
    for (Visibility vv : out.verdicts) rec.c.inside += vv == Visibility::inside;
    rec.c.tr_frames = rec.tr_used;
    rec.c.octant_frames = rec.octant_used;
    rec.c.time_ns = t1 - t0;
    r_.records.push_back(rec);
    auto& lv = leafv_[ci];
    lv.assign(L_, static_cast<std::uint8_t>(Visibility::outside));
    for (std::size_t k = 0; k < out.indices.size(); ++k) lv[out.indices[k]] = static_cast<std::uint8_t>(out.verdicts[k]);
  }

  // The configuration's culler in view v (one per view: each keeps its own caches).
  HierarchyCuller& culler_of(std::size_t ci, int v) {
    auto& per_view = cullers_[ci];
    HierarchyCuller::Options o;
    o.ignore_projection_change = opt_.bypass_zoom_guard;
    while (static_cast<int>(per_view.size()) <= v) per_view.emplace_back(r_.configs[ci], world_.bvh, o);
    return per_view[static_cast<std::size_t>(v)];
  }

  // Every leaf when exhaustive; else opt.samples random leaves (seeded by seed, frame and view)
  // and every leaf on which the configurations disagree.
  std::vector<std::uint32_t> leaves_to_check(int f, int v) const {
    std::vector<std::uint32_t> cand;
    if (opt_.exhaustive) {
      cand.resize(L_);
      for (std::uint32_t k = 0; k < L_; ++k) cand[k] = k;
      return cand;
    }
    std::set<std::uint32_t> s;
    SplitMix64 rng{opt_.seed * 1000003ull + static_cast<std::uint64_t>(f) * 7919ull + static_cast<std::uint64_t>(v)};
    for (int k = 0; k < opt_.samples && L_ > 0; ++k) s.insert(static_cast<std::uint32_t>(rng.next() % L_));
    for (std::uint32_t k = 0; k < L_; ++k)
      for (std::size_t ci = 1; ci < r_.configs.size(); ++ci)
        if (leafv_[ci][k] != leafv_[0][k]) {
          s.insert(k);
          break;
        }
    cand.assign(s.begin(), s.end());
    return cand;
  }

  // The view's records (the last ones pushed) gain their error counts; a false reject or false
  // inside becomes a mismatch.
  void check_view(int f, int v, const CameraFrame& cam, const View& view) {
    const std::vector<std::uint32_t> cand = leaves_to_check(f, v);
    const CaseFrustum spec = frustum_spec(view.frustum);
    std::vector<std::uint8_t> truth(cand.size());
    tbb::parallel_for(std::size_t(0), cand.size(), [&](std::size_t i) {
      truth[i] = static_cast<std::uint8_t>(oracle::truth(spec, Volume(world_.bvh.prim_boxes[cand[i]])));
    });
    const std::size_t first_rec = r_.records.size() - r_.configs.size();
    for (std::size_t ci = 0; ci < r_.configs.size(); ++ci) {
      FrameRecord& rec = r_.records[first_rec + ci];
      const Config c = r_.configs[ci];
      rec.c.checked = cand.size();
      for (std::size_t i = 0; i < cand.size(); ++i) {
        const auto verdict = static_cast<Visibility>(leafv_[ci][cand[i]]);
        Visibility t = static_cast<Visibility>(truth[i]);
        ErrorClass e = error_class(verdict, t);
        if ((e == ErrorClass::false_reject || e == ErrorClass::false_inside) && c == Config::perspective_transform) {
          t = oracle::truth(frustum_spec(view.clip, view.depth), Volume(world_.bvh.prim_boxes[cand[i]]));
          e = error_class(verdict, t);
        }
        switch (e) {
          case ErrorClass::false_reject: ++rec.c.false_reject; break;
          case ErrorClass::false_inside: ++rec.c.false_inside; break;
          case ErrorClass::false_intersect: ++rec.c.false_intersect; break;
          case ErrorClass::under_inside: ++rec.c.under_inside; break;
          default: break;
        }
        if (e == ErrorClass::false_reject || e == ErrorClass::false_inside)
          mismatch(ci, f, v, cam, view, spec, cand[i], verdict, t, e);
      }
    }
  }

  // The node that decided a leaf's wrong verdict: its highest visited ancestor that was outside
  // or inside.
  std::uint32_t decider(std::size_t ci, std::uint32_t leaf) const {
    std::uint32_t d = world_.leaf_node[leaf];
    const auto& nv = node_verdicts_[ci];
    for (std::int32_t n = static_cast<std::int32_t>(d); n >= 0; n = world_.parent[static_cast<std::size_t>(n)]) {
      const std::uint8_t x = nv.empty() ? 255 : nv[static_cast<std::size_t>(n)];
      if (x == static_cast<std::uint8_t>(Visibility::outside) || x == static_cast<std::uint8_t>(Visibility::inside))
        d = static_cast<std::uint32_t>(n);
    }
    return d;
  }

  void mismatch(std::size_t ci, int f, int v, const CameraFrame& cam, const View& view, const CaseFrustum& spec,
                std::uint32_t leaf, Visibility verdict, Visibility t, ErrorClass e) {
    const Config c = r_.configs[ci];
    Mismatch mm;
    mm.frame = f;
    mm.view = v;
    mm.config = c;
    mm.leaf = leaf;
    mm.error = to_string(e);
    mm.node = decider(ci, leaf);
    if (opt_.write_corpus && written_[ci] < opt_.corpus_per_config) {
      ++written_[ci];
      mm.file = write_mismatch(ci, mm, cam, view, spec, verdict, t);
    }
    r_.mismatches.push_back(mm);
  }

  // The deciding node's box as a corpus case, with the state of the configuration that produced
  // the verdict (plane-coherency cache, TR coherency, octant).
  std::string write_mismatch(std::size_t ci, const Mismatch& mm, const CameraFrame& cam, const View& view,
                             const CaseFrustum& spec, Visibility verdict, Visibility t) {
    const Config c = mm.config;
    Case cs;
    cs.id = fmt::format("scene-{}-{}-f{}-v{}-n{}", scene_.name, to_string(c), mm.frame, mm.view, mm.node);
    cs.frustum = c == Config::perspective_transform ? frustum_spec(view.clip, view.depth) : spec;
    cs.volume = world_.bvh.nodes[mm.node].box;
    cs.truth = oracle::truth(cs.frustum, cs.volume);
    cs.note = fmt::format("scene simulation: {} gave {} for leaf {} (truth {})", to_string(c),
                          std::string(cullproof::to_string(verdict)), mm.leaf, std::string(cullproof::to_string(t)));
    const HierarchyCuller& culler = cullers_[ci][static_cast<std::size_t>(mm.view)];
    const HierarchyFrame& st = culler.frame();
    const TrObjectState& trs = culler.tr_state(mm.node);
    json tr = {{"test_frame", trs.test_frame},
               {"outside_bits", trs.outside_bits},
               {"angle_at_test", trs.angle_at_test},
               {"p_value", std::vector<float>(trs.p_value, trs.p_value + 6)},
               {"n_value", std::vector<float>(trs.n_value, trs.n_value + 6)},
               {"box", box_json(trs.box)}};
    cs.extra = json{{"scene", scene_.file},
                    {"scene_name", scene_.name},
                    {"frame", mm.frame},
                    {"view", mm.view},
                    {"camera_motion", to_string(cam.motion)},
                    {"method", to_string(c)},
                    {"verdict", std::string(cullproof::to_string(verdict))},
                    {"error", mm.error},
                    {"leaf", mm.leaf},
                    {"leaf_box", box_json(world_.bvh.prim_boxes[mm.leaf])},
                    {"node", mm.node},
                    {"cached_state",
                     {{"plane_coherency_last_plane", culler.last_plane(mm.node)},
                      {"tr_used", st.tr_used},
                      {"tr_reason", st.tr_why},
                      {"octant_used", st.octant_used},
                      {"tr", tr}}}};
    const std::filesystem::path file = std::filesystem::path(opt_.corpus_dir) / (cs.id + ".json");
    std::filesystem::create_directories(file.parent_path());
    write_case_file(file, cs, true);
    return file.string();
  }

  const SceneDesc& scene_;
  World& world_;
  const SimulateOptions& opt_;
  SimResult& r_;
  std::vector<std::vector<HierarchyCuller>> cullers_;  // per configuration, per view
  std::vector<VisibleSet> outs_;
  std::vector<std::vector<std::uint8_t>> node_verdicts_;
  std::vector<std::vector<std::uint8_t>> leafv_;
  std::vector<int> written_;
  const std::uint32_t L_;
};

}  // namespace

SimResult simulate(const SceneDesc& scene_in, World& world, const SimulateOptions& opt) {
  const double t_start = now_ns();
  SceneDesc scene = scene_in;
  if (opt.frames > 0 && scene.camera.kind != PathKind::keyframes) scene.camera.frames = opt.frames;
  std::vector<CameraFrame> path = camera_path(scene, world);
  if (opt.frames > 0 && static_cast<int>(path.size()) > opt.frames) path.resize(static_cast<std::size_t>(opt.frames));

  SimResult r;
  r.scene = scene.name;
  r.file = scene.file;
  r.triangles = world.triangles;
  r.polygons = world.polygons;
  r.nodes = world.node_count();
  r.leaves = world.leaf_count();
  r.instances = world.instances.size();
  r.leaf_triangles = world.leaf_triangles;
  r.frames = static_cast<int>(path.size());
  r.views_per_frame = scene.projection.kind == ProjectionKind::stereo ? 2 : 1;
  r.optimisations = decide_optimisations(scene, world, path);
  for (int c = 0; c < kConfigCount; ++c) r.configs.push_back(static_cast<Config>(c));
  r.totals.assign(r.configs.size(), Counters{});

  Simulation sim(scene, world, opt, r);
  Progress progress{opt.progress, r.frames, "simulate " + scene.name};
  const oracle::Stats oracle_before = oracle::stats();
  for (int f = 0; f < r.frames; ++f) {
    std::vector<std::uint32_t> moved;
    if (!scene.moving.empty()) moved = move_objects(scene, world, f);
    const CameraFrame& cam = path[static_cast<std::size_t>(f)];
    sim.frame(f, cam, moved);
    progress.update(f + 1);
  }
  for (const FrameRecord& rec : r.records)
    for (std::size_t ci = 0; ci < r.configs.size(); ++ci)
      if (r.configs[ci] == rec.config) r.totals[ci].add(rec.c);
  r.oracle_calls = oracle::stats().calls - oracle_before.calls;
  r.wall_seconds = (now_ns() - t_start) * 1e-9;
  return r;
}

// ---------------------------------------------------------------------------------------------
// Output

void write_csv(const SimResult& r, std::ostream& out) {
  out << "scene,frame,view,motion,config,tr_used,octant_used,moved_nodes,nodes_visited,plane_tests,leaves,visible,"
         "inside,checked,false_reject,false_inside,false_intersect,under_inside,time_ns\n";
  for (const FrameRecord& x : r.records)
    out << r.scene << ',' << x.frame << ',' << x.view << ',' << to_string(x.motion) << ',' << to_string(x.config) << ','
        << x.tr_used << ',' << x.octant_used << ',' << x.moved_nodes << ',' << x.c.nodes_visited << ',' << x.c.plane_tests
        << ',' << x.c.leaves << ',' << x.c.visible << ',' << x.c.inside << ',' << x.c.checked << ',' << x.c.false_reject
        << ',' << x.c.false_inside << ',' << x.c.false_intersect << ',' << x.c.under_inside << ','
        << static_cast<std::uint64_t>(x.c.time_ns) << '\n';
}

namespace {
json counters_json(const Counters& c) {
  return json{{"nodes_visited", c.nodes_visited}, {"plane_tests", c.plane_tests},   {"leaves", c.leaves},
              {"visible", c.visible},             {"inside", c.inside},             {"checked", c.checked},
              {"false_reject", c.false_reject},   {"false_inside", c.false_inside}, {"false_intersect", c.false_intersect},
              {"under_inside", c.under_inside},   {"tr_frames", c.tr_frames},       {"octant_frames", c.octant_frames},
              {"time_ns", c.time_ns}};
}
}  // namespace

json to_json(const SimResult& r) {
  json j;
  j["scene"] = r.scene;
  j["file"] = r.file;
  j["world"] = {{"triangles", r.triangles}, {"polygons", r.polygons},       {"nodes", r.nodes},
                {"leaves", r.leaves},       {"instances", r.instances},     {"leaf_triangles", r.leaf_triangles},
                {"frames", r.frames},       {"views_per_frame", r.views_per_frame}};
  j["optimisations"] = json::array();
  for (const Optimisation& o : r.optimisations) j["optimisations"].push_back({{"name", o.name}, {"state", o.state}, {"why", o.why}});
  j["totals"] = json::object();
  for (std::size_t i = 0; i < r.configs.size(); ++i) j["totals"][to_string(r.configs[i])] = counters_json(r.totals[i]);
  j["frames"] = json::array();
  for (const FrameRecord& x : r.records) {
    json f = counters_json(x.c);
    f["frame"] = x.frame;
    f["view"] = x.view;
    f["motion"] = to_string(x.motion);
    f["config"] = to_string(x.config);
    f["tr_used"] = x.tr_used;
    f["octant_used"] = x.octant_used;
    f["moved_nodes"] = x.moved_nodes;
    j["frames"].push_back(std::move(f));
  }
  j["mismatches"] = json::array();
  for (const Mismatch& m : r.mismatches)
    j["mismatches"].push_back({{"frame", m.frame}, {"view", m.view}, {"config", to_string(m.config)}, {"leaf", m.leaf},
                               {"node", m.node}, {"error", m.error}, {"file", m.file}});
  j["oracle_calls"] = r.oracle_calls;
  j["wall_seconds"] = r.wall_seconds;
  return j;
}

void print_summary(const SimResult& r, std::ostream& out) {
  out << fmt::format("scene {} ({})\n", r.scene, r.file);
  out << fmt::format("  {} instances, {} polygons ({} triangles), {} hierarchy nodes, {} leaves of <= {} triangles\n",
                     r.instances, r.polygons, r.triangles, r.nodes, r.leaves, r.leaf_triangles);
  out << fmt::format("  {} frames x {} view(s)\n", r.frames, r.views_per_frame);
  out << "optimisations:\n";
  for (const Optimisation& o : r.optimisations) out << fmt::format("  {:<16} {:<9} {}\n", o.name, o.state, o.why);
  out << "per configuration (frames x views; us median: culling time per frame and view, including the per-frame set-up;\n"
         "Table 1's timing is `--table1`):\n";
  out << fmt::format("{:<22} {:>10} {:>10} {:>8} {:>9} {:>9} {:>8} {:>8} {:>9} {:>8} {:>9}\n", "configuration", "visited/f",
                     "tests/node", "culled", "checked", "false-rej", "false-in", "false-ix", "under-in", "TR frm", "us median");
  const double fv = std::max(1, r.frames * r.views_per_frame);
  for (std::size_t i = 0; i < r.configs.size(); ++i) {
    const Counters& c = r.totals[i];
    const bool baseline = r.configs[i] == Config::perspective_transform;
    // Median time per frame and view (a mean would be dominated by the odd preempted frame).
    std::vector<double> times;
    for (const FrameRecord& x : r.records)
      if (x.config == r.configs[i]) times.push_back(x.c.time_ns);
    std::sort(times.begin(), times.end());
    const double med = times.empty() ? 0.0 : times[times.size() / 2];
    out << fmt::format("{:<22} {:>10.1f} {:>10} {:>7.1f}% {:>9} {:>9} {:>8} {:>8} {:>9} {:>8} {:>9.2f}\n",
                       to_string(r.configs[i]), c.nodes_visited / fv,
                       baseline ? std::string("-") : fmt::format("{:.2f}", c.nodes_visited ? double(c.plane_tests) / c.nodes_visited : 0.0),
                       c.leaves ? 100.0 * double(c.leaves - c.visible) / double(c.leaves) : 0.0, c.checked, c.false_reject,
                       c.false_inside, c.false_intersect, c.under_inside, c.tr_frames, med * 1e-3);
  }
  std::uint64_t checked = 0;
  for (const Counters& c : r.totals) checked += c.checked;
  out << fmt::format("verification: {} leaf verdicts checked against the oracle ({} oracle calls), {} false rejects + false "
                     "insides, {} mismatches written\n",
                     checked, r.oracle_calls, r.forbidden_errors(),
                     std::count_if(r.mismatches.begin(), r.mismatches.end(), [](const Mismatch& m) { return !m.file.empty(); }));
  for (const Mismatch& m : r.mismatches)
    if (!m.file.empty()) out << fmt::format("  mismatch: frame {} view {} {} leaf {} {} -> {}\n", m.frame, m.view, to_string(m.config), m.leaf, m.error, m.file);
  out << fmt::format("wall time {:.2f} s\n", r.wall_seconds);
}

}  // namespace cullproof::sim

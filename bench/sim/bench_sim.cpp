// Time per frame of each culler configuration over a shipped scene's path (default
// corpus/scenes/table1-model3.json, or $CULLPROOF_BENCH_SCENE), each path kind of A&M §4.
// Every iteration runs the whole path from fresh state (coherence caches empty at frame 0), so
// the coherent configurations are measured as they work: across frames. Run from the source
// directory after scripts/fetch-meshes. `cullproof simulate --table1` reports the same as speedups.
#include "cullproof/sim/simulate.hpp"

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

using namespace cullproof;
using namespace cullproof::sim;

namespace {

struct Loaded {
  SceneDesc scene;
  std::unique_ptr<World> world;
  std::vector<std::vector<std::vector<CullView>>> views;  // [path kind][frame][view]
  std::string error;
};

const Loaded& loaded() {
  static const Loaded l = [] {
    Loaded x;
    try {
      const char* f = std::getenv("CULLPROOF_BENCH_SCENE");
      x.scene = load_scene(f ? f : "corpus/scenes/table1-model3.json");
      x.world = std::make_unique<World>(build_world(x.scene));
      for (PathKind k : {PathKind::navigation, PathKind::translation_rotation, PathKind::rotation, PathKind::translation}) {
        SceneDesc s = x.scene;
        s.camera.kind = k;
        std::vector<std::vector<CullView>> v;
        for (const CameraFrame& c : camera_path(s, *x.world)) {
          v.emplace_back();
          for (const View& one : frame_views(s.projection, c)) v.back().push_back(cull_view(one));
        }
        x.views.push_back(std::move(v));
      }
    } catch (const std::exception& e) {
      x.error = e.what();
    }
    return x;
  }();
  return l;
}

void BM_Path(benchmark::State& state) {
  const Loaded& l = loaded();
  if (!l.error.empty()) {
    state.SkipWithError(l.error.c_str());
    return;
  }
  const auto& views = l.views[static_cast<std::size_t>(state.range(0))];
  const Config c = static_cast<Config>(state.range(1));
  std::vector<HierarchyCuller> cullers;
  for (std::size_t v = 0; v < views.front().size(); ++v) cullers.emplace_back(c, l.world->bvh);
  VisibleSet out;
  for (auto _ : state) {
    for (HierarchyCuller& one : cullers) one.reset();
    for (const auto& frame : views)
      for (std::size_t v = 0; v < frame.size(); ++v) cullers[v].cull(frame[v], out);
    benchmark::DoNotOptimize(out.indices.data());
  }
  state.counters["s_per_frame"] = benchmark::Counter(static_cast<double>(views.size()),
                                                  benchmark::Counter::kIsIterationInvariantRate |
                                                      benchmark::Counter::kInvert);
  state.SetLabel(std::string(to_string(c)) + " path " + std::to_string(state.range(0) + 1));
}

void configs(benchmark::internal::Benchmark* b) {
  for (int path = 0; path < 4; ++path)
    for (Config c : {Config::perspective_transform, Config::basic_np, Config::pc_octant, Config::pc_tr,
                     Config::pc_octant_tr, Config::masking})
      b->Args({path, static_cast<int>(c)});
}

BENCHMARK(BM_Path)->Apply(configs)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

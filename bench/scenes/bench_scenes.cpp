// What judging a culling system costs, against what culling costs: frames of `clusters` scenes of
// 1,000, 100,000 and 1,000,000 objects (one frame each, static), culled by the built-in masking
// BVH (bvh-masked: its build once, then one cull per iteration) and judged exactly (the truth of
// every object against the frame's frustum, one object at a time and down the hierarchy as
// scenes::judge_run decides it).
//
// BM_Cull/N: one cull of the frame by bvh-masked (the BVH built outside the timing).
// BM_Judge/N: the exact truth of every object of the frame, one oracle::truth (filtered) each.
// BM_JudgeHierarchy/N: the same truths down the hierarchy of enclosing boxes (scenes::SceneTruths,
//   built outside the timing): a node decided inside or outside decides its objects, the
//   exact-certified cascade the objects no certified test decides.
// BM_JudgeRun/N: scenes::judge_run on the one-frame run: the system built and culled, the set
//   checked, the hierarchy built and decided, every object's error class.
// Counters: ns per object; visible_fraction of the frame; oracle calls and exact-certified
// decisions per object.
#include "cullproof/oracle/oracle.hpp"
#include "cullproof/scenes/scenes.hpp"
#include "cullproof/systems/system.hpp"

#include <benchmark/benchmark.h>

#include <map>

namespace {

using namespace cullproof;

const scenes::SceneRun& run_of(std::size_t objects) {
  static std::map<std::size_t, scenes::SceneRun> runs;
  auto it = runs.find(objects);
  if (it == runs.end()) it = runs.emplace(objects, scenes::draw_run("clusters", 1, 0, {objects, 1})).first;
  return it->second;
}

const System& masked() {
  static const System s = builtin_systems({"bvh-masked"}).front();
  return s;
}

void BM_Cull(benchmark::State& state) {
  const scenes::SceneRun& run = run_of(std::size_t(state.range(0)));
  const auto sys = masked().build(run.scene);
  VisibleSet out;
  for (auto _ : state) {
    out.clear();
    sys->cull(run.frames[0].view, out);
    benchmark::DoNotOptimize(out.indices.data());
  }
  state.counters["ns_per_object"] =
      benchmark::Counter(double(run.scene.objects.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["visible_fraction"] = double(out.indices.size()) / double(run.scene.objects.size());
}

void BM_Judge(benchmark::State& state) {
  const scenes::SceneRun& run = run_of(std::size_t(state.range(0)));
  const CaseFrustum& f = run.frames[0].view.frustum;
  std::size_t visible = 0;
  for (auto _ : state) {
    visible = 0;
    for (const SceneObject& o : run.scene.objects) visible += oracle::truth(f, o.world) != Visibility::outside;
    benchmark::DoNotOptimize(visible);
  }
  state.counters["ns_per_object"] =
      benchmark::Counter(double(run.scene.objects.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["visible_fraction"] = double(visible) / double(run.scene.objects.size());
}

void BM_JudgeHierarchy(benchmark::State& state) {
  const scenes::SceneRun& run = run_of(std::size_t(state.range(0)));
  std::vector<Volume> world;
  for (const SceneObject& o : run.scene.objects) world.push_back(o.world);
  scenes::SceneTruths truths(world);
  std::vector<Visibility> truth;
  const std::uint64_t before = truths.oracle_calls(), exact_before = truths.exact_decisions();
  std::uint64_t frames = 0;
  for (auto _ : state) {
    truths.decide(run.frames[0].view.frustum, truth);
    benchmark::DoNotOptimize(truth.data());
    ++frames;
  }
  state.counters["ns_per_object"] =
      benchmark::Counter(double(run.scene.objects.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["oracle_calls_per_object"] =
      double(truths.oracle_calls() - before) / double(frames) / double(run.scene.objects.size());
  state.counters["exact_per_object"] =
      double(truths.exact_decisions() - exact_before) / double(frames) / double(run.scene.objects.size());
}

void BM_JudgeRun(benchmark::State& state) {
  const scenes::SceneRun& run = run_of(std::size_t(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(scenes::judge_run(masked(), run).judged);
  state.counters["ns_per_object"] =
      benchmark::Counter(double(run.scene.objects.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

BENCHMARK(BM_Cull)->Arg(1000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Judge)->Arg(1000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_JudgeHierarchy)->Arg(1000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_JudgeRun)->Arg(1000)->Arg(100000)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace

// Throughput of culling shaders on the Vulkan device: the example shader
// (examples/shaders/plane-tests.glsl), the certified one beside it (what certainty costs), and the
// view-space sphere tests (the certified one among them), over frames of 1,024 random boxes or
// spheres near a symmetric frustum, asked as the campaign asks (Method::classify_frames: one dispatch per kind for all the
// frames), for 1 to 512 frames per dispatch. items/s is volumes per second of wall time (upload,
// dispatch, wait, read-back); device_ns_per_volume is the device's own time (its timestamps
// around the dispatch) per volume.
#include <benchmark/benchmark.h>

#include "cullproof/gpu/gpu.hpp"

#include <fstream>
#include <random>
#include <sstream>

namespace cullproof {
namespace {

constexpr std::size_t kVolumesPerFrame = 1024;

// The shaders measured, by index: their file, the kinds they take, whether spheres take the
// view-space form.
struct Spec {
  const char* stem;
  unsigned volumes;
  bool view_space;
};
constexpr Spec kShaders[] = {
    {"plane-tests", kSphereKind | kAabbKind, false},
    {"certified-plane-tests", kSphereKind | kAabbKind, false},
    {"view-symmetric-sphere", kSphereKind, true},
    {"projected-sphere", kSphereKind, true},
    {"certified-view-sphere", kSphereKind, true},
};

const Method& shader(int which) {
  static std::vector<Method> made;
  if (made.empty())
    for (const Spec& spec : kShaders) {
      std::ifstream in(std::string(CULLPROOF_SOURCE_DIR) + "/examples/shaders/" + spec.stem + ".glsl");
      std::stringstream text;
      text << in.rdbuf();
      MethodInfo info;
      info.name = std::string("glsl-") + spec.stem;
      info.claim = Claim::conservative;
      info.volumes = spec.volumes;
      made.push_back(gpu::make_shader_method(info, {text.str(), std::string(spec.stem) + ".glsl", spec.view_space}));
    }
  return made[std::size_t(which)];
}

template <class K>
void BM_Shader(benchmark::State& state, int which) {
  const std::size_t frames = std::size_t(state.range(0));
  const CaseFrustum f = frustum_spec(off_axis_projection(-1.0f, 1.0f, -0.6f, 0.6f, 0.5f, 100.0f), {});
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-60.0f, 60.0f), size(0.1f, 4.0f);
  std::vector<Volume> volumes;
  for (std::size_t i = 0; i < kVolumesPerFrame; ++i) {
    const glm::vec3 c(u(rng), u(rng), -std::abs(u(rng)));
    if constexpr (std::is_same_v<K, Aabb>) volumes.push_back(Aabb{c, c + glm::vec3(size(rng))});
    else volumes.push_back(Sphere{c, size(rng)});
  }
  std::vector<FrameRequest> requests(frames, FrameRequest{&f, volumes.data(), volumes.size()});
  std::vector<Answer> answers(frames * kVolumesPerFrame);
  const Method& m = shader(which);
  m.take_own_timing();
  for (auto _ : state) {
    m.classify_frames(requests.data(), requests.size(), answers.data());
    benchmark::DoNotOptimize(answers.data());
  }
  const auto [ns, counted] = m.take_own_timing();
  state.SetItemsProcessed(std::int64_t(state.iterations() * frames * kVolumesPerFrame));
  state.counters["device_ns_per_volume"] = counted ? ns / double(counted) : 0.0;
}

void BM_Boxes(benchmark::State& state, int which) { BM_Shader<Aabb>(state, which); }
void BM_Spheres(benchmark::State& state, int which) { BM_Shader<Sphere>(state, which); }

BENCHMARK_CAPTURE(BM_Boxes, plane_tests, 0)->RangeMultiplier(8)->Range(1, 512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spheres, plane_tests, 0)->RangeMultiplier(8)->Range(1, 512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Boxes, certified, 1)->Arg(1)->Arg(64)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spheres, certified, 1)->Arg(1)->Arg(64)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spheres, view_symmetric, 2)->Arg(1)->Arg(64)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spheres, projected, 3)->Arg(1)->Arg(64)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Spheres, certified_view, 4)->Arg(1)->Arg(64)->Arg(512)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cullproof

// Throughput of a culling shader on the Vulkan device: the example shader
// (examples/shaders/plane-tests.glsl) over frames of 1,024 random boxes or spheres near a
// frustum, asked as the campaign asks (Method::classify_frames: one dispatch per kind for all the
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

const Method& shader() {
  static const Method m = [] {
    std::ifstream in(std::string(CULLPROOF_SOURCE_DIR) + "/examples/shaders/plane-tests.glsl");
    std::stringstream text;
    text << in.rdbuf();
    MethodInfo info;
    info.name = "glsl-plane-tests";
    info.claim = Claim::conservative;
    info.volumes = kPointKind | kSphereKind | kAabbKind;
    return gpu::make_shader_method(info, {text.str(), "plane-tests.glsl"});
  }();
  return m;
}

template <class K>
void BM_Shader(benchmark::State& state) {
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
  const Method& m = shader();
  m.take_own_timing();
  for (auto _ : state) {
    m.classify_frames(requests.data(), requests.size(), answers.data());
    benchmark::DoNotOptimize(answers.data());
  }
  const auto [ns, counted] = m.take_own_timing();
  state.SetItemsProcessed(std::int64_t(state.iterations() * frames * kVolumesPerFrame));
  state.counters["device_ns_per_volume"] = counted ? ns / double(counted) : 0.0;
}

BENCHMARK_TEMPLATE(BM_Shader, Aabb)->RangeMultiplier(8)->Range(1, 512)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_Shader, Sphere)->RangeMultiplier(8)->Range(1, 512)->UseRealTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace cullproof

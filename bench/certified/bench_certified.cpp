// What certification costs: each certified test next to its plain float twin, on the same
// random near-frustum volumes, with the per-frame preparation (plane normalisation, certified
// bounds) done once outside the timed loop, as a culler does it per frame.
#include "cullproof/core/certified.hpp"
#include "cullproof/simd/certified_batch.hpp"
#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/core/exact.hpp"
#include "cullproof/core/frustum_build.hpp"

#include <benchmark/benchmark.h>
#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

using namespace cullproof;

namespace {

constexpr std::size_t kCount = 4096;

struct Data {
  glm::mat4 vp;
  Frustum planes, normalized;
  CertifiedFrustum cert;
  std::vector<Aabb> aabbs;
  std::vector<Obb> obbs;
  std::vector<Sphere> spheres;
};

// A camera 40 units from the origin; volumes of size 0.05..2 placed within a few sizes of a
// random frustum face (so every branch of the tests is taken).
const Data& data() {
  static const Data d = [] {
    Data x;
    PerspectiveCamera cam;
    cam.eye = {30.0f, 20.0f, 18.0f};
    cam.target = {0.0f, 0.0f, 0.0f};
    cam.fovy_degrees = 60.0f;
    cam.aspect = 1.6f;
    cam.near_dist = 0.5f;
    cam.far_dist = 200.0f;
    x.vp = view_projection(cam);
    x.planes = frustum_from_matrix(x.vp);
    x.normalized = x.planes.normalized();
    x.cert = certify_matrix(x.vp);
    const auto corners = frustum_corners(x.planes);
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (std::size_t i = 0; i < kCount; ++i) {
      // A point on a random face edge region: mix of corners, pushed out or in.
      const int a = int(u(rng) * 8) & 7, b = a ^ (1 << (int(u(rng) * 3) % 3));
      glm::dvec3 p = glm::mix(corners[std::size_t(a)], corners[std::size_t(b)], u(rng));
      p = glm::mix(p, frustum_center(x.planes), 0.3 * u(rng));
      const float s = float(0.05 + 2.0 * u(rng));
      const glm::vec3 c(p);
      x.aabbs.push_back(Aabb{c - glm::vec3(s), c + glm::vec3(s * 0.7f)});
      const glm::quat q = glm::normalize(glm::quat(float(u(rng) - 0.5), float(u(rng) - 0.5), float(u(rng) - 0.5), float(u(rng) - 0.5)));
      x.obbs.push_back(Obb{c, glm::mat3_cast(q), glm::vec3(s, s * 0.5f, s * 0.8f)});
      x.spheres.push_back(Sphere{c, s});
    }
    return x;
  }();
  return d;
}

template <class F>
void run(benchmark::State& state, F&& f) {
  unsigned sink = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kCount; ++i) sink += unsigned(f(i));
    benchmark::DoNotOptimize(sink);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kCount));
  state.counters["ns_per_test"] =
      benchmark::Counter(double(kCount), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_aabb_pn_vertex(benchmark::State& s) { run(s, [](std::size_t i) { return pn_vertex(data().planes, data().aabbs[i]); }); }
void BM_aabb_pn_vertex_certified(benchmark::State& s) {
  run(s, [](std::size_t i) { return certified_pn_vertex(data().cert, data().aabbs[i]); });
}
void BM_obb_pn_vertex(benchmark::State& s) { run(s, [](std::size_t i) { return obb_pn_vertex(data().planes, data().obbs[i]); }); }
void BM_obb_pn_vertex_certified(benchmark::State& s) {
  run(s, [](std::size_t i) { return certified_obb_pn_vertex(data().cert, data().obbs[i]); });
}
void BM_sphere_plane(benchmark::State& s) {
  run(s, [](std::size_t i) { return sphere_plane_test(data().normalized, data().spheres[i]); });
}
void BM_sphere_certified(benchmark::State& s) {
  run(s, [](std::size_t i) { return certified_sphere(data().cert, data().spheres[i]); });
}
// The exact family on the same OBBs (what accuracy costs). Hoff's tests get the
// frustum's apex (centre of projection) computed once per frame.
void BM_hoff96(benchmark::State& s) {
  static const glm::vec3 cop = *frustum_apex(data().planes);
  run(s, [](std::size_t i) { return *hoff96(data().planes, data().obbs[i], cop); });
}
void BM_hoff_exact(benchmark::State& s) {
  run(s, [](std::size_t i) { return *hoff_exact(data().planes, data().obbs[i]); });
}
void BM_pn_vertex_reverse(benchmark::State& s) {
  run(s, [](std::size_t i) { return pn_vertex_reverse(data().planes, data().obbs[i]); });
}
void BM_sat_exact(benchmark::State& s) {
  run(s, [](std::size_t i) { return *sat_classify(data().planes, data().obbs[i]); });
}
void BM_sat_certified(benchmark::State& s) {
  run(s, [](std::size_t i) { return *certified_sat(data().cert, data().obbs[i]); });
}

// 1M AABBs, structure of arrays, 64-byte aligned (see cull_batch.hpp), warm cache: the plain
// SIMD batch against the certified one.
struct Soa {
  static constexpr std::size_t kN = 1u << 20;
  std::vector<float> storage;
  AabbSoa boxes;
  std::vector<std::uint64_t> visible = std::vector<std::uint64_t>(bitset_words(kN));
  Soa() {
    storage.resize(6 * kN + 16);
    float* base = storage.data();
    while (reinterpret_cast<std::uintptr_t>(base) % 64) ++base;
    float* a[6];
    for (int k = 0; k < 6; ++k) a[k] = base + std::size_t(k) * kN;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> pos(-60, 60), size(0.05f, 2.0f);
    for (std::size_t i = 0; i < kN; ++i)
      for (int k = 0; k < 3; ++k) {
        const float c = pos(rng), h = size(rng);
        a[k][i] = c - h;
        a[3 + k][i] = c + h;
      }
    boxes = AabbSoa{a[0], a[1], a[2], a[3], a[4], a[5], kN};
  }
};
Soa& soa() {
  static Soa s;
  return s;
}

// The first state.range(0) boxes: 1M (24 MB, L3: the memory-bound case) and 32k (768 KB, L2:
// the compute-bound case).
void BM_batch_plain(benchmark::State& state) {
  Soa& s = soa();
  AabbSoa b = s.boxes;
  b.count = std::size_t(state.range(0));
  for (auto _ : state) {
    cull_aabbs_bitset(data().planes, b, s.visible.data());
    benchmark::DoNotOptimize(s.visible.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_box"] = benchmark::Counter(double(b.count), benchmark::Counter::kIsIterationInvariantRate |
                                                                         benchmark::Counter::kInvert);
}
void BM_batch_certified(benchmark::State& state) {
  Soa& s = soa();
  AabbSoa b = s.boxes;
  b.count = std::size_t(state.range(0));
  for (auto _ : state) {
    certified_cull_aabbs_bitset(data().cert, b, s.visible.data());
    benchmark::DoNotOptimize(s.visible.data());
    benchmark::ClobberMemory();
  }
  state.counters["ns_per_box"] = benchmark::Counter(double(b.count), benchmark::Counter::kIsIterationInvariantRate |
                                                                         benchmark::Counter::kInvert);
}

// Both batches in turn on the same boxes, each call timed: the ratio certified / plain of the
// summed times. Drift of a shared machine (10-20% between runs here) moves both calls of a pair
// alike, so this ratio is steadier than two separately timed benchmarks.
void BM_batch_certified_over_plain(benchmark::State& state) {
  Soa& s = soa();
  AabbSoa b = s.boxes;
  b.count = std::size_t(state.range(0));
  using clock = std::chrono::steady_clock;
  double plain = 0.0, cert = 0.0;
  for (auto _ : state) {
    const auto t0 = clock::now();
    cull_aabbs_bitset(data().planes, b, s.visible.data());
    benchmark::ClobberMemory();
    const auto t1 = clock::now();
    certified_cull_aabbs_bitset(data().cert, b, s.visible.data());
    benchmark::ClobberMemory();
    const auto t2 = clock::now();
    plain += std::chrono::duration<double>(t1 - t0).count();
    cert += std::chrono::duration<double>(t2 - t1).count();
    state.SetIterationTime(std::chrono::duration<double>(t2 - t0).count());
  }
  state.counters["certified_over_plain"] = cert / plain;
}

}  // namespace

// The machine is shared: with --benchmark_repetitions the minimum is the least disturbed run.
double min_of(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
BENCHMARK(BM_batch_plain)->Arg(1 << 20)->Arg(1 << 15)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);
BENCHMARK(BM_batch_certified)->Arg(1 << 20)->Arg(1 << 15)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);
BENCHMARK(BM_batch_certified_over_plain)->Arg(1 << 20)->Arg(1 << 15)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_aabb_pn_vertex);
BENCHMARK(BM_aabb_pn_vertex_certified);
BENCHMARK(BM_obb_pn_vertex);
BENCHMARK(BM_obb_pn_vertex_certified);
BENCHMARK(BM_sphere_plane);
BENCHMARK(BM_sphere_certified);
BENCHMARK(BM_hoff96);
BENCHMARK(BM_hoff_exact);
BENCHMARK(BM_pn_vertex_reverse);
BENCHMARK(BM_sat_exact);
BENCHMARK(BM_sat_certified);
BENCHMARK_MAIN();

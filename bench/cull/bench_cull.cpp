// Benchmarks of the fast culler family. One binary, the same data for all methods:
//  - ns per test for every method on random near-frustum volumes (direct API with per-frame
//    set-up hoisted, and through the method interface, as verify times them);
//  - batch cull of 1M AABBs (SoA, warm cache): SIMD vs the scalar n/p loop vs a plain SoA loop;
//  - hierarchy of 100k leaves: ns per visited node, and the all-visible traversal vs the flat
//    batch scan of the same leaves.
#include <benchmark/benchmark.h>

#include "cullproof/core/cull.hpp"
#include "cullproof/simd/cull_batch.hpp"
#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/simd/bvh_wide.hpp"
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/methods/methods.hpp"

#include <glm/ext/matrix_transform.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>

namespace cullproof {
namespace {

// ---------------------------------------------------------------------------------------------
// Shared data

PerspectiveCamera bench_camera() {
  PerspectiveCamera c;
  c.fovy_degrees = 60;
  c.aspect = 16.0f / 9.0f;
  c.near_dist = 0.1f;
  c.far_dist = 100;
  c.eye = {1, 2, 3};
  c.target = {10, 0, -40};
  return c;
}

struct Data {
  PerspectiveCamera cam = bench_camera();
  glm::mat4 matrix = view_projection(cam);
  // Planes from the camera in double (Lighthouse3D geometric approach): symmetric to 1e-5, so
  // the octant and radar methods apply (the float matrix extraction is not, at near = 0.1).
  Frustum f = frustum_from_camera(cam);
  CaseFrustum spec = frustum_spec(f);
  Frustum fn = f.normalized();
  std::vector<Aabb> boxes;
  std::vector<Sphere> spheres;
  std::vector<Point> points;
  std::vector<Obb> obbs;
  std::vector<Volume> vol_box, vol_sphere, vol_point, vol_obb;
};

// Random boxes near the frustum: centres uniform in its bounding box grown by 20%, extents in
// [0, 2 * scale] (scale = 1% of the frustum size): a mix of outside, straddling and inside.
std::vector<Aabb> near_frustum_boxes(const Frustum& f, std::size_t n, std::uint32_t seed) {
  const FrustumBounds fb = frustum_bounds(f);
  const glm::vec3 lo = fb.box.min, hi = fb.box.max, pad = 0.2f * (hi - lo);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  const float scale = 0.01f * glm::length(hi - lo);
  std::vector<Aabb> out(n);
  for (auto& b : out) {
    const glm::vec3 c = lo - pad + glm::vec3(u(rng), u(rng), u(rng)) * (hi - lo + 2.0f * pad);
    const glm::vec3 h = glm::vec3(u(rng), u(rng), u(rng)) * scale;
    b = Aabb{c - h, c + h};
  }
  return out;
}

const Data& data() {
  static const Data d = [] {
    Data x;
    x.boxes = near_frustum_boxes(x.f, 4096, 1);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> u(-1, 1);
    for (const Aabb& b : x.boxes) {
      x.spheres.push_back(Sphere{b.center(), glm::length(b.half_extent())});
      x.points.push_back(b.center());
      const glm::mat3 r(glm::rotate(glm::mat4(1.0f), 3.0f * u(rng), glm::normalize(glm::vec3(u(rng), u(rng), 1.0f))));
      x.obbs.push_back(Obb{b.center(), r, b.half_extent()});
    }
    for (std::size_t i = 0; i < x.boxes.size(); ++i) {
      x.vol_box.emplace_back(x.boxes[i]);
      x.vol_sphere.emplace_back(x.spheres[i]);
      x.vol_point.emplace_back(x.points[i]);
      x.vol_obb.emplace_back(x.obbs[i]);
    }
    int counts[3] = {0, 0, 0};
    for (const Aabb& b : x.boxes) ++counts[static_cast<int>(pn_vertex(x.f, b))];
    std::printf("near-frustum boxes: %d outside, %d intersecting, %d inside (pn-vertex)\n", counts[0], counts[1],
                counts[2]);
    return x;
  }();
  return d;
}

void per_test(benchmark::State& state, std::size_t n) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * n));
  state.counters["ns_per_test"] = benchmark::Counter(double(state.iterations()) * double(n),
                                                     benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Runs fn(i) over the 4096 items, summing verdicts so nothing is optimised away.
template <class Fn>
void loop(benchmark::State& state, Fn fn) {
  const std::size_t n = data().boxes.size();
  for (auto _ : state) {
    unsigned sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += static_cast<unsigned>(fn(i));
    benchmark::DoNotOptimize(sum);
  }
  per_test(state, n);
}

// ---------------------------------------------------------------------------------------------
// Direct API, per-frame set-up hoisted

void register_direct() {
  const Data& d = data();
  auto reg = [](const char* name, auto fn) {
    benchmark::RegisterBenchmark((std::string("direct/") + name).c_str(), [fn](benchmark::State& s) { loop(s, fn); });
  };
  reg("point-plane", [&d](std::size_t i) { return point_plane_test(d.f, d.points[i]); });
  static const RadarCamera radar = *radar_camera_from_frustum(d.f);
  static const RadarCamera radar_pub = *radar_camera_from_frustum(d.f, true);
  reg("radar-point", [&d](std::size_t i) { return radar_point(radar, d.points[i]); });
  reg("sphere-plane", [&d](std::size_t i) { return sphere_plane_test(d.fn, d.spheres[i]); });
  reg("radar-sphere", [&d](std::size_t i) { return radar_sphere(radar, d.spheres[i]); });
  reg("radar-sphere-as-published", [&d](std::size_t i) { return radar_sphere(radar_pub, d.spheres[i]); });
  reg("eight-corner", [&d](std::size_t i) { return aabb_eight_corner(d.f, d.boxes[i]); });
  reg("pn-vertex", [&d](std::size_t i) { return pn_vertex(d.f, d.boxes[i]); });
  reg("pn-vertex-index", [&d](std::size_t i) { return pn_vertex_index(d.f, d.boxes[i]); });
  reg("p-vertex-post", [&d](std::size_t i) { return p_vertex_post(d.f, d.boxes[i]); });
  static const PnLut lut = make_pn_lut(d.f);
  reg("pn-vertex-lut", [&d](std::size_t i) { return pn_vertex_lut(lut, d.boxes[i]); });
  reg("perspective-transform-as-published",
      [&d](std::size_t i) { return perspective_transform_as_published(d.matrix, {}, d.boxes[i]); });
  reg("perspective-transform", [&d](std::size_t i) { return perspective_transform(d.matrix, {}, d.boxes[i]); });
  reg("obb-pn-vertex", [&d](std::size_t i) { return obb_pn_vertex(d.f, d.obbs[i]); });
  reg("box-sphere-then-pn-vertex", [&d](std::size_t i) {
    if (auto r = box_sphere_stage(d.fn, d.boxes[i])) return *r;
    return pn_vertex(d.f, d.boxes[i]);
  });
  reg("box-sphere-only", [&d](std::size_t i) {
    if (auto r = box_sphere_stage(d.fn, d.boxes[i])) return *r;
    return Visibility::intersecting;
  });
  static const FrustumBounds fb = frustum_bounds(d.f);
  reg("frustum-sphere-then-pn-vertex", [&d](std::size_t i) {
    if (auto r = frustum_sphere_stage(fb, d.boxes[i])) return *r;
    return pn_vertex(d.f, d.boxes[i]);
  });
  reg("frustum-aabb-then-pn-vertex", [&d](std::size_t i) {
    if (auto r = frustum_aabb_stage(fb, d.boxes[i])) return *r;
    return pn_vertex(d.f, d.boxes[i]);
  });
  // Stateful: steady state of a still camera (caches warmed by the previous frame).
  static std::vector<PlaneCoherencyCache> pc(d.boxes.size());
  for (std::size_t i = 0; i < d.boxes.size(); ++i) plane_coherency_test(d.f, d.boxes[i], pc[i]);
  reg("plane-coherency", [&d](std::size_t i) { return plane_coherency_test(d.f, d.boxes[i], pc[i]); });
  static const OctantCuller oct(d.f);
  reg("octant", [&d](std::size_t i) { return oct.classify(d.boxes[i]); });
  reg("octant-corrected", [&d](std::size_t i) { return oct.classify_corrected(d.boxes[i]); });
  // TR coherency over a pure translation path: every frame moves the camera by a small step.
  benchmark::RegisterBenchmark("direct/tr-coherency(translation path)", [](benchmark::State& s) {
    const Data& dd = data();
    TrCoherencyCuller c;
    std::vector<TrObjectState> st(dd.boxes.size());
    Frustum g = dd.f;
    c.begin_frame(g);
    for (std::size_t i = 0; i < dd.boxes.size(); ++i) c.classify(dd.boxes[i], st[i]);
    const glm::vec3 step(0.001f, 0.0f, -0.002f);
    for (auto _ : s) {
      for (int k = 0; k < 6; ++k) g[k].d -= dot(g[k].n, step);
      c.begin_frame(g);
      unsigned sum = 0;
      for (std::size_t i = 0; i < dd.boxes.size(); ++i) sum += static_cast<unsigned>(c.classify(dd.boxes[i], st[i]));
      benchmark::DoNotOptimize(sum);
    }
    per_test(s, dd.boxes.size());
  });
  benchmark::RegisterBenchmark("direct/tr-coherency(full tests)", [](benchmark::State& s) {
    const Data& dd = data();
    TrCoherencyCuller c;
    std::vector<TrObjectState> st(dd.boxes.size());
    for (auto _ : s) {
      c.begin_frame(dd.f);  // the same frustum, but every state is from two frames ago
      c.begin_frame(dd.f);
      unsigned sum = 0;
      for (std::size_t i = 0; i < dd.boxes.size(); ++i) {
        st[i].test_frame = 0;  // forget: full test
        sum += static_cast<unsigned>(c.classify(dd.boxes[i], st[i]));
      }
      benchmark::DoNotOptimize(sum);
    }
    per_test(s, dd.boxes.size());
  });
}

// Through the method interface, as `cullproof verify` times every method: prepare once per
// frame (set-up/NAME), then classify_batch over the frame's volumes (interface/NAME: the
// method's array form where it has one, else its classify in a loop over the array).
void register_interface() {
  for (const Method& m : builtin_methods()) {
    benchmark::RegisterBenchmark(("interface/" + m.name).c_str(), [&m](benchmark::State& s) {
      const Data& dd = data();
      const auto p = m.prepare(dd.spec);
      if (!p) {
        s.SkipWithError("does not apply to the benchmark frustum");
        return;
      }
      std::vector<Answer> out(dd.boxes.size());
      for (auto _ : s) {
        if (m.volumes & kObbKind) p->classify_batch(dd.obbs.data(), dd.obbs.size(), out.data());
        else if (m.volumes & kAabbKind) p->classify_batch(dd.boxes.data(), dd.boxes.size(), out.data());
        else if (m.volumes & kSphereKind) p->classify_batch(dd.spheres.data(), dd.spheres.size(), out.data());
        else p->classify_batch(dd.points.data(), dd.points.size(), out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
      }
      per_test(s, dd.boxes.size());
    });
    benchmark::RegisterBenchmark(("set-up/" + m.name).c_str(), [&m](benchmark::State& s) {
      const Data& dd = data();
      for (auto _ : s) {
        auto p = m.prepare(dd.spec);
        benchmark::DoNotOptimize(p.get());
      }
    });
  }
}

// ---------------------------------------------------------------------------------------------
// Batch: 1M AABBs, SoA, warm cache (24 MB, within L3 after the first iteration)

// 64-byte aligned float storage: a std::vector of a few MB starts 16 bytes past a page
// boundary (malloc header), which makes every 64-byte SIMD load straddle two cache lines
// (measured here: 0.60 ms aligned vs 0.71 ms unaligned for 1M boxes). The batch API accepts any
// alignment; aligned SoA arrays are what a renderer's culling data should use.
template <class T>
struct Aligned64 {
  using value_type = T;
  Aligned64() = default;
  template <class U>
  Aligned64(const Aligned64<U>&) noexcept {}
  T* allocate(std::size_t n) {
    void* p = std::aligned_alloc(64, (n * sizeof(T) + 63) / 64 * 64);
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }
  template <class U>
  bool operator==(const Aligned64<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const Aligned64<U>&) const noexcept { return false; }
};
using FloatArray = std::vector<float, Aligned64<float>>;

struct Soa {
  FloatArray a[6];
  FloatArray sx, sy, sz, sr;
  AabbSoa view() const {
    return AabbSoa{a[0].data(), a[1].data(), a[2].data(), a[3].data(), a[4].data(), a[5].data(), a[0].size()};
  }
  SphereSoa spheres() const { return SphereSoa{sx.data(), sy.data(), sz.data(), sr.data(), sx.size()}; }
};

const Soa& soa_1m() {
  static const Soa s = [] {
    Soa x;
    const auto boxes = near_frustum_boxes(data().f, 1u << 20, 3);
    for (int k = 0; k < 6; ++k) x.a[k].reserve(boxes.size());
    for (const Aabb& b : boxes) {
      for (int k = 0; k < 3; ++k) {
        x.a[k].push_back(b.min[k]);
        x.a[3 + k].push_back(b.max[k]);
      }
      const glm::vec3 c = b.center();
      x.sx.push_back(c.x); x.sy.push_back(c.y); x.sz.push_back(c.z);
      x.sr.push_back(glm::length(b.half_extent()));
    }
    return x;
  }();
  return s;
}

// The machine is shared: with --benchmark_repetitions the minimum is the least disturbed run.
double min_of(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }

void batch_counters(benchmark::State& s, std::size_t n) {
  s.SetItemsProcessed(static_cast<std::int64_t>(s.iterations() * n));
  s.counters["ns_per_box"] = benchmark::Counter(double(s.iterations()) * double(n),
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_batch_aabb_simd_bitset(benchmark::State& s) {
  const Soa& x = soa_1m();
  AabbSoa v = x.view();
  v.count = static_cast<std::size_t>(s.range(0));  // the first N boxes
  std::vector<std::uint64_t> bits(bitset_words(v.count));
  for (auto _ : s) {
    cull_aabbs_bitset(data().f, v, bits.data());
    benchmark::DoNotOptimize(bits.data());
    benchmark::ClobberMemory();
  }
  batch_counters(s, v.count);
  s.SetLabel(batch_simd_target());
}
// 1M boxes (24 MB, L3) is the target; 32k boxes (768 kB, L2) shows the compute cost alone.
BENCHMARK(BM_batch_aabb_simd_bitset)->Arg(1 << 20)->Arg(1 << 15)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

void BM_batch_aabb_simd_classify(benchmark::State& s) {
  const Soa& x = soa_1m();
  std::vector<std::uint64_t> vis(bitset_words(x.a[0].size())), ins(vis.size());
  for (auto _ : s) {
    classify_aabbs_bitset(data().f, x.view(), vis.data(), ins.data());
    benchmark::DoNotOptimize(vis.data());
    benchmark::DoNotOptimize(ins.data());
    benchmark::ClobberMemory();
  }
  batch_counters(s, x.a[0].size());
}
BENCHMARK(BM_batch_aabb_simd_classify)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

void BM_batch_aabb_simd_indices(benchmark::State& s) {
  const Soa& x = soa_1m();
  std::vector<std::uint32_t> idx(x.a[0].size());
  for (auto _ : s) {
    benchmark::DoNotOptimize(cull_aabbs_indices(data().f, x.view(), idx.data()));
    benchmark::ClobberMemory();
  }
  batch_counters(s, x.a[0].size());
}
BENCHMARK(BM_batch_aabb_simd_indices)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

void BM_batch_aabb_scalar_pn_loop(benchmark::State& s) {
  const Soa& x = soa_1m();
  std::vector<std::uint64_t> bits(bitset_words(x.a[0].size()));
  for (auto _ : s) {
    cull_aabbs_bitset_scalar(data().f, x.view(), bits.data());
    benchmark::DoNotOptimize(bits.data());
    benchmark::ClobberMemory();
  }
  batch_counters(s, x.a[0].size());
}
BENCHMARK(BM_batch_aabb_scalar_pn_loop)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

// The reference of the issue: a plain SoA loop the compiler may vectorise (one byte per box,
// min/max chosen per plane by a loop-invariant select), built with the project's flags only
// (no -march: SSE2 for GCC's auto-vectoriser).
void BM_batch_aabb_plain_soa_loop(benchmark::State& s) {
  const Soa& x = soa_1m();
  const Frustum& f = data().f;
  const std::size_t n = x.a[0].size();
  std::vector<std::uint8_t> out(n);
  float a[6], b[6], c[6], dd[6];
  bool sx[6], sy[6], sz[6];
  for (int k = 0; k < 6; ++k) {
    a[k] = f[k].n.x; b[k] = f[k].n.y; c[k] = f[k].n.z; dd[k] = f[k].d;
    sx[k] = a[k] > 0; sy[k] = b[k] > 0; sz[k] = c[k] > 0;
  }
  const float* __restrict mnx = x.a[0].data();
  const float* __restrict mny = x.a[1].data();
  const float* __restrict mnz = x.a[2].data();
  const float* __restrict mxx = x.a[3].data();
  const float* __restrict mxy = x.a[4].data();
  const float* __restrict mxz = x.a[5].data();
  std::uint8_t* __restrict o = out.data();
  for (auto _ : s) {
    for (std::size_t i = 0; i < n; ++i) {
      const float x0 = mnx[i], y0 = mny[i], z0 = mnz[i], x1 = mxx[i], y1 = mxy[i], z1 = mxz[i];
      int vis = 1;
      for (int k = 0; k < 6; ++k)
        vis &= ((a[k] * (sx[k] ? x1 : x0) + b[k] * (sy[k] ? y1 : y0)) + c[k] * (sz[k] ? z1 : z0)) + dd[k] >= 0.0f;
      o[i] = static_cast<std::uint8_t>(vis);
    }
    benchmark::DoNotOptimize(o);
    benchmark::ClobberMemory();
  }
  batch_counters(s, n);
}
BENCHMARK(BM_batch_aabb_plain_soa_loop)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

void BM_batch_sphere_simd_bitset(benchmark::State& s) {
  const Soa& x = soa_1m();
  std::vector<std::uint64_t> bits(bitset_words(x.sx.size()));
  for (auto _ : s) {
    cull_spheres_bitset(data().fn, x.spheres(), bits.data());
    benchmark::DoNotOptimize(bits.data());
    benchmark::ClobberMemory();
  }
  batch_counters(s, x.sx.size());
}
BENCHMARK(BM_batch_sphere_simd_bitset)->Unit(benchmark::kMillisecond)->ComputeStatistics("min", min_of);

// ---------------------------------------------------------------------------------------------
// Hierarchy: 100k leaves

struct Scene {
  std::vector<Aabb> boxes;
  Bvh bvh;
  Bvh4 bvh4;  // collapsed from bvh
  Bvh8 bvh8;  // collapsed from bvh
  Soa soa;
  Frustum all_visible;
};

const Scene& scene_100k() {
  static const Scene s = [] {
    Scene x;
    // A city-like scene: 100k small boxes on a 400 x 400 ground patch, heights up to 20.
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(0, 1);
    for (int i = 0; i < 100000; ++i) {
      const glm::vec3 lo(400 * u(rng) - 200, 0, 400 * u(rng) - 200);
      x.boxes.push_back(Aabb{lo, lo + glm::vec3(0.5f + 2 * u(rng), 1 + 19 * u(rng), 0.5f + 2 * u(rng))});
    }
    x.bvh = build_bvh(x.boxes, 1);
    x.bvh4 = build_bvh4(x.bvh);
    x.bvh8 = build_bvh8(x.bvh);
    for (const Aabb& b : x.boxes)
      for (int k = 0; k < 3; ++k) {
        x.soa.a[k].push_back(b.min[k]);
        x.soa.a[3 + k].push_back(b.max[k]);
      }
    // A camera high above looking down with a wide frustum: every leaf inside.
    PerspectiveCamera c;
    c.fovy_degrees = 120;
    c.aspect = 1;
    c.near_dist = 1;
    c.far_dist = 2000;
    c.eye = {0, 600, 0};
    c.target = {0, 0, 0};
    c.up = {0, 0, -1};
    x.all_visible = frustum_from_camera(c);
    return x;
  }();
  return s;
}

Frustum street_frustum() {
  PerspectiveCamera c;
  c.fovy_degrees = 60;
  c.aspect = 16.0f / 9.0f;
  c.near_dist = 0.5f;
  c.far_dist = 300;
  c.eye = {-150, 30, 150};
  c.target = {0, 0, 0};
  return frustum_from_camera(c);
}

Frustum narrow_frustum() {
  PerspectiveCamera c;
  c.fovy_degrees = 15;
  c.aspect = 16.0f / 9.0f;
  c.near_dist = 0.5f;
  c.far_dist = 300;
  c.eye = {-150, 30, 150};
  c.target = {0, 0, 0};
  return frustum_from_camera(c);
}

// view: 0 street (wide), 1 everything visible, 2 narrow (few visible: traversal cost alone).
// kKind: 0 plain, 1 masked, 2 coherent (binary BVH), 3 / 4 masked on the 4- / 8-wide BVH (a
// visited node there is a child lane tested, see cull_bvh4_masked; compare the absolute time too),
// 5 / 6 the same with the visible set written as runs (VisibleRuns) instead of indices.
void BM_bvh(benchmark::State& s, int kKind, int view) {
  const Scene& x = scene_100k();
  const Frustum f = view == 1 ? x.all_visible : view == 2 ? narrow_frustum() : street_frustum();
  VisibleSet out;
  out.indices.reserve(x.boxes.size());
  out.verdicts.reserve(x.boxes.size());
  VisibleRuns runs;
  runs.runs.reserve(x.boxes.size());
  BvhCoherency cache;
  CullStats st;
  if (kKind == 2) cull_bvh_coherent(f, x.bvh, cache, out, st);  // warm: a still camera
  CullStats total;
  for (auto _ : s) {
    if (kKind == 0) cull_bvh_plain(f, x.bvh, out, total);
    if (kKind == 1) cull_bvh_masked(f, x.bvh, out, total);
    if (kKind == 2) cull_bvh_coherent(f, x.bvh, cache, out, total);
    if (kKind == 3) cull_bvh4_masked(f, x.bvh4, out, total);
    if (kKind == 4) cull_bvh8_masked(f, x.bvh8, out, total);
    if (kKind == 5) cull_bvh4_masked(f, x.bvh4, runs, total);
    if (kKind == 6) cull_bvh8_masked(f, x.bvh8, runs, total);
    benchmark::DoNotOptimize(out.indices.data());
    benchmark::DoNotOptimize(runs.runs.data());
  }
  const double it = double(s.iterations());
  s.counters["visible"] = double(kKind >= 5 ? runs.count() : out.indices.size());
  if (kKind >= 5) s.counters["runs"] = double(runs.runs.size());
  s.counters["nodes_visited"] = double(total.nodes_visited) / it;
  s.counters["plane_tests"] = double(total.plane_tests) / it;
  s.counters["ns_per_node"] = benchmark::Counter(double(total.nodes_visited), benchmark::Counter::kIsRate |
                                                                             benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_bvh, plain_street, 0, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, masked_street, 1, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, coherent_street, 2, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, plain_all_visible, 0, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, masked_all_visible, 1, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, plain_narrow, 0, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, masked_narrow, 1, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, coherent_narrow, 2, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_masked_street, 3, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_masked_all_visible, 3, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_masked_narrow, 3, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_masked_street, 4, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_masked_all_visible, 4, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_masked_narrow, 4, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_runs_street, 5, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_runs_all_visible, 5, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide4_runs_narrow, 5, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_runs_street, 6, 0)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_runs_all_visible, 6, 1)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_bvh, wide8_runs_narrow, 6, 2)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);

// The flat batch scan of the same 100k leaves (bitset, and indices like the traversal output).
void BM_flat_batch_100k_bitset(benchmark::State& s, bool all_visible) {
  const Scene& x = scene_100k();
  const Frustum f = all_visible ? x.all_visible : street_frustum();
  std::vector<std::uint64_t> bits(bitset_words(x.boxes.size()));
  for (auto _ : s) {
    cull_aabbs_bitset(f, x.soa.view(), bits.data());
    benchmark::DoNotOptimize(bits.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK_CAPTURE(BM_flat_batch_100k_bitset, street, false)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_flat_batch_100k_bitset, all_visible, true)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);

void BM_flat_batch_100k_indices(benchmark::State& s, bool all_visible) {
  const Scene& x = scene_100k();
  const Frustum f = all_visible ? x.all_visible : street_frustum();
  std::vector<std::uint32_t> idx(x.boxes.size());
  for (auto _ : s) {
    benchmark::DoNotOptimize(cull_aabbs_indices(f, x.soa.view(), idx.data()));
    benchmark::ClobberMemory();
  }
}
BENCHMARK_CAPTURE(BM_flat_batch_100k_indices, street, false)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);
BENCHMARK_CAPTURE(BM_flat_batch_100k_indices, all_visible, true)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", min_of);

}  // namespace
}  // namespace cullproof

int main(int argc, char** argv) {
  cullproof::register_direct();
  cullproof::register_interface();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

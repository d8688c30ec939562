// What exact culling costs: the certified-exact cascade (cullproof/simd/exact_certified.hpp) beside the
// certified n/p-vertex tests it starts from, per test, with the per-frame set-up hoisted, on the
// frames `cullproof verify` times (gen::draw_frame: one camera per frame, 1,024 volumes of the
// distribution around it; 8 frames per distribution, seed 1), for each generic distribution and
// for all of them pooled; the array forms through the method interface; and, per distribution
// of the campaign's cases, how often each stage decides and what a volume costs when the exact
// stage has to run.
//
//   generic/<kind>/<distribution>/<method>   ns per test (counter ns_per_test)
//   ratio/<kind>/<distribution>               both tests in turn on the same frames, each pass
//                                            timed: exact over certified of the summed times
//                                            (a shared machine's drift moves both alike)
//   batch/<kind>/<distribution>/<method>     ns per volume through classify_batch
//   batch-ratio/<kind>/<distribution>         the certified and exact array forms through
//                                            classify_batch in turn, frame by frame, each call
//                                            timed: exact over certified of the summed times
//   stages/<kind>/<distribution>             counters planes, axes, exact (fractions of the
//                                            volumes decided by each stage) and cases; the timed
//                                            loop classifies the volumes that reach the exact
//                                            stage (ns_per_test: the cost of one such volume)
//   passes/<aabb|sphere>/<distribution>      the array forms' passes on the generic frames:
//                                            counters, fractions of all volumes, of what each
//                                            leaves open (nothing is timed)
//
// --simd_target=NAME (a Highway target this machine runs: AVX3, AVX2, SSE4, ...) runs the
// vector code of both the exact and the certified methods as on a machine whose best is NAME.
#include "cullproof/simd/batch_adapter.hpp"       // AoS to SoA chunks (not installed)
#include "cullproof/simd/batch_combinations.hpp"  // the AABB array form's float passes (not installed)
#include "cullproof/simd/batch_spheres.hpp"       // the sphere array form's double pass (not installed)
#include "cullproof/core/certified.hpp"
#include "cullproof/simd/certified_batch.hpp"
#include "cullproof/simd/exact_certified.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/methods/methods.hpp"

#include <benchmark/benchmark.h>
#include <hwy/targets.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <vector>

using namespace cullproof;

namespace {

constexpr std::uint64_t kSeed = 1;
constexpr int kFrames = 8;
constexpr std::size_t kFrameSize = 1024;
constexpr std::size_t kStageCases = 20000;

template <class K>
struct Frames {
  std::vector<CaseFrustum> frustum;
  std::vector<CertifiedFrustum> cert;
  std::vector<ExactCertifiedFrustum> exact;
  std::vector<std::vector<K>> volumes;
  std::size_t count = 0;
};

template <class K>
unsigned kind_bit();
template <>
unsigned kind_bit<Aabb>() { return kAabbKind; }
template <>
unsigned kind_bit<Obb>() { return kObbKind; }
template <>
unsigned kind_bit<Sphere>() { return kSphereKind; }

// The frames of one distribution (or of every generic one, pooled: `d` empty).
template <class K>
const Frames<K>& frames(const std::string& name) {
  static std::map<std::string, Frames<K>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Frames<K> out;
  const std::vector<gen::Distribution> ds =
      name == "all-generic" ? gen::generic_distributions() : gen::parse_distributions(name);
  for (gen::Distribution d : ds)
    for (int i = 0; i < kFrames; ++i) {
      const gen::Frame fr = gen::draw_frame(d, kSeed, std::uint64_t(i), kFrameSize, kind_bit<K>());
      if (fr.volumes.empty()) continue;
      out.frustum.push_back(fr.frustum);
      out.cert.push_back(certify(fr.frustum));
      out.exact.push_back(prepare_exact_certified(fr.frustum));
      std::vector<K> v;
      for (const Volume& x : fr.volumes) v.push_back(std::get<K>(x));
      out.count += v.size();
      out.volumes.push_back(std::move(v));
    }
  return cache.emplace(name, std::move(out)).first->second;
}

void per_test(benchmark::State& s, std::size_t n) {
  s.counters["ns_per_test"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// fn(frame index, volume) -> Visibility, over every frame's volumes.
template <class K, class Fn>
void run(benchmark::State& s, const Frames<K>& fr, Fn&& fn) {
  unsigned sink = 0;
  for (auto _ : s) {
    for (std::size_t f = 0; f < fr.volumes.size(); ++f)
      for (const K& v : fr.volumes[f]) sink += unsigned(fn(f, v));
    benchmark::DoNotOptimize(sink);
  }
  per_test(s, fr.count);
}

std::vector<std::string> distributions() {
  std::vector<std::string> out{"all-generic"};
  for (gen::Distribution d : gen::generic_distributions()) out.emplace_back(gen::to_string(d));
  return out;
}

void register_generic() {
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark(("generic/aabb/" + d + "/pn-vertex-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Aabb>(d);
      run(s, fr, [&](std::size_t f, const Aabb& b) { return certified_pn_vertex(fr.cert[f], b); });
    });
    benchmark::RegisterBenchmark(("generic/aabb/" + d + "/aabb-exact-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Aabb>(d);
      run(s, fr, [&](std::size_t f, const Aabb& b) { return exact_certified_aabb(fr.exact[f], b); });
    });
    benchmark::RegisterBenchmark(("generic/obb/" + d + "/obb-pn-vertex-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Obb>(d);
      run(s, fr, [&](std::size_t f, const Obb& b) { return certified_obb_pn_vertex(fr.cert[f], b); });
    });
    benchmark::RegisterBenchmark(("generic/obb/" + d + "/obb-exact-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Obb>(d);
      run(s, fr, [&](std::size_t f, const Obb& b) { return exact_certified_obb(fr.exact[f], b); });
    });
    benchmark::RegisterBenchmark(("generic/sphere/" + d + "/sphere-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Sphere>(d);
      run(s, fr, [&](std::size_t f, const Sphere& b) { return certified_sphere(fr.cert[f], b); });
    });
    benchmark::RegisterBenchmark(("generic/sphere/" + d + "/sphere-exact-certified").c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Sphere>(d);
      run(s, fr, [&](std::size_t f, const Sphere& b) { return exact_certified_sphere(fr.exact[f], b); });
    });
  }
}

// The two tests in turn, each pass over the frames timed apart: the ratio of the summed times.
template <class K, class Base, class Exact>
void register_ratio(const char* kind, Base base, Exact exact) {
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark((std::string("ratio/") + kind + "/" + d).c_str(), [d, base, exact](benchmark::State& s) {
      const auto& fr = frames<K>(d);
      using clock = std::chrono::steady_clock;
      double tb = 0.0, te = 0.0;
      unsigned sink = 0;
      for (auto _ : s) {
        const auto t0 = clock::now();
        for (std::size_t f = 0; f < fr.volumes.size(); ++f)
          for (const K& v : fr.volumes[f]) sink += unsigned(base(fr.cert[f], v));
        const auto t1 = clock::now();
        for (std::size_t f = 0; f < fr.volumes.size(); ++f)
          for (const K& v : fr.volumes[f]) sink += unsigned(exact(fr.exact[f], v));
        const auto t2 = clock::now();
        tb += std::chrono::duration<double>(t1 - t0).count();
        te += std::chrono::duration<double>(t2 - t1).count();
        benchmark::DoNotOptimize(sink);
      }
      s.counters["exact_over_certified"] = te / tb;
      s.counters["certified_ns"] = 1e9 * tb / double(s.iterations()) / double(fr.count);
      s.counters["exact_ns"] = 1e9 * te / double(s.iterations()) / double(fr.count);
    });
  }
}

// Through the method interface, as verify times the array forms: prepare hoisted, classify_batch
// over each frame's volumes.
template <class K>
void register_batch(const char* kind, const char* name) {
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark((std::string("batch/") + kind + "/" + d + "/" + name).c_str(), [d, name](benchmark::State& s) {
      const auto& fr = frames<K>(d);
      const Method* m = find_builtin(name);
      std::vector<std::unique_ptr<PreparedFrustum>> prepared;
      for (const CaseFrustum& f : fr.frustum) prepared.push_back(m->prepare(f));
      std::vector<Answer> out(kFrameSize);
      for (auto _ : s) {
        for (std::size_t f = 0; f < fr.volumes.size(); ++f)
          prepared[f]->classify_batch(fr.volumes[f].data(), fr.volumes[f].size(), out.data());
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
      }
      per_test(s, fr.count);
    });
  }
}

// The two array forms through classify_batch in turn, frame by frame, each call timed: the ratio
// of the summed times (as ratio/, steadier than two batch/ runs on a shared machine).
template <class K>
void register_batch_ratio(const char* kind, const char* base_name, const char* exact_name) {
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark((std::string("batch-ratio/") + kind + "/" + d).c_str(), [d, base_name, exact_name](benchmark::State& s) {
      const auto& fr = frames<K>(d);
      const Method* base = find_builtin(base_name);
      const Method* exact = find_builtin(exact_name);
      std::vector<std::unique_ptr<PreparedFrustum>> pb, pe;
      for (const CaseFrustum& f : fr.frustum) pb.push_back(base->prepare(f)), pe.push_back(exact->prepare(f));
      std::vector<Answer> out(kFrameSize);
      using clock = std::chrono::steady_clock;
      double tb = 0.0, te = 0.0;
      for (auto _ : s) {
        for (std::size_t f = 0; f < fr.volumes.size(); ++f) {
          const auto t0 = clock::now();
          pb[f]->classify_batch(fr.volumes[f].data(), fr.volumes[f].size(), out.data());
          benchmark::DoNotOptimize(out.data());
          const auto t1 = clock::now();
          pe[f]->classify_batch(fr.volumes[f].data(), fr.volumes[f].size(), out.data());
          benchmark::DoNotOptimize(out.data());
          const auto t2 = clock::now();
          tb += std::chrono::duration<double>(t1 - t0).count();
          te += std::chrono::duration<double>(t2 - t1).count();
        }
        benchmark::ClobberMemory();
      }
      s.counters["exact_over_certified"] = te / tb;
      s.counters["certified_ns"] = 1e9 * tb / double(s.iterations()) / double(fr.count);
      s.counters["exact_ns"] = 1e9 * te / double(s.iterations()) / double(fr.count);
    });
  }
}

// Stage statistics on the campaign's cases (gen::draw, seed 1) of every distribution.
template <class K, class Classify>
void register_stages(const char* kind, Classify classify) {
  for (gen::Distribution d : gen::parse_distributions("all")) {
    const std::string name = std::string("stages/") + kind + "/" + std::string(gen::to_string(d));
    benchmark::RegisterBenchmark(name.c_str(), [d, classify](benchmark::State& s) {
      std::size_t count[3] = {0, 0, 0}, cases = 0;
      std::vector<ExactCertifiedFrustum> ef;
      std::vector<K> ev;
      for (std::uint64_t i = 0; i < kStageCases; ++i) {
        const gen::GenCase g = gen::draw_case(d, kSeed, i);
        const K* v = std::get_if<K>(&g.volume);
        if (!v) continue;
        const ExactCertifiedFrustum f = prepare_exact_certified(g.frustum);
        ExactStage st{};
        classify(f, *v, &st);
        ++count[int(st)], ++cases;
        if (st == ExactStage::exact) ef.push_back(f), ev.push_back(*v);
      }
      unsigned sink = 0;
      for (auto _ : s) {
        for (std::size_t i = 0; i < ev.size(); ++i) sink += unsigned(classify(ef[i], ev[i], nullptr));
        benchmark::DoNotOptimize(sink);
      }
      s.counters["cases"] = double(cases);
      for (int k = 0; k < 3; ++k)
        s.counters[std::string(to_string(ExactStage(k)))] = cases ? double(count[k]) / double(cases) : 0.0;
      if (!ev.empty()) per_test(s, ev.size());
    });
  }
}

// The AABB array form's passes, each on what the one before leaves (as exact_certified_aabbs runs
// them, but with the witness pass on every chunk), per distribution over the frames of batch/:
//   certified       left by the certified SIMD batch (neither outside nor inside proved);
//   exact_planes    left by the exact planes' float items, each with its own threshold, tried
//                   on the same boxes instead (no witness point): the open set is the same when
//                   the boxes left cross a plane rather than lie within the certified margin;
//   witness         left by the witness pass (a point of the box proved inside every plane);
//   float_planes    left by the float pass's planes (J, and a p-vertex shared by J proved inside);
//   combinations    left by the frame's combinations;
//   box_planes      left by the box pass (stage 1 in double): what reaches the scalar cascade.
void register_passes() {
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark(("passes/aabb/" + d).c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Aabb>(d);
      std::size_t left[6] = {}, total = 0;
      constexpr std::size_t kChunk = detail::kSoaChunk;
      alignas(64) float a[6][kChunk];
      for (std::size_t f = 0; f < fr.volumes.size(); ++f) {
        const ExactCertifiedFrustum& ef = fr.exact[f];
        if (ef.float_planes == 0) continue;
        const glm::vec3 seed(float(ef.interior[0]), float(ef.interior[1]), float(ef.interior[2]));
        for (std::size_t i0 = 0; i0 < fr.volumes[f].size(); i0 += kChunk) {
          const std::size_t m = std::min(kChunk, fr.volumes[f].size() - i0);
          const AabbSoa chunk = detail::aabb_soa(fr.volumes[f].data() + i0, m, a);
          total += m;
          std::uint64_t vis[kChunk / 64] = {}, ins[kChunk / 64] = {}, todo[kChunk / 64] = {}, meets[kChunk / 64] = {},
                        all[kChunk / 64];
          for (std::uint64_t& w : all) w = ~std::uint64_t{0};
          certified_cull_aabbs_bitset(ef.certified, chunk, vis, ins);
          for (std::size_t w = 0; w < bitset_words(m); ++w) todo[w] = vis[w] & ~ins[w];
          FloatFirstResult planes_only;
          exact_float_first(ef, chunk, seed, planes_only, all);
          certified_meets_aabbs_bitset(ef.certified, chunk, seed, todo, meets);
          // The boxes the witness pass leaves, gathered, through the float pass (their witness
          // points tried) and the combinations.
          alignas(64) float g[6][kChunk];
          std::size_t n = 0;
          for (std::size_t j = 0; j < m; ++j) {
            const std::uint64_t bit = std::uint64_t{1} << (j % 64);
            const bool open = todo[j / 64] & bit, met = meets[j / 64] & bit;
            left[0] += open;
            left[1] += bool((planes_only.open[j / 64] | planes_only.meets[j / 64]) & bit);
            if (!open || met) continue;
            for (int k = 0; k < 6; ++k) g[k][n] = a[k][j];
            ++n;
          }
          left[2] += n;
          if (n == 0) continue;
          for (std::size_t q = n; q < bitset_words(n) * 64; ++q)
            for (int k = 0; k < 6; ++k) g[k][q] = 0.0f;
          const AabbSoa gathered{g[0], g[1], g[2], g[3], g[4], g[5], n};
          FloatFirstResult r;
          exact_float_first(ef, gathered, seed, r, all);
          FloatOpenResult o;
          exact_float_open(ef, gathered, r, o);
          left[3] += o.count;
          std::uint64_t rest[kChunk / 64] = {};
          for (std::size_t p = 0; p < o.count; ++p)
            if (!((o.outside[p / 64] | o.meets[p / 64]) >> (p % 64) & 1u)) {
              ++left[4];
              rest[o.order[p] / 64] |= std::uint64_t{1} << (o.order[p] % 64);
            }
          detail::PassProofs bp;
          exact_box_planes(ef, gathered, rest, bp);
          for (std::size_t w = 0; w < bitset_words(n); ++w)
            left[5] += std::size_t(__builtin_popcountll(rest[w] & ~(bp.outside[w] | bp.inside[w] | bp.meets[w])));
        }
      }
      for (auto _ : s) benchmark::DoNotOptimize(total);
      const char* names[6] = {"certified", "exact_planes", "witness", "float_planes", "combinations", "box_planes"};
      for (int k = 0; k < 6; ++k) s.counters[names[k]] = total ? double(left[k]) / double(total) : 0.0;
      s.counters["boxes"] = double(total);
    });
  }
  // The sphere array form's passes the same way, over the frames of batch/:
  //   certified  left by the certified SIMD batch;
  //   witness    left by the witness pass (a point of the ball proved inside every plane);
  //   double     left by the double pass (batch_spheres.cpp): what reaches the scalar cascade.
  for (const std::string& d : distributions()) {
    benchmark::RegisterBenchmark(("passes/sphere/" + d).c_str(), [d](benchmark::State& s) {
      const auto& fr = frames<Sphere>(d);
      std::size_t left[3] = {}, total = 0;
      constexpr std::size_t kChunk = detail::kSoaChunk;
      alignas(64) float a[4][kChunk] = {};
      for (std::size_t f = 0; f < fr.volumes.size(); ++f) {
        const ExactCertifiedFrustum& ef = fr.exact[f];
        const glm::vec3 seed(float(ef.interior[0]), float(ef.interior[1]), float(ef.interior[2]));
        for (std::size_t i0 = 0; i0 < fr.volumes[f].size(); i0 += kChunk) {
          const std::size_t m = std::min(kChunk, fr.volumes[f].size() - i0);
          const SphereSoa chunk = detail::sphere_soa(fr.volumes[f].data() + i0, m, a);
          total += m;
          std::uint64_t vis[kChunk / 64] = {}, ins[kChunk / 64] = {}, todo[kChunk / 64] = {}, meets[kChunk / 64] = {};
          certified_cull_spheres_bitset(ef.certified, chunk, vis, ins);
          for (std::size_t w = 0; w < bitset_words(m); ++w) todo[w] = vis[w] & ~ins[w];
          certified_meets_spheres_bitset(ef.certified, chunk, seed, todo, meets);
          for (std::size_t w = 0; w < bitset_words(m); ++w) {
            left[0] += std::size_t(__builtin_popcountll(todo[w]));
            todo[w] &= ~meets[w];
            left[1] += std::size_t(__builtin_popcountll(todo[w]));
          }
          detail::PassProofs r;
          exact_ball_pass(ef, chunk, todo, r);
          for (std::size_t w = 0; w < bitset_words(m); ++w)
            left[2] += std::size_t(__builtin_popcountll(todo[w] & ~(r.outside[w] | r.inside[w] | r.meets[w])));
        }
      }
      for (auto _ : s) benchmark::DoNotOptimize(total);
      const char* names[3] = {"certified", "witness", "double"};
      for (int k = 0; k < 3; ++k) s.counters[names[k]] = total ? double(left[k]) / double(total) : 0.0;
      s.counters["balls"] = double(total);
    });
  }
}

}  // namespace

int main(int argc, char** argv) {
  register_generic();
  register_ratio<Aabb>("aabb", [](const CertifiedFrustum& f, const Aabb& b) { return certified_pn_vertex(f, b); },
                       [](const ExactCertifiedFrustum& f, const Aabb& b) { return exact_certified_aabb(f, b); });
  register_ratio<Obb>("obb", [](const CertifiedFrustum& f, const Obb& b) { return certified_obb_pn_vertex(f, b); },
                      [](const ExactCertifiedFrustum& f, const Obb& b) { return exact_certified_obb(f, b); });
  register_ratio<Sphere>("sphere", [](const CertifiedFrustum& f, const Sphere& b) { return certified_sphere(f, b); },
                         [](const ExactCertifiedFrustum& f, const Sphere& b) { return exact_certified_sphere(f, b); });
  register_batch<Aabb>("aabb", "pn-vertex-batch-certified");
  register_batch<Aabb>("aabb", "aabb-batch-exact-certified");
  register_batch<Sphere>("sphere", "sphere-batch-certified");
  register_batch<Sphere>("sphere", "sphere-batch-exact-certified");
  register_batch_ratio<Aabb>("aabb", "pn-vertex-batch-certified", "aabb-batch-exact-certified");
  register_batch_ratio<Sphere>("sphere", "sphere-batch-certified", "sphere-batch-exact-certified");
  register_passes();
  register_stages<Aabb>("aabb", [](const ExactCertifiedFrustum& f, const Aabb& b, ExactStage* s) {
    return exact_certified_aabb(f, b, s);
  });
  register_stages<Obb>("obb", [](const ExactCertifiedFrustum& f, const Obb& b, ExactStage* s) {
    return exact_certified_obb(f, b, s);
  });
  register_stages<Sphere>("sphere", [](const ExactCertifiedFrustum& f, const Sphere& b, ExactStage* s) {
    return exact_certified_sphere(f, b, s);
  });
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i], flag = "--simd_target=";
    if (arg.compare(0, flag.size(), flag) != 0) continue;
    const std::string name = arg.substr(flag.size());
    std::string known;
    std::int64_t chosen = 0;
    for (const std::int64_t t : hwy::SupportedAndGeneratedTargets()) {
      known += std::string(known.empty() ? "" : ", ") + hwy::TargetName(t);
      if (name == hwy::TargetName(t)) chosen = t;
    }
    if (chosen == 0) {
      std::fprintf(stderr, "--simd_target=%s: not a target this machine runs (it runs %s)\n", name.c_str(), known.c_str());
      return 1;
    }
    hwy::SetSupportedTargetsForTest(chosen);
    for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
    --argc, --i;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

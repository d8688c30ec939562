// Per-call cost of the oracle on OBB-vs-frustum cases near the frustum boundary.
//
// Cases: 4096 random perspective cameras (fov 30-100°, aspect 0.5-2, near 0.1-1, far 50-1000,
// a quarter infinite; all four depth conventions), each with an OBB of random orientation and
// size (1-10% of its distance to the eye) whose centre is placed on a random boundary point
// (a clip-space point with x, y or depth on the clip boundary, unprojected) and then pushed
// along a random direction by up to 3 times its half-diagonal, so boxes straddle the boundary,
// lie just outside or just inside it (the truth mix is reported as counters). Deterministic (std::mt19937, seed 3).
//
// BM_OracleFiltered: truth() — interval filter, exact route on fallback, certificate checked.
// BM_OracleExactRoute: the exact route only (filter off; no distance, no witness JSON).
// BM_OracleFull: classify() with witness JSON and exact distance (what `cullproof classify` runs).
// BM_OracleIndependent: the independent cross-check method.
// BM_OracleOutsideDistance: classify() with the exact distance, no witness, on the outside cases
//   alone (second argument: 0 the exact QP alone, 1 the closest pair found in double first, as
//   by default); counter closest_pairs_per_call: the pairs proven without a QP.
// BM_VerdictDistance: distance_to_verdict (what the judge measures for a wrong verdict), per
//   verdict given (second argument: 0 outside, 1 intersecting, 2 inside), on the OBBs, and on
//   balls of the OBB's centre and half-diagonal (third argument 1); a case whose truth is the
//   verdict costs only its truth.
// Counters: fallback_fraction = fallbacks / calls of the filter over the benchmark's calls.
#include "cullproof/oracle/oracle.hpp"

#include <benchmark/benchmark.h>
#include <glm/gtc/quaternion.hpp>

#include <random>
#include <string>
#include <vector>

namespace {

using namespace cullproof;

struct BenchCase {
  CaseFrustum frustum;
  Volume volume;
};

std::vector<BenchCase> make_cases(bool as_matrix) {
  std::mt19937 rng(3);
  auto uni = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  std::vector<BenchCase> out;
  const DepthConvention conventions[4] = {{DepthRange::negative_one_to_one, false},
                                          {DepthRange::zero_to_one, false},
                                          {DepthRange::zero_to_one, true},
                                          {DepthRange::negative_one_to_one, true}};
  while (out.size() < 4096) {
    PerspectiveCamera cam;
    cam.fovy_degrees = float(uni(30, 100));
    cam.aspect = float(uni(0.5, 2));
    cam.near_dist = float(uni(0.1, 1));
    cam.far_dist = uni(0, 1) < 0.25 ? INFINITY : float(uni(50, 1000));
    cam.eye = glm::vec3(uni(-50, 50), uni(-50, 50), uni(-50, 50));
    cam.target = cam.eye + glm::vec3(uni(-1, 1), uni(-1, 1), uni(-1, 1));
    if (glm::length(cam.target - cam.eye) < 0.1f) continue;
    const DepthConvention depth = conventions[rng() % 4];
    const glm::mat4 m = view_projection(cam, depth);
    // A boundary point in clip space, unprojected.
    const bool zo = depth.range == DepthRange::zero_to_one;
    double cx = uni(-1, 1), cy = uni(-1, 1), cz = zo ? uni(0, 0.99) : uni(-1, 0.99);
    switch (rng() % 3) {
      case 0: cx = rng() % 2 ? 1 : -1; break;
      case 1: cy = rng() % 2 ? 1 : -1; break;
      default: cz = depth.reversed_z ? 1.0 : (zo ? 0.0 : -1.0); break;
    }
    const glm::dvec4 h = glm::inverse(glm::dmat4(m)) * glm::dvec4(cx, cy, cz, 1.0);
    const glm::dvec3 p = glm::dvec3(h) / h.w;
    const double dist = glm::length(p - glm::dvec3(cam.eye));
    if (!std::isfinite(dist) || dist > 1e4) continue;
    Obb o;
    o.axes = glm::mat3_cast(glm::normalize(glm::quat(float(uni(-1, 1)), float(uni(-1, 1)), float(uni(-1, 1)), float(uni(-1, 1)))));
    o.half = glm::vec3(uni(0.01, 0.1), uni(0.01, 0.1), uni(0.01, 0.1)) * float(dist);
    const glm::dvec3 push = glm::normalize(glm::dvec3(uni(-1, 1), uni(-1, 1), uni(-1, 1))) *
                            (uni(-3.0, 3.0) * glm::length(glm::dvec3(o.half)));
    o.center = glm::vec3(p + push);
    BenchCase c{frustum_spec(m, depth), o};
    if (!as_matrix) c.frustum = frustum_spec(c.frustum.planes);
    out.push_back(c);
  }
  return out;
}

const std::vector<BenchCase>& cases(bool as_matrix) {
  static const std::vector<BenchCase> planes = make_cases(false), matrix = make_cases(true);
  return as_matrix ? matrix : planes;
}

template <class Fn>
void run(benchmark::State& state, Fn fn) {
  const auto& cs = cases(state.range(0) != 0);
  oracle::reset_stats();
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& c = cs[i++ % cs.size()];
    benchmark::DoNotOptimize(fn(c));
  }
  const oracle::Stats s = oracle::stats();
  state.counters["fallback_fraction"] = s.fallback_fraction();
  state.counters["exact_solves_per_call"] = double(s.exact_lp) / double(state.iterations());
  double mix[3] = {0, 0, 0};
  for (const auto& c : cs) mix[static_cast<int>(oracle::truth(c.frustum, c.volume))] += 1.0 / double(cs.size());
  state.counters["outside"] = mix[0];
  state.counters["intersecting"] = mix[1];
  state.counters["inside"] = mix[2];
  state.SetLabel(state.range(0) ? "matrix" : "planes");
}

void BM_OracleFiltered(benchmark::State& state) {
  run(state, [](const BenchCase& c) { return oracle::truth(c.frustum, c.volume); });
}
void BM_OracleExactRoute(benchmark::State& state) {
  oracle::Options o;
  o.filter = false;
  o.distance = false;
  o.witness = false;
  run(state, [&](const BenchCase& c) { return oracle::classify(c.frustum, c.volume, o).truth; });
}
void BM_OracleFull(benchmark::State& state) {
  run(state, [](const BenchCase& c) { return oracle::classify(c.frustum, c.volume).truth; });
}
void BM_OracleIndependent(benchmark::State& state) {
  run(state, [](const BenchCase& c) { return oracle::classify_independent(c.frustum, c.volume); });
}

void BM_OracleOutsideDistance(benchmark::State& state) {
  std::vector<BenchCase> outside;
  for (const BenchCase& c : cases(state.range(0) != 0))
    if (oracle::truth(c.frustum, c.volume) == Visibility::outside) outside.push_back(c);
  oracle::Options o;
  o.witness = false;
  o.closest_in_double = state.range(1) != 0;
  oracle::reset_stats();
  std::size_t i = 0;
  for (auto _ : state) {
    const BenchCase& c = outside[i++ % outside.size()];
    benchmark::DoNotOptimize(oracle::classify(c.frustum, c.volume, o).distance);
  }
  const oracle::Stats s = oracle::stats();
  state.counters["closest_pairs_per_call"] = double(s.closest_pairs) / double(state.iterations());
  state.counters["cases"] = double(outside.size());
  state.SetLabel(std::string(state.range(0) ? "matrix" : "planes") + (o.closest_in_double ? ", double first" : ", QP alone"));
}

void BM_VerdictDistance(benchmark::State& state) {
  const auto verdict = static_cast<Visibility>(state.range(1));
  const bool ball = state.range(2) != 0;
  run(state, [&](const BenchCase& c) {
    if (!ball) return oracle::distance_to_verdict(c.frustum, c.volume, verdict).distance;
    const Obb& o = std::get<Obb>(c.volume);
    return oracle::distance_to_verdict(c.frustum, Sphere{o.center, glm::length(o.half)}, verdict).distance;
  });
  state.SetLabel(std::string(state.range(0) ? "matrix" : "planes") + (ball ? ", balls" : ", OBBs"));
}

// Each is run with 4096 x k iterations so every case is visited equally often.
BENCHMARK(BM_OracleFiltered)->Arg(0)->Arg(1)->Iterations(4096 * 20)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OracleExactRoute)->Arg(0)->Arg(1)->Iterations(4096 * 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OracleFull)->Arg(0)->Arg(1)->Iterations(4096 * 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OracleIndependent)->Arg(0)->Arg(1)->Iterations(4096)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OracleOutsideDistance)->ArgsProduct({{0, 1}, {0, 1}})->Iterations(4096)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_VerdictDistance)
    ->ArgsProduct({{0, 1}, {0, 1, 2}, {0, 1}})
    ->Iterations(4096)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

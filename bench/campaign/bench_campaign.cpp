// What a verification run costs per case, and where the time goes: the campaign's throughput
// (cases judged per second) beside its parts, drawing the cases and the oracle's truth, which
// bounds it.
//
// Cases: the `uniform` family, seed 1, as `cullproof verify` draws them (gen::draw_case).
//
// BM_Draw: draw one case (gen::draw_case: the counter-based stream, no RapidCheck; the frame's
//   camera drawn with every case).
// BM_DrawFrames: cases drawn 256 at a time as the campaign draws them (gen::draw_cases: a frame's
//   camera once per 16 cases), per case.
// BM_DrawShrinkable: the same case as the Shrinkable a mismatch is shrunk from (gen::draw: drawn,
//   then replayed inside RapidCheck), its root evaluated; paid once per error recorded.
// BM_OracleTruth: the oracle's truth of one case (filtered; cases drawn beforehand), per case.
// BM_Campaign/<set>/<threads>: run_verify over cases of `uniform`, no timing, no corpus, no
//   progress; set 0: one method (`pn-vertex`), 200,000 cases; set 1: every built-in method,
//   20,000 cases; items = cases.
// BM_CampaignProtocol/<jobs>/<binary>: the same run of the reference adapter (the n/p-vertex test
//   behind the process protocol, tests/protocol/reference_adapter.cpp) with <jobs> copies, 2
//   threads, 200,000 cases, in JSON Lines (binary 0) or in the binary encoding (binary 1: a chunk's
//   frames in one message); BM_Campaign/0/2 is the same run in process. Only built when the tests
//   are.
// Counters: cases_per_second (items_per_second) in every run.
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/oracle/oracle.hpp"
#ifdef CULLPROOF_REFERENCE_ADAPTER
#include "cullproof/protocol/external.hpp"
#endif

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace cullproof;

constexpr gen::Distribution kFamily = gen::Distribution::uniform;
constexpr std::uint64_t kOneMethodCases = 200000, kEveryMethodCases = 20000;

void BM_Draw(benchmark::State& state) {
  std::uint64_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(gen::draw_case(kFamily, 1, i++));
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Draw);

void BM_DrawFrames(benchmark::State& state) {
  std::vector<gen::GenCase> cases(256);
  std::uint64_t first = 0;
  for (auto _ : state) {
    gen::draw_cases(kFamily, 1, first, cases.size(), cases.data());
    benchmark::DoNotOptimize(cases.data());
    first += cases.size();
  }
  state.SetItemsProcessed(state.iterations() * std::int64_t(cases.size()));
}
BENCHMARK(BM_DrawFrames);

void BM_DrawShrinkable(benchmark::State& state) {
  std::uint64_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(gen::draw(kFamily, 1, i++).value());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DrawShrinkable);

void BM_OracleTruth(benchmark::State& state) {
  std::vector<gen::GenCase> cases;
  for (std::uint64_t i = 0; i < 4096; ++i) cases.push_back(gen::draw_case(kFamily, 1, i));
  std::size_t i = 0;
  for (auto _ : state) {
    const gen::GenCase& c = cases[i++ % cases.size()];
    benchmark::DoNotOptimize(oracle::truth(c.frustum, c.volume));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_OracleTruth);

VerifyOptions run_options(int threads, std::uint64_t cases) {
  VerifyOptions o;
  o.cases = cases;
  o.seed = 1;
  o.distributions = {kFamily};
  o.threads = threads;
  o.progress = false;
  o.timing = false;
  return o;
}

void BM_Campaign(benchmark::State& state) {
  const std::vector<Method> methods = state.range(0) == 0 ? builtin_methods({"pn-vertex"}) : builtin_methods();
  const VerifyOptions o = run_options(int(state.range(1)), state.range(0) == 0 ? kOneMethodCases : kEveryMethodCases);
  for (auto _ : state) benchmark::DoNotOptimize(run_verify(o, methods));
  state.SetItemsProcessed(state.iterations() * std::int64_t(o.cases));
  state.counters["methods"] = double(methods.size());
}
BENCHMARK(BM_Campaign)->ArgsProduct({{0, 1}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

#ifdef CULLPROOF_REFERENCE_ADAPTER
void BM_CampaignProtocol(benchmark::State& state) {
  ExternalOptions e;
  e.command = {CULLPROOF_REFERENCE_ADAPTER};
  if (state.range(1)) e.command.push_back("binary");
  e.instances = int(state.range(0));
  const std::vector<Method> methods = external_methods(e);
  const VerifyOptions o = run_options(2, kOneMethodCases);
  for (auto _ : state) benchmark::DoNotOptimize(run_verify(o, methods));
  state.SetItemsProcessed(state.iterations() * std::int64_t(o.cases));
}
BENCHMARK(BM_CampaignProtocol)->ArgsProduct({{1, 2}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
#endif

}  // namespace

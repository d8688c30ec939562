// Timing a method as it runs in an engine: prepare once per frame, then classify the frame's
// volumes, the two phases apart (see cullproof/campaign/campaign.hpp "cost").
#include "campaign_internal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <type_traits>
#include <utility>
#include <variant>

namespace cullproof::detail {

KindedFrame split(gen::Frame f) {
  KindedFrame k;
  k.frustum = std::move(f.frustum);
  k.continues = f.continues;
  for (const Volume& v : f.volumes)
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, Point>) k.points.push_back(x);
          else if constexpr (std::is_same_v<T, Sphere>) k.spheres.push_back(x);
          else if constexpr (std::is_same_v<T, Aabb>) k.aabbs.push_back(x);
          else k.obbs.push_back(x);
        },
        v);
  return k;
}

namespace {

// Classifies a frame's volumes through classify_batch, kind by kind; answers sized for it.
unsigned classify_frame(PreparedFrustum& p, const KindedFrame& f, std::vector<Answer>& answers) {
  Answer* a = answers.data();
  if (!f.points.empty()) p.classify_batch(f.points.data(), f.points.size(), a), a += f.points.size();
  if (!f.spheres.empty()) p.classify_batch(f.spheres.data(), f.spheres.size(), a), a += f.spheres.size();
  if (!f.aabbs.empty()) p.classify_batch(f.aabbs.data(), f.aabbs.size(), a), a += f.aabbs.size();
  if (!f.obbs.empty()) p.classify_batch(f.obbs.data(), f.obbs.size(), a), a += f.obbs.size();
  return (answers[0] ? unsigned(*answers[0]) : 3u) + (answers[f.size() - 1] ? unsigned(*answers[f.size() - 1]) : 3u);
}

// Each measure is the fastest of kPasses passes of at least kPassSeconds each (every pass goes
// over all the frames, as many times as it takes): the fastest pass is the one least disturbed by
// the rest of the machine (another thread's work, an interrupt), which a mean over one longer
// interval would take in.
constexpr int kPasses = 3;
constexpr double kPassSeconds = 0.0006;

// Runs `pass` (one pass over the frames, returning for each of N figures how many units it timed
// and in how many seconds) until its figures have run for N * kPassSeconds together, kPasses
// times; per figure, the least time per unit of the passes, or NaN for every figure when a pass
// timed no unit of the first.
template <std::size_t N, typename Pass>
std::array<double, N> fastest_passes(Pass&& pass) {
  std::array<double, N> best;
  best.fill(std::numeric_limits<double>::infinity());
  for (int k = 0; k < kPasses; ++k) {
    std::array<std::uint64_t, N> units{};
    std::array<double, N> secs{};
    double total = 0.0;
    do {
      const std::array<std::pair<std::uint64_t, double>, N> r = pass();
      if (r[0].first == 0) {
        best.fill(std::numeric_limits<double>::quiet_NaN());
        return best;
      }
      for (std::size_t i = 0; i < N; ++i) {
        units[i] += r[i].first;
        secs[i] += r[i].second;
        total += r[i].second;
      }
    } while (total < double(N) * kPassSeconds);
    for (std::size_t i = 0; i < N; ++i) best[i] = std::min(best[i], secs[i] * 1e9 / double(units[i]));
  }
  return best;
}

// One figure: `pass` returns the units it timed and their seconds.
template <typename Pass>
double fastest_pass(Pass&& pass) {
  return fastest_passes<1>([&] { return std::array<std::pair<std::uint64_t, double>, 1>{pass()}; })[0];
}

// A stateful method runs as it would in an engine: frame after frame, each prepared and then
// classified (reset() where a frame does not continue the previous one's path), the two phases
// timed apart with a clock read around each (about 20 ns a read, in the set-up figure); a pass
// starts from reset(), so every pass sees the same sequence.
Timing time_stateful(const Method& m, const std::vector<KindedFrame>& frames) {
  Timing t;
  std::size_t largest = 0;
  for (const KindedFrame& f : frames) largest = std::max(largest, f.size());
  if (largest == 0) return t;
  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  // Figures: the set-up per frame prepared, the classification per volume.
  const std::array<double, 2> best = fastest_passes<2>([&] {
    std::array<std::pair<std::uint64_t, double>, 2> r{};
    m.reset();
    for (const KindedFrame& f : frames) {
      if (!f.continues) m.reset();
      if (f.size() == 0) continue;
      const auto t0 = Clock::now();
      const auto p = m.prepare(f.frustum);
      const auto t1 = Clock::now();
      r[0].second += std::chrono::duration<double>(t1 - t0).count();
      if (!p) continue;
      ++r[0].first;
      sink += classify_frame(*p, f, answers);
      r[1].second += std::chrono::duration<double>(Clock::now() - t1).count();
      r[1].first += f.size();
    }
    return r;
  });
  static std::atomic<unsigned> keep{0};
  keep += sink;
  if (std::isnan(best[0])) return t;
  t.ns_setup_per_frame = best[0];
  t.ns_per_test = best[1];
  return t;
}

// Times prepare once per frame and classify_batch over each frame's volumes, each the fastest of
// its passes over the frames. Frames the method does not apply to are left out.
Timing time_classify(const Method& m, const std::vector<KindedFrame>& frames) {
  Timing t;
  // The frames the method applies to, each with its state for the classify passes.
  std::vector<const KindedFrame*> mine;
  std::vector<std::unique_ptr<PreparedFrustum>> states;
  std::size_t volumes = 0, largest = 0;
  for (const KindedFrame& f : frames) {
    if (f.size() == 0) continue;
    auto p = m.prepare(f.frustum);
    if (!p) continue;
    mine.push_back(&f);
    states.push_back(std::move(p));
    volumes += f.size();
    largest = std::max(largest, f.size());
  }
  if (mine.empty()) return t;
  t.ns_setup_per_frame = fastest_pass([&] {
    std::uint64_t prepared = 0;
    const auto t0 = Clock::now();
    for (const KindedFrame* f : mine) prepared += m.prepare(f->frustum) != nullptr;
    return std::pair{prepared, std::chrono::duration<double>(Clock::now() - t0).count()};
  });
  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  t.ns_per_test = fastest_pass([&] {
    const auto t0 = Clock::now();
    for (std::size_t i = 0; i < mine.size(); ++i) sink += classify_frame(*states[i], *mine[i], answers);
    return std::pair{std::uint64_t(volumes), std::chrono::duration<double>(Clock::now() - t0).count()};
  });
  static std::atomic<unsigned> keep{0};
  keep += sink;  // keeps the calls from being optimised away
  return t;
}

}  // namespace

Timing time_method(const Method& m, const std::vector<KindedFrame>& frames) {
  (void)m.take_own_timing();  // what the method reported before the timed frames
  Timing t = m.stateful ? time_stateful(m, frames) : time_classify(m, frames);
  const auto [own_ns, own_volumes] = m.take_own_timing();
  if (own_volumes > 0) t.ns_per_test_own = own_ns / double(own_volumes);
  return t;
}

}  // namespace cullproof::detail

// Timing a method as it runs in an engine: prepare once per frame, then classify the frame's
// volumes, the two phases apart (see cullproof/campaign/campaign.hpp "cost").
#include "campaign_internal.hpp"

#include <algorithm>
#include <memory>
#include <type_traits>
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

constexpr double kMinTimingSeconds = 0.005;

// A stateful method runs as it would in an engine: frame after frame, each prepared and then
// classified (reset() where a frame does not continue the previous one's path), the two phases
// timed apart with a clock read around each (about 20 ns a read, in the set-up figure).
Timing time_stateful(const Method& m, const std::vector<KindedFrame>& frames) {
  Timing t;
  std::size_t largest = 0;
  for (const KindedFrame& f : frames) largest = std::max(largest, f.size());
  if (largest == 0) return t;
  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  std::uint64_t tests = 0, prepared = 0;
  double prep_secs = 0.0, cls_secs = 0.0;
  do {
    for (const KindedFrame& f : frames) {
      if (!f.continues) m.reset();
      if (f.size() == 0) continue;
      const auto t0 = Clock::now();
      const auto p = m.prepare(f.frustum);
      const auto t1 = Clock::now();
      prep_secs += std::chrono::duration<double>(t1 - t0).count();
      if (!p) continue;
      ++prepared;
      sink += classify_frame(*p, f, answers);
      cls_secs += std::chrono::duration<double>(Clock::now() - t1).count();
      tests += f.size();
    }
  } while (prepared > 0 && prep_secs + cls_secs < kMinTimingSeconds);
  static std::atomic<unsigned> keep{0};
  keep += sink;
  if (prepared == 0) return t;
  t.ns_setup_per_frame = prep_secs * 1e9 / double(prepared);
  t.ns_per_test = cls_secs * 1e9 / double(tests);
  return t;
}

// Times prepare once per frame and classify_batch over each frame's volumes, in passes over the
// frames until each measure has run for at least 5 ms. Frames the method does not apply to
// are left out.
Timing time_classify(const Method& m, const std::vector<KindedFrame>& frames) {
  constexpr double kMinSeconds = kMinTimingSeconds;
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
  std::size_t prepared = 0;
  const auto t0 = Clock::now();
  double secs = 0.0;
  do {
    for (const KindedFrame* f : mine) {
      const auto p = m.prepare(f->frustum);
      prepared += p != nullptr;
    }
    secs = std::chrono::duration<double>(Clock::now() - t0).count();
  } while (secs < kMinSeconds);
  t.ns_setup_per_frame = secs * 1e9 / double(prepared);

  std::vector<Answer> answers(largest);
  unsigned sink = 0;
  std::uint64_t tests = 0;
  const auto t1 = Clock::now();
  secs = 0.0;
  do {
    for (std::size_t i = 0; i < mine.size(); ++i) sink += classify_frame(*states[i], *mine[i], answers);
    tests += volumes;
    secs = std::chrono::duration<double>(Clock::now() - t1).count();
  } while (secs < kMinSeconds);
  static std::atomic<unsigned> keep{0};
  keep += sink;  // keeps the calls from being optimised away
  t.ns_per_test = secs * 1e9 / double(tests);
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

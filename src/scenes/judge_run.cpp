// A system run over a scene and judged: every object of every frame against the exact truth,
// under the system's claim (cullproof/scenes/scenes.hpp).
#include "cullproof/scenes/scenes.hpp"

#include "cullproof/gen/generators.hpp"

#include <chrono>
#include <cmath>
#include <exception>

namespace cullproof::scenes {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Runs `phase` of the system; anything it throws becomes a SystemFault naming the phase and frame.
template <class F>
void guarded(const System& s, const char* phase, std::size_t frame, F&& f) {
  try {
    f();
  } catch (const SystemFault&) {
    throw;
  } catch (const std::exception& e) {
    throw SystemFault("system '" + s.name + "' threw in " + phase + " on frame " + std::to_string(frame) + ": " + e.what(),
                      frame);
  } catch (...) {
    throw SystemFault("system '" + s.name + "' threw a non-exception in " + phase + " on frame " + std::to_string(frame),
                      frame);
  }
}

}  // namespace

void verdicts_by_position(const SystemInfo& info, const std::unordered_map<std::uint32_t, std::size_t>& position,
                          const VisibleSet& set, std::vector<Visibility>& out) {
  out.assign(position.size(), Visibility::outside);
  const bool with_verdicts = !set.verdicts.empty();
  if (with_verdicts && set.verdicts.size() != set.indices.size())
    throw std::runtime_error("the visible set has " + std::to_string(set.indices.size()) + " ids and " +
                             std::to_string(set.verdicts.size()) + " verdicts");
  if (!with_verdicts && info.three_way && !set.indices.empty())
    throw std::runtime_error("a three-way system's visible set has no verdicts (" + std::to_string(set.indices.size()) +
                             " ids)");
  std::vector<bool> seen(position.size(), false);
  for (std::size_t k = 0; k < set.indices.size(); ++k) {
    const std::uint32_t id = set.indices[k];
    const auto it = position.find(id);
    if (it == position.end())
      throw std::runtime_error("entry " + std::to_string(k) + " of the visible set: id " + std::to_string(id) +
                               " is not in the scene");
    if (seen[it->second])
      throw std::runtime_error("entry " + std::to_string(k) + " of the visible set: id " + std::to_string(id) + " again");
    seen[it->second] = true;
    const Visibility v = with_verdicts ? set.verdicts[k] : Visibility::intersecting;
    if (v != Visibility::inside && v != Visibility::intersecting)
      throw std::runtime_error("entry " + std::to_string(k) + " of the visible set: id " + std::to_string(id) +
                               " listed with verdict " + (v == Visibility::outside ? std::string("outside") : std::to_string(int(v))));
    if (v == Visibility::inside && !info.three_way)
      throw std::runtime_error("entry " + std::to_string(k) + " of the visible set: id " + std::to_string(id) +
                               " answered inside by a two-way system");
    out[it->second] = v;
  }
}

RunJudgement judge_run(const System& system, const SceneRun& run) {
  RunJudgement j;
  std::unordered_map<std::uint32_t, std::size_t> position;
  position.reserve(run.scene.objects.size());
  for (std::size_t i = 0; i < run.scene.objects.size(); ++i) position.emplace(run.scene.objects[i].id, i);
  // The world volumes as they are this frame (moves applied), and their truths.
  std::vector<Volume> start;
  start.reserve(run.scene.objects.size());
  for (const SceneObject& o : run.scene.objects) start.push_back(o.world);
  SceneTruths truths(std::move(start));
  const std::vector<Volume>& world = truths.world();
  std::vector<Visibility> truth;

  auto t = Clock::now();
  std::unique_ptr<SystemState> state;
  guarded(system, "build", 0, [&] { state = system.build(run.scene); });
  if (!state) throw SystemFault("system '" + system.name + "' built nothing (a null state) for scene " + run.scene.name, 0);
  j.cull_seconds += seconds_since(t);

  VisibleSet set;
  std::vector<Visibility> verdicts;
  for (std::size_t k = 0; k < run.frames.size(); ++k) {
    const RunFrame& frame = run.frames[k];
    for (const SceneObject& o : frame.moved) truths.move(position.at(o.id), o.world);
    t = Clock::now();
    if (!frame.moved.empty()) guarded(system, "update", k, [&] { state->update(frame.moved); });
    set.clear();
    guarded(system, "cull", k, [&] { state->cull(frame.view, set); });
    j.cull_seconds += seconds_since(t);
    const double own = state->last_cull_ns();
    try {
      verdicts_by_position(system, position, set, verdicts);
    } catch (const std::exception& e) {
      throw SystemFault("system '" + system.name + "' on frame " + std::to_string(k) + ": " + e.what(), k);
    }

    t = Clock::now();
    const CaseFrustum& f = frame.view.frustum;
    truths.decide(f, truth);
    const std::uint64_t judged_before = j.judged;
    for (std::size_t i = 0; i < world.size(); ++i) {
      const Volume& v = world[i];
      if (!system.takes(v)) continue;
      const ErrorClass e = error_class(verdicts[i], truth[i], system.three_way);
      ++j.judged;
      j.truth_outside += truth[i] == Visibility::outside;
      ++j.by_class[std::size_t(e)];
      if (e == ErrorClass::correct) continue;
      Finding found;
      found.frame = k, found.id = run.scene.objects[i].id, found.object = i;
      found.verdict = verdicts[i], found.truth = truth[i], found.error = e;
      const bool exact_case = gen::float_exact(f, v);
      found.distance = needs_distance(system.claim, e, exact_case) ? error_distance(f, v, verdicts[i]) : 0.0;
      found.breaks_claim =
          violates_claim(system.claim, e, found.distance, system.tolerance, gen::case_scale(f, v), exact_case);
      if (!j.first_error) j.first_error = found;
      if (found.breaks_claim) {
        ++j.claim_broken;
        if (!j.first_broken) j.first_broken = found;
      }
    }
    j.judge_seconds += seconds_since(t);
    if (!std::isnan(own)) {
      j.own_cull_ns += own;
      ++j.own_culls;
      j.own_object_frames += j.judged - judged_before;
    }
  }
  j.oracle_calls = truths.oracle_calls();
  j.exact_decisions = truths.exact_decisions();
  return j;
}

namespace {

// Judges `system` on one run and adds it to the family's tally; a fault names the run.
void tally_run(const System& system, SceneRun run, const std::string& which, FamilyTally& t, std::uint64_t& judged,
               Clock::time_point start) {
  RunJudgement j;
  try {
    j = judge_run(system, run);
  } catch (const SystemFault& f) {
    throw SystemFault(std::string(f.what()) + " (" + which + ")", f.frame(), std::make_shared<const SceneRun>(std::move(run)));
  }
  ++t.runs;
  t.judged += j.judged;
  t.truth_outside += j.truth_outside;
  judged += j.judged;
  t.claim_broken += j.claim_broken;
  t.cull_seconds += j.cull_seconds;
  t.judge_seconds += j.judge_seconds;
  t.own_cull_ns += j.own_cull_ns;
  t.own_culls += j.own_culls;
  t.own_object_frames += j.own_object_frames;
  for (int c = 0; c < 5; ++c) t.by_class[c] += j.by_class[c];
  if (j.first_broken && !t.broken) {
    t.broken = j.first_broken;
    t.broken_run = std::move(run);
    t.seconds_to_broken = seconds_since(start);
    t.judged_to_broken = judged;
  }
}

}  // namespace

std::vector<FamilyTally> verify_system(const System& system, const VerifyRuns& runs) {
  std::vector<FamilyTally> out;
  const auto start = Clock::now();
  std::uint64_t judged = 0;
  for (const std::string& family : runs.families) {
    FamilyTally t;
    t.family = family;
    const std::uint64_t first = runs.only_index ? *runs.only_index : 0;
    const std::uint64_t last = runs.only_index ? first + 1 : runs.runs;
    for (std::uint64_t i = first; i < last; ++i)
      tally_run(system, draw_run(family, runs.seed, i, runs.size),
                "run " + std::to_string(i) + " of " + family + ", seed " + std::to_string(runs.seed), t, judged, start);
    out.push_back(std::move(t));
  }
  for (const SceneRun& run : runs.given) {
    FamilyTally t;
    t.family = run.family;
    tally_run(system, run, "scene " + run.scene.name, t, judged, start);
    out.push_back(std::move(t));
  }
  return out;
}

Case case_of(const SceneRun& run, std::size_t frame, std::size_t object) {
  Case c;
  const SceneObject& o = run.scene.objects.at(object);
  c.id = run.family + "-" + std::to_string(run.index) + "-f" + std::to_string(frame) + "-o" + std::to_string(o.id);
  c.frustum = run.frames.at(frame).view.frustum;
  c.volume = o.world;
  for (std::size_t k = 1; k <= frame; ++k)
    for (const SceneObject& m : run.frames[k].moved)
      if (m.id == o.id) c.volume = m.world;
  c.note = "scene " + run.scene.name + " (seed " + std::to_string(run.seed) + "), frame " + std::to_string(frame) +
           " (camera: " + run.frames[frame].camera + "), object " + std::to_string(o.id);
  return c;
}

}  // namespace cullproof::scenes

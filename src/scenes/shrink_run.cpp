// A run on which a system breaks its claim, shrunk to a smaller one on which it still does
// (cullproof/scenes/scenes.hpp): the frames after the failing one dropped, earlier frames dropped
// (their moves folded into the scene or the frame after), objects removed in halving chunks and
// then one by one (delta debugging, Zeller & Hildebrandt 2002), and moves dropped. Every try
// rebuilds the system from the scene and runs it through every frame: a system's state is under
// test, so no try reuses another's.
#include "cullproof/scenes/scenes.hpp"

#include <algorithm>
#include <unordered_map>
#include <unordered_set>

namespace cullproof::scenes {

namespace {

// Applies `moved` to `objects` (by id).
void apply(std::vector<SceneObject>& objects, const std::vector<SceneObject>& moved) {
  std::unordered_map<std::uint32_t, std::size_t> at;
  for (std::size_t i = 0; i < objects.size(); ++i) at.emplace(objects[i].id, i);
  for (const SceneObject& m : moved)
    if (const auto it = at.find(m.id); it != at.end()) objects[it->second] = m;
}

// Merges the moves of an earlier frame into a later one's (the later move of an object wins).
std::vector<SceneObject> merged(const std::vector<SceneObject>& earlier, const std::vector<SceneObject>& later) {
  std::vector<SceneObject> out = later;
  std::unordered_set<std::uint32_t> seen;
  for (const SceneObject& m : later) seen.insert(m.id);
  for (const SceneObject& m : earlier)
    if (!seen.count(m.id)) out.push_back(m);
  return out;
}

// The run from frame `first` to frame `last`: the moves before `first` folded into the scene.
SceneRun window(const SceneRun& run, std::size_t first, std::size_t last) {
  SceneRun out;
  out.family = run.family, out.seed = run.seed, out.index = run.index, out.motion = run.motion;
  out.scene = run.scene;
  for (std::size_t k = 1; k <= first; ++k) apply(out.scene.objects, run.frames[k].moved);
  out.frames.assign(run.frames.begin() + std::ptrdiff_t(first), run.frames.begin() + std::ptrdiff_t(last) + 1);
  out.frames.front().moved.clear();
  return out;
}

// The run without frame j (0 < j < last): its moves happen with the next frame's.
SceneRun without_frame(const SceneRun& run, std::size_t j) {
  SceneRun out = run;
  out.frames[j + 1].moved = merged(run.frames[j].moved, run.frames[j + 1].moved);
  out.frames.erase(out.frames.begin() + std::ptrdiff_t(j));
  return out;
}

// The run without the objects at positions [from, to) of its scene (and their moves).
SceneRun without_objects(const SceneRun& run, std::size_t from, std::size_t to) {
  SceneRun out = run;
  std::unordered_set<std::uint32_t> gone;
  for (std::size_t i = from; i < to; ++i) gone.insert(run.scene.objects[i].id);
  out.scene.objects.erase(out.scene.objects.begin() + std::ptrdiff_t(from), out.scene.objects.begin() + std::ptrdiff_t(to));
  for (RunFrame& f : out.frames)
    f.moved.erase(std::remove_if(f.moved.begin(), f.moved.end(), [&](const SceneObject& m) { return gone.count(m.id) != 0; }),
                  f.moved.end());
  return out;
}

// The run with object `id` never moving.
SceneRun without_moves(const SceneRun& run, std::uint32_t id) {
  SceneRun out = run;
  for (RunFrame& f : out.frames)
    f.moved.erase(std::remove_if(f.moved.begin(), f.moved.end(), [&](const SceneObject& m) { return m.id == id; }), f.moved.end());
  return out;
}

std::size_t moves_in(const SceneRun& run) {
  std::size_t n = 0;
  for (const RunFrame& f : run.frames) n += f.moved.size();
  return n;
}

struct Shrinker {
  const System& system;
  int budget;
  int tries = 0;

  bool spent() const { return tries >= budget; }
  // Whether the system breaks its claim on `r` (a fault is not the failure being shrunk).
  bool breaks(const SceneRun& r) {
    ++tries;
    try {
      return judge_run(system, r).claim_broken > 0;
    } catch (const SystemFault&) {
      return false;
    }
  }
  // Takes `candidate` when it still breaks the claim.
  bool take(SceneRun& run, SceneRun candidate) {
    if (spent() || !breaks(candidate)) return false;
    run = std::move(candidate);
    return true;
  }

  void frames_before(SceneRun& run) {
    // Start later: by halves of what lies before the last frame, then by one.
    for (std::size_t step = run.frames.size() / 2; step >= 1 && !spent(); step /= 2)
      while (run.frames.size() > step && take(run, window(run, step, run.frames.size() - 1))) {
      }
    for (std::size_t j = 1; j + 1 < run.frames.size() && !spent();)
      if (!take(run, without_frame(run, j))) ++j;
  }

  void objects(SceneRun& run) {
    for (std::size_t chunk = std::max<std::size_t>(run.scene.objects.size() / 2, 1); chunk >= 1 && !spent(); chunk /= 2) {
      for (std::size_t i = 0; i < run.scene.objects.size() && !spent();) {
        const std::size_t to = std::min(i + chunk, run.scene.objects.size());
        if (run.scene.objects.size() > to - i && take(run, without_objects(run, i, to))) continue;
        i = to;
      }
      if (chunk == 1) break;
    }
  }

  void moves(SceneRun& run) {
    std::vector<std::uint32_t> movers;
    for (const RunFrame& f : run.frames)
      for (const SceneObject& m : f.moved)
        if (std::find(movers.begin(), movers.end(), m.id) == movers.end()) movers.push_back(m.id);
    for (std::uint32_t id : movers)
      if (!spent()) take(run, without_moves(run, id));
  }
};

}  // namespace

SceneRun shrink_run(const System& system, const SceneRun& run, const Finding& failure, int budget, ShrinkStats* stats) {
  Shrinker s{system, budget};
  SceneRun best = window(run, 0, std::min(failure.frame, run.frames.size() - 1));
  if (!s.breaks(best)) best = run;  // the failure needs nothing after its frame, unless the system disagrees
  const std::size_t objects0 = run.scene.objects.size(), frames0 = run.frames.size(), moves0 = moves_in(run);
  // Objects first (each try is cheaper then), frames, moves, and objects again: fewer frames and
  // moves may let more objects go.
  s.objects(best);
  s.frames_before(best);
  s.moves(best);
  s.objects(best);
  if (stats) {
    stats->tries = s.tries;
    stats->objects_before = objects0, stats->objects_after = best.scene.objects.size();
    stats->frames_before = frames0, stats->frames_after = best.frames.size();
    stats->moves_before = moves0, stats->moves_after = moves_in(best);
    stats->budget_spent = s.spent();
  }
  return best;
}

}  // namespace cullproof::scenes

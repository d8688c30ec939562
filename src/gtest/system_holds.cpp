// system_holds and verify_system (cullproof/gtest/gtest.hpp): a culling system over the scene
// families, judged exactly.
#include "cullproof/gtest/gtest.hpp"

#include "helper_text.hpp"

#include <fmt/format.h>

#include <chrono>

namespace cullproof::testing {

namespace {

using detail::env;
using detail::env_number;

SystemOptions with_environment(SystemOptions o) {
  o.seed = env_number("CULLPROOF_SEED", o.seed);
  o.runs = env_number("CULLPROOF_RUNS", o.runs);
  o.size.objects = env_number("CULLPROOF_OBJECTS", o.size.objects);
  o.size.frames = env_number("CULLPROOF_FRAMES", o.size.frames);
  if (const auto f = env("CULLPROOF_SCENE_FAMILY")) o.families = scenes::parse_families(*f);
  return o;
}

std::string reproduce(const SystemOptions& o, const std::string& family, std::uint64_t index) {
  return fmt::format("CULLPROOF_SEED={} CULLPROOF_SCENE_FAMILY={} CULLPROOF_SCENE_INDEX={} CULLPROOF_OBJECTS={} "
                     "CULLPROOF_FRAMES={}",
                     o.seed, family, index, o.size.objects, o.size.frames);
}

}  // namespace

std::vector<FamilyTally> verify_system(const System& system, const SystemOptions& options) {
  const SystemOptions o = with_environment(options);
  const auto only = env("CULLPROOF_SCENE_INDEX");
  std::vector<FamilyTally> out;
  const auto start = std::chrono::steady_clock::now();
  std::uint64_t judged = 0;
  for (const std::string& family : o.families) {
    FamilyTally t;
    t.family = family;
    const std::uint64_t first = only ? env_number("CULLPROOF_SCENE_INDEX", 0) : 0;
    const std::uint64_t last = only ? first + 1 : o.runs;
    for (std::uint64_t i = first; i < last; ++i) {
      scenes::SceneRun run = scenes::draw_run(family, o.seed, i, o.size);
      const scenes::RunJudgement j = scenes::judge_run(system, run);
      ++t.runs;
      t.judged += j.judged;
      judged += j.judged;
      t.claim_broken += j.claim_broken;
      for (int c = 0; c < 5; ++c) t.by_class[c] += j.by_class[c];
      if (j.first_broken && !t.broken) {
        t.broken = j.first_broken;
        t.broken_run = std::move(run);
        t.seconds_to_broken = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        t.judged_to_broken = judged;
      }
    }
    out.push_back(std::move(t));
  }
  return out;
}

::testing::AssertionResult system_holds(const System& system, const SystemOptions& options) {
  const SystemOptions o = with_environment(options);
  std::vector<FamilyTally> tallies;
  try {
    tallies = verify_system(system, options);
  } catch (const scenes::SystemFault& f) {
    return ::testing::AssertionFailure() << "cullproof: FAULT: " << f.what();
  }
  std::uint64_t judged = 0, broken = 0;
  std::string counts;
  const FamilyTally* first = nullptr;
  for (const FamilyTally& t : tallies) {
    judged += t.judged;
    broken += t.claim_broken;
    if (t.claim_broken == 0) continue;
    counts += fmt::format("  {}: {} of {} object-frames ({} false rejects, {} false insides, {} false intersects, {} "
                          "under-insides)\n",
                          t.family, t.claim_broken, t.judged, t.by_class[int(ErrorClass::false_reject)],
                          t.by_class[int(ErrorClass::false_inside)], t.by_class[int(ErrorClass::false_intersect)],
                          t.by_class[int(ErrorClass::under_inside)]);
    if (!first) first = &t;
  }
  if (broken == 0)
    return ::testing::AssertionSuccess() << system.name << " holds its claim '" << to_string(system.claim) << "' on "
                                         << judged << " object-frames";
  const scenes::SceneRun& run = *first->broken_run;
  const scenes::Finding& f = *first->broken;
  const Case c = scenes::case_of(run, f.frame, f.object);
  std::string msg = fmt::format("{} ({} system) breaks its claim '{}' on {} of {} object-frames (seed {}):\n{}", system.name,
                                to_string(system.origin), to_string(system.claim), broken, judged, o.seed, counts);
  msg += fmt::format("first: run {} of {} ({} objects, {} frames, moving: {}), frame {} (camera: {}), object {}\n",
                     run.index, run.family, run.scene.objects.size(), run.frames.size(), run.motion, f.frame,
                     run.frames[f.frame].camera, f.id);
  msg += fmt::format("  {} says {} where the truth is {} ({}); distance to the verdict given {}\n", system.name,
                     to_string(f.verdict), to_string(f.truth), to_string(f.error), f.distance);
  msg += "  case: " + format_case(c) + "\n" + detail::hex_numbers(c) + "\n";
  msg += "  reproduce: " + reproduce(o, run.family, run.index) + "\n";
  return ::testing::AssertionFailure() << msg;
}

}  // namespace cullproof::testing

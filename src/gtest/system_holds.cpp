// system_holds and verify_system (cullproof/gtest/gtest.hpp): a culling system over the scene
// families, judged exactly.
#include "cullproof/gtest/gtest.hpp"

#include "helper_text.hpp"

#include <fmt/format.h>

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
  if (!o.corpus) o.corpus = std::filesystem::path("cullproof-corpus") / "systems";
  if (const auto c = env("CULLPROOF_CORPUS")) o.corpus = std::filesystem::path(*c);
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
  scenes::VerifyRuns runs;
  runs.runs = o.runs, runs.seed = o.seed, runs.size = o.size, runs.families = o.families;
  if (env("CULLPROOF_SCENE_INDEX")) runs.only_index = env_number("CULLPROOF_SCENE_INDEX", 0);
  return scenes::verify_system(system, runs);
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
  const scenes::SceneRun& found = *first->broken_run;
  scenes::ShrinkStats st;
  const scenes::SceneRun run = scenes::shrink_run(system, found, *first->broken, o.shrink_budget, &st);
  scenes::Finding f = *first->broken;
  try {
    if (const auto j = scenes::judge_run(system, run); j.first_broken) f = *j.first_broken;
  } catch (const scenes::SystemFault&) {
  }
  const Case c = scenes::case_of(run, f.frame, f.object);
  const std::string again = reproduce(o, found.family, found.index);
  std::string msg = fmt::format("{} ({} system) breaks its claim '{}' on {} of {} object-frames (seed {}):\n{}", system.name,
                                to_string(system.origin), to_string(system.claim), broken, judged, o.seed, counts);
  msg += fmt::format("first: run {} of {} ({} objects, {} frames, moving: {}), shrunk in {} system runs to {} object(s), "
                     "{} frame(s), {} move(s)\n",
                     found.index, found.family, found.scene.objects.size(), found.frames.size(), found.motion, st.tries,
                     run.scene.objects.size(), run.frames.size(), st.moves_after);
  msg += fmt::format("  on frame {} of the shrunk run (camera: {}), object {}: {} says {} where the truth is {} ({}); "
                     "distance to the verdict given {}\n",
                     f.frame, run.frames[f.frame].camera, f.id, system.name, to_string(f.verdict), to_string(f.truth),
                     to_string(f.error), f.distance);
  msg += "  case: " + format_case(c) + "\n" + detail::hex_numbers(c) + "\n";
  try {
    msg += "  record: " + scenes::write_system_record(*o.corpus, system, run, f, again).string() + "\n";
  } catch (const std::exception& e) {
    msg += std::string("  (the shrunk run could not be recorded: ") + e.what() + ")\n";
  }
  msg += "  reproduce: " + again + "\n";
  return ::testing::AssertionFailure() << msg;
}

}  // namespace cullproof::testing

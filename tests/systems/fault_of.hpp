// The fault a culling system makes on a small run, for the tests of faults (tests/systems,
// tests/protocol).
#pragma once

#include "cullproof/scenes/scenes.hpp"

#include <cstddef>
#include <string>

namespace cullproof::test {

/// What judge_run's SystemFault says for `s` on run 0 of `clusters` (seed 1, `objects` objects,
/// 3 frames), or "" when the run raises none.
inline std::string fault_of(const System& s, std::size_t objects) {
  const scenes::SceneRun run = scenes::draw_run("clusters", 1, 0, {objects, 3});
  try {
    scenes::judge_run(s, run);
  } catch (const scenes::SystemFault& f) {
    return f.what();
  }
  return "";
}

}  // namespace cullproof::test

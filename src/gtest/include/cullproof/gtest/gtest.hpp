// Verifying a culler from a GoogleTest test, in one line:
//
//   #include <cullproof/gtest/gtest.hpp>
//   TEST(MyCuller, HoldsItsClaim) { EXPECT_TRUE(cullproof::testing::claim_holds(my_method())); }
//
// claim_holds runs every case distribution against the method (the campaign of `cullproof
// verify`), checks its claim against the exact oracle, shrinks what breaks it, writes the shrunk
// cases to a corpus folder, and fails with the first one printed exactly: the case as a
// case-format line and its numbers as hex floats, the method's verdict, the truth, every other
// method's verdict, the oracle's witness, the distance, the corpus file and how to reproduce it.
//
// Environment overrides, so that a CI log's failure can be rerun as it happened:
//   CULLPROOF_SEED=S  CULLPROOF_DISTRIBUTION=NAME  CULLPROOF_INDEX=I  CULLPROOF_CASES=N
//   CULLPROOF_CORPUS=DIR
// A user's methods have no `cullproof verify` command line: the reproduce line of their cases is
// these variables.
#pragma once

#include "cullproof/campaign/campaign.hpp"
#include "cullproof/methods/methods.hpp"
#include "cullproof/scenes/scenes.hpp"
#include "cullproof/systems/system.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

namespace cullproof::testing {

struct ClaimOptions {
  std::uint64_t cases = 2000;  ///< per distribution (17 families x 2000 by default)
  std::uint64_t seed = 1;
  /// Every distribution, generic and hard, but `huge` (gen::no_overflow_distributions), unless
  /// set. `huge` takes coordinates, extents and coefficients to FLT_MAX, where a plain float
  /// culler's sums overflow: the example project's correct n/p-vertex culler and five of the six
  /// mutation controls break a conservative claim there (docs/float-range.md). A culler meant for
  /// the whole float range asks for it: `distributions = gen::parse_distributions("all")`.
  /// `subnormal` is in the default: those cullers hold there.
  std::vector<gen::Distribution> distributions = gen::no_overflow_distributions();
  /// Where shrunk failing cases are written (one file each, the corpus layout). Unset: a
  /// folder "cullproof-corpus" in the working directory (a test's build or CTest directory).
  std::optional<std::filesystem::path> corpus;
  int threads = 0;          ///< 0: all hardware threads
  int shrink_budget = 400;  ///< oracle calls per shrink
  /// Built-in methods whose verdicts are printed beside the method's on a failing case
  /// (they are not judged here).
  std::vector<std::string> beside = {"pn-vertex", "obb-pn-vertex", "sphere-plane", "point-plane",
                                     "pn-vertex-certified", "sat-certified"};
};

/// Whether `method` holds its claim on every case of the distributions (see the top of this
/// file). A method that faults (throws, answers what is not a verdict) fails with the fault.
::testing::AssertionResult claim_holds(const Method& method, const ClaimOptions& options = {});

/// The campaign behind claim_holds, for a test that wants the numbers (error counts, rates,
/// costs): the options with the environment overrides applied, run on `methods`.
VerifyResult verify_methods(const std::vector<Method>& methods, const ClaimOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Culling systems (cullproof/systems/system.hpp), in one line:
//
//   TEST(MySystem, HoldsItsClaim) { EXPECT_TRUE(cullproof::testing::system_holds(my_system())); }
//
// system_holds draws runs of every scene family (cullproof/scenes/scenes.hpp), runs the system
// over each (build, updates, a cull per frame) and judges every object of every frame exactly.
// It shrinks the first run that breaks the claim (fewer objects, fewer frames, fewer moves: each try
// rebuilds the system), records the shrunk run in the corpus folder, and fails with it: the run
// (family, index, seed, what moves, its size before and after shrinking), the frame and what the
// camera did, the object, the verdict and the truth, the case as a case-format line with its
// numbers in hex, the record's file, and how to rerun exactly the run it was found on:
//   CULLPROOF_SEED=S  CULLPROOF_SCENE_FAMILY=NAME  CULLPROOF_SCENE_INDEX=I  CULLPROOF_RUNS=N
//   CULLPROOF_OBJECTS=N  CULLPROOF_FRAMES=N  CULLPROOF_CORPUS=DIR

struct SystemOptions {
  std::uint64_t runs = 6;  ///< per family
  std::uint64_t seed = 1;
  scenes::RunSize size;    ///< objects and frames per run
  std::vector<std::string> families = scenes::parse_families("all");
  /// Where the shrunk failing run is recorded (scenes::write_system_record). Unset: a folder
  /// "cullproof-corpus/systems" in the working directory.
  std::optional<std::filesystem::path> corpus;
  int shrink_budget = 300;  ///< system runs per shrink
};

/// Whether `system` holds its claim on every object-frame of the runs. A fault (a phase threw, a
/// visible set that is not one) fails with the fault.
::testing::AssertionResult system_holds(const System& system, const SystemOptions& options = {});

/// The tally behind system_holds, per family, for a test that wants the numbers (the options with
/// the environment overrides applied).
using FamilyTally = scenes::FamilyTally;
std::vector<FamilyTally> verify_system(const System& system, const SystemOptions& options = {});

}  // namespace cullproof::testing

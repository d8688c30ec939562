// The mutation table for culling systems (docs/mutation.md): every planted bug refuted by the
// default system run (system_holds), every control holding; the seconds and object-frames to the
// first failure recorded.
#include "system_mutants.hpp"

#include "cullproof/gtest/gtest.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace cullproof;

namespace {

class SystemMutation : public ::testing::TestWithParam<mutants::SystemMutant> {};

TEST_P(SystemMutation, MutantRefutedControlHolds) {
  const mutants::SystemMutant& m = GetParam();
  const System s = mutants::make_system_mutant(m);
  cullproof::testing::SystemOptions o;
  o.corpus = std::filesystem::path(::testing::TempDir()) / "cullproof-system-mutants";
  const ::testing::AssertionResult r = cullproof::testing::system_holds(s, o);
  if (m.control()) {
    EXPECT_TRUE(r) << "control " << m.name << " flagged";
    return;
  }
  ASSERT_FALSE(r) << m.name << " (" << m.bug << ") was not refuted: " << r.message();
  const std::string msg = r.message();
  EXPECT_NE(msg.find(m.name + " (user system) breaks its claim 'conservative'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("reproduce: CULLPROOF_SEED="), std::string::npos) << msg;
  EXPECT_NE(msg.find("  record: "), std::string::npos) << msg;
  // The cost of the first failure (docs/mutation.md), and the families that show the bug.
  double seconds = -1.0;
  std::uint64_t judged = 0;
  std::string families;
  for (const cullproof::testing::FamilyTally& t : cullproof::testing::verify_system(s, o)) {
    if (!t.broken) continue;
    if (seconds < 0.0) seconds = t.seconds_to_broken, judged = t.judged_to_broken;
    families += (families.empty() ? "" : " ") + t.family;
  }
  RecordProperty("seconds_to_first_failure", std::to_string(seconds));
  RecordProperty("object_frames_to_first_failure", std::to_string(judged));
  RecordProperty("families", families);
}

INSTANTIATE_TEST_SUITE_P(Systems, SystemMutation, ::testing::ValuesIn(mutants::system_mutants()),
                         [](const ::testing::TestParamInfo<mutants::SystemMutant>& p) {
                           std::string name = p.param.name;
                           for (char& c : name)
                             if (c == '-') c = '_';
                           return name;
                         });

}  // namespace

// ctest -L mutation: the verifier tested by planted bugs. Each mutant (tests/mutants/mutants.cpp)
// goes through the test helper exactly as a user's culler would, with its default budget (every
// distribution, 2,000 cases each, seed 1): it must be refuted, with a shrunk case written to the
// corpus folder. Each control must hold its claim.
#include "mutants.hpp"

#include "cullproof/corpus.hpp"
#include "cullproof/gtest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace cullproof {
namespace {

std::vector<mutants::Mutant> every() { return mutants::all(); }

class Mutation : public ::testing::TestWithParam<mutants::Mutant> {};

TEST_P(Mutation, IsRefutedOrHolds) {
  const mutants::Mutant& m = GetParam();
  const auto dir = std::filesystem::temp_directory_path() /
                   ("cullproof-mutation-" + m.method.name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  testing::ClaimOptions o;
  o.corpus = dir;
  const ::testing::AssertionResult r = testing::claim_holds(m.method, o);
  if (m.control) {
    EXPECT_TRUE(r) << m.method.name << " (" << m.defect << ") is correct, yet:\n" << r.message();
  } else {
    EXPECT_FALSE(r) << m.method.name << " (" << m.defect << ") survived: " << r.message();
    const std::string msg = r.message();
    EXPECT_NE(msg.find("corpus file: "), std::string::npos) << "no shrunk case shown:\n" << msg;
    std::size_t kept = 0;
    for (const CorpusEntry& e : load_corpus(dir))
      kept += e.method == m.method.name && e.c.extra.at("violates_claim").get<bool>();
    EXPECT_GT(kept, 0u) << "no claim-breaking case written under " << dir;
  }
  std::filesystem::remove_all(dir);
}

std::string name_of(const ::testing::TestParamInfo<mutants::Mutant>& p) {
  std::string s = p.param.method.name;
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(PlantedBugs, Mutation, ::testing::ValuesIn(every()), name_of);

}  // namespace
}  // namespace cullproof

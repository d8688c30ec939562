// ctest -L mutation: the verifier tested by planted bugs. Each mutant (tests/mutants/mutants.cpp)
// goes through the test helper exactly as a user's culler would, with its default budget (every
// distribution, 2,000 cases each, seed 1): it must be refuted, with a shrunk case written to the
// corpus folder. Each control must hold its claim. Every one is run twice: linked in (the method
// interface) and behind the process protocol (mutant_adapter.cpp), as a culler in another
// language is verified.
#include "mutants.hpp"

#include "cullproof/corpus/corpus.hpp"
#include "cullproof/protocol/external.hpp"
#include "cullproof/gtest/gtest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <ostream>
#include <string>

namespace cullproof {
namespace {

struct Route {
  mutants::Mutant mutant;
  bool protocol = false;  // behind the process protocol instead of linked in
};

// How GoogleTest names a route in its output (instead of the bytes of the struct).
void PrintTo(const Route& r, std::ostream* os) { *os << r.mutant.method.name << (r.protocol ? " via the protocol" : ""); }

std::vector<Route> every() {
  std::vector<Route> out;
  for (const mutants::Mutant& m : mutants::all()) out.push_back({m, false});
  for (const mutants::Mutant& m : mutants::all()) out.push_back({m, true});
  return out;
}

// The method as the adapter program offers it (a process of its own for each test).
Method through_protocol(const std::string& name) {
  ExternalOptions o;
  o.command = {CULLPROOF_MUTANT_ADAPTER};
  for (Method& m : external_methods(o))
    if (m.name == name) return std::move(m);
  throw std::runtime_error("the mutant adapter does not offer " + name);
}

class Mutation : public ::testing::TestWithParam<Route> {};

TEST_P(Mutation, IsRefutedOrHolds) {
  const mutants::Mutant& m = GetParam().mutant;
  const Method method = GetParam().protocol ? through_protocol(m.method.name) : m.method;
  const auto dir = std::filesystem::temp_directory_path() /
                   ("cullproof-mutation-" + m.method.name + "-" + std::to_string(::getpid()) +
                    (GetParam().protocol ? "-protocol" : ""));
  std::filesystem::remove_all(dir);
  testing::ClaimOptions o;
  o.corpus = dir;
  const ::testing::AssertionResult r = testing::claim_holds(method, o);
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
    // Every record is judged as the judge judges it (its distance from the verdict given beyond
    // its allowance, after shrinking as before).
    for (const Rejudged& stale : rejudge(dir, {method}))
      ADD_FAILURE() << stale.id << ": recorded judgement is stale (violates " << stale.violated_before << " -> "
                    << stale.violates_now << ", distance " << stale.distance << ", allowance " << stale.allowance << ")";
  }
  std::filesystem::remove_all(dir);
}

std::string name_of(const ::testing::TestParamInfo<Route>& p) {
  std::string s = p.param.mutant.method.name + (p.param.protocol ? "_via_protocol" : "");
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(PlantedBugs, Mutation, ::testing::ValuesIn(every()), name_of);

}  // namespace
}  // namespace cullproof

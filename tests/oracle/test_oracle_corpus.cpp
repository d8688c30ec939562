// Every committed case (corpus/, examples/cases.jsonl, examples/float-range.jsonl, examples/engines/corpus/) through the oracle and the independent method:
// zero disagreements, and where a case records a truth, the oracle reproduces it.
#include "cullproof/io/case_io.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <vector>

namespace cullproof::oracle::test {
namespace {

namespace fs = std::filesystem;

std::vector<fs::path> case_files() {
  std::vector<fs::path> out;
  // The example cases and the engines' corpus; not examples/ as a whole, which holds npm's
  // package files and installed packages.
  out.push_back("examples/cases.jsonl");
  out.push_back("examples/float-range.jsonl");
  for (const char* dir : {"corpus", "examples/engines/corpus"}) {
    if (!fs::exists(dir)) continue;
    for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator(); ++it) {
      // corpus/scenes*/ hold scene descriptions, not cases.
      if (it->is_directory() && it.depth() == 0 && it->path().filename().string().rfind("scenes", 0) == 0) {
        it.disable_recursion_pending();
        continue;
      }
      const auto ext = it->path().extension();
      if (it->is_regular_file() && (ext == ".json" || ext == ".jsonl")) out.push_back(it->path());
    }
  }
  return out;
}

TEST(OracleCorpus, EveryCommittedCaseAgreesWithTheIndependentMethod) {
  int n = 0;
  for (const fs::path& file : case_files()) {
    for (const Case& c : read_cases(file)) {
      ++n;
      const Result r = classify(c.frustum, c.volume);
      EXPECT_EQ(r.truth, classify_independent(c.frustum, c.volume)) << file << " " << c.id;
      if (c.truth) {
        EXPECT_EQ(r.truth, *c.truth) << file << " " << c.id << ": recorded truth";
      }
    }
  }
  std::cout << n << " committed cases checked\n";
  EXPECT_GT(n, 0) << "no case files found under corpus/ or examples/";
}

}  // namespace
}  // namespace cullproof::oracle::test

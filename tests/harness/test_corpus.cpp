// ctest -L corpus: every committed corpus case replays. The truth recorded in the file is still
// the oracle's (and the independent exact method's), and the method's recorded verdict still
// reproduces (a fixed method must have its evidence moved out of the corpus deliberately).
#include "cullproof/corpus.hpp"
#include "cullproof/oracle.hpp"

#include <gtest/gtest.h>

#include <filesystem>

using namespace cullproof;

namespace {

std::vector<std::filesystem::path> corpus_files() { return corpus_case_files(CULLPROOF_CORPUS_DIR); }

class Corpus : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(Corpus, Replays) {
  const std::filesystem::path dir(CULLPROOF_CORPUS_DIR);
  std::vector<CorpusEntry> one;
  // load_corpus validates the record; load the directory holding this file and pick it.
  for (CorpusEntry& e : load_corpus(GetParam().parent_path()))
    if (e.file == GetParam()) one.push_back(std::move(e));
  ASSERT_EQ(one.size(), 1u);
  const CorpusEntry& e = one[0];
  const ReplayResult r = replay(e);
  EXPECT_FALSE(r.truth_changed) << e.file << ": recorded truth " << to_string(*e.c.truth) << ", oracle now "
                                << to_string(r.truth_now);
  EXPECT_EQ(oracle::classify_independent(e.c.frustum, e.c.volume), *e.c.truth)
      << e.file << ": the independent exact method disagrees";
  EXPECT_TRUE(r.reproduces) << e.file << ": " << e.method << " recorded " << to_string(e.verdict) << ", now "
                            << (r.verdict_now ? std::string(to_string(*r.verdict_now)) : std::string("does not apply"));
  EXPECT_TRUE(r.regressed.empty()) << e.file << ": methods correct in the record and wrong now: "
                                   << ::testing::PrintToString(r.regressed);
}

std::string test_name(const ::testing::TestParamInfo<std::filesystem::path>& info) {
  std::string s = std::filesystem::relative(info.param, CULLPROOF_CORPUS_DIR).replace_extension().string();
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Committed, Corpus, ::testing::ValuesIn(corpus_files()), test_name);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(Corpus);

}  // namespace

// ctest -L corpus: every committed corpus case replays. The truth recorded in the file is still
// the oracle's (and the independent exact method's), and the method's recorded verdict still
// reproduces (a fixed method must have its evidence moved out of the corpus deliberately). Every
// record's judgement (whether it breaks its claim, its distance to the verdict given, the
// allowance) is the judge's as it is now: a change to the judge is followed by `corpus rejudge`.
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <unistd.h>

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

TEST(CorpusJudgement, EveryRecordIsJudgedAsTheJudgeJudgesNow) {
  // rejudge rewrites what it finds stale: on a copy, nothing may need rewriting.
  const auto copy = std::filesystem::temp_directory_path() / ("cullproof-rejudge-" + std::to_string(::getpid()));
  std::filesystem::remove_all(copy);
  std::filesystem::copy(CULLPROOF_CORPUS_DIR, copy, std::filesystem::copy_options::recursive);
  const std::vector<Rejudged> stale = rejudge(copy, builtin_methods());
  std::filesystem::remove_all(copy);
  for (const Rejudged& r : stale)
    ADD_FAILURE() << r.id << ": recorded judgement differs from the judge's now (violates_claim "
                  << r.violated_before << " -> " << r.violates_now << ", distance to the verdict " << r.distance
                  << ", allowance " << r.allowance << "); run `cullproof corpus rejudge`";
  EXPECT_TRUE(stale.empty());
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

// The corpus under concurrency and faults, with the real program: two `cullproof verify` runs
// writing into the same corpus folder at once (the same seed, and different seeds), and runs killed
// with SIGKILL at random points while they write. Afterwards the folder holds only complete case
// files, each byte for byte the file an undisturbed run writes under that name, all of which the
// corpus reader reads; what else a killed writer may leave is its temporary file, hidden and named
// so that no reader takes it for a case (write_file_atomic). A later complete run fills in what the
// killed ones did not write.
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/io/files.hpp"
#include "harness_files.hpp"
#include "run_program.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <random>
#include <regex>
#include <string>
#include <thread>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using cullproof::test::files_under;

std::vector<std::string> verify_args(const fs::path& corpus, int seed) {
  // hoff96 falsely rejects rods: each run writes its shrunk evidence, a handful of files.
  return {CULLPROOF_BIN, "verify", "--seed", std::to_string(seed), "-d", "rod", "-d", "corner", "--method", "hoff96",
          "--cases", "200", "--threads", "1", "--corpus", corpus.string(), "--no-progress"};
}

// Files and folders under `dir` (0 when it does not exist).
std::size_t entries_under(const fs::path& dir) {
  std::error_code ec;
  std::size_t n = 0;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
    ++n;
  return n;
}

bool is_temporary(const std::string& relative) {
  static const std::regex tmp(R"(^\..+\.json\.tmp-[0-9]+-[0-9]+$)");
  return std::regex_match(fs::path(relative).filename().string(), tmp);
}

int wait_for(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

class CorpusUnderFaults : public ::testing::Test {
 protected:

  // An undisturbed run: its files, and the time from its first write to its last (as the entries
  // under its folder change).
  std::map<std::string, std::string> reference(int seed, double* write_seconds = nullptr) {
    const fs::path dir = root_ / ("reference-" + std::to_string(seed));
    const pid_t pid = cullproof::testing::start_program(verify_args(dir, seed));
    std::optional<Clock::time_point> first, last;
    std::size_t seen = 0;
    int status = 0;
    while (::waitpid(pid, &status, WNOHANG) == 0) {
      const std::size_t now = entries_under(dir);
      if (now != seen) {
        seen = now;
        last = Clock::now();
        if (!first) first = last;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "reference run, seed " << seed;
    if (write_seconds) *write_seconds = first ? std::chrono::duration<double>(*last - *first).count() : 0.0;
    const auto files = files_under(dir);
    EXPECT_GE(files.size(), 3u) << "the reference run writes evidence";
    for (const auto& [name, bytes] : files) EXPECT_FALSE(is_temporary(name)) << name << " left by a complete run";
    return files;
  }

  cullproof::testing::ScratchDir scratch_{"cullproof-corpus-faults"};
  const fs::path& root_ = scratch_.path();
};

// Only complete files of the references (by name and bytes), all readable; the rest temporaries.
void only_complete_files(const fs::path& dir, const std::vector<const std::map<std::string, std::string>*>& refs,
                         std::size_t* temporaries = nullptr) {
  std::size_t tmp = 0;
  for (const auto& [name, bytes] : files_under(dir)) {
    if (is_temporary(name)) {
      ++tmp;
      continue;
    }
    bool matches = false;
    for (const auto* ref : refs) {
      const auto it = ref->find(name);
      matches = matches || (it != ref->end() && it->second == bytes);
    }
    EXPECT_TRUE(matches) << name << " is not, byte for byte, a file an undisturbed run writes (" << bytes.size() << " bytes)";
  }
  try {
    const std::vector<cullproof::CorpusEntry> entries = cullproof::load_corpus(dir);
    EXPECT_EQ(entries.size(), cullproof::corpus_case_files(dir).size());
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the corpus reader chokes: " << e.what();
  }
  if (temporaries) *temporaries += tmp;
}

TEST_F(CorpusUnderFaults, TwoRunsAtOnceWriteOneCompleteFileEach) {
  const auto a = reference(3), b = reference(4);
  // The same seed twice at once: the same files, each written whole once (link() refuses the second).
  const fs::path same = root_ / "same-seed";
  const pid_t p1 = cullproof::testing::start_program(verify_args(same, 3));
  const pid_t p2 = cullproof::testing::start_program(verify_args(same, 3));
  for (pid_t p : {p1, p2}) {
    const int status = wait_for(p);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  EXPECT_EQ(files_under(same), a);
  // Two seeds at once: every file of either run, none clobbered by the other's.
  const fs::path both = root_ / "two-seeds";
  const pid_t q1 = cullproof::testing::start_program(verify_args(both, 3));
  const pid_t q2 = cullproof::testing::start_program(verify_args(both, 4));
  for (pid_t p : {q1, q2}) {
    const int status = wait_for(p);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  std::size_t temporaries = 0;
  only_complete_files(both, {&a, &b}, &temporaries);
  EXPECT_EQ(temporaries, 0u);
  for (const auto* ref : {&a, &b})
    for (const auto& [name, bytes] : *ref) EXPECT_TRUE(fs::exists(both / name)) << name << " missing";
}

TEST_F(CorpusUnderFaults, RunsKilledWhileWritingLeaveOnlyCompleteFiles) {
  double window = 0.0;
  const auto a = reference(3, &window);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> when(0.0, 1.0);
  // The kill's delay is drawn within the reference run's writing time, scaled down (halved) after
  // every run that ended before its kill: a run undisturbed by other work writes faster than the
  // reference did under a busy machine's load, and a run that ends is no test of a kill.
  double scale = std::max(window, 0.005);
  std::size_t temporaries = 0, killed = 0, partial = 0, runs = 0;
  for (int k = 0; k < 40 && killed < 10; ++k, ++runs) {
    // Each run writes into a folder of its own and is killed at a random point after its first
    // write began (the moment the folder appears with an entry), before the run would end.
    const fs::path dir = root_ / ("killed-" + std::to_string(k));
    const pid_t pid = cullproof::testing::start_program(verify_args(dir, 3));
    const double delay = scale * when(rng);
    std::optional<Clock::time_point> started;
    int status = 0;
    bool exited = false;
    while (!exited) {
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      if (!started && entries_under(dir) > 0) started = Clock::now();
      if (started && std::chrono::duration<double>(Clock::now() - *started).count() >= delay) break;
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (!exited) {
      ::kill(pid, SIGKILL);
      status = wait_for(pid);
      killed += WIFSIGNALED(status);
      exited = !WIFSIGNALED(status);
    }
    if (exited) scale /= 2;
    only_complete_files(dir, {&a}, &temporaries);
    std::size_t complete = 0;
    for (const auto& [name, bytes] : files_under(dir)) complete += !is_temporary(name);
    partial += complete < a.size();
    if (HasFailure()) return;
  }
  EXPECT_GE(killed, 10u) << "the runs must be killed while they write, not after (" << runs << " runs)";
  EXPECT_GE(partial, 3u) << "some runs must be killed before they wrote every file";
  // A complete run into a killed run's folder writes what it did not: nothing is lost for good.
  const fs::path dir = root_ / "killed-0";
  const int status = wait_for(cullproof::testing::start_program(verify_args(dir, 3)));
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::map<std::string, std::string> cases;
  for (auto& [name, bytes] : files_under(dir))
    if (!is_temporary(name)) cases[name] = bytes;
  EXPECT_EQ(cases, a);
  RecordProperty("runs", int(runs));
  RecordProperty("killed", int(killed));
  RecordProperty("killed_before_every_file", int(partial));
  RecordProperty("temporaries_left", int(temporaries));
}

}  // namespace

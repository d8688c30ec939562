// Every output of the cullproof program when writing it fails: a full disk (/dev/full, and a
// regular folder with the file-size limit below what is written, which fails the write as a full
// disk does), a read-only folder (for a test running as root, with the capabilities that bypass
// permissions dropped), a folder that cannot be made (under a regular file). The run stops with a
// non-zero status and an error naming the path, and leaves no half-written file: the folder holds
// what it held before.
#include "run_program.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using cullproof::testing::RunOptions;
using cullproof::testing::RunResult;
using cullproof::testing::run_program;

// A short run: hoff96 falsely rejects rods, so it writes corpus files as well.
std::vector<std::string> verify(std::vector<std::string> more) {
  std::vector<std::string> a = {CULLPROOF_BIN, "verify", "--seed", "3", "-d", "rod", "--method", "hoff96",
                                "--cases", "200", "--threads", "1", "--no-progress"};
  a.insert(a.end(), more.begin(), more.end());
  return a;
}

std::vector<std::string> files_under(const fs::path& dir) {
  std::vector<std::string> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (!e.is_directory()) out.push_back(fs::relative(e.path(), dir).string());
  return out;
}

std::string contents(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class FailingOutputs : public ::testing::Test {
 protected:

  // The program stopped with a non-zero status and an error "<file>: cannot write: ... <reason>",
  // the file being `path` or under it (a corpus folder).
  static void refused(const RunResult& r, const std::string& path, const std::string& reason) {
    EXPECT_FALSE(r.timed_out);
    EXPECT_EQ(r.signal, 0) << r.err;
    EXPECT_NE(r.exit_code, 0) << r.err;
    const std::size_t at = r.err.find("error: " + path);
    EXPECT_NE(at, std::string::npos) << "the error does not name " << path << ":\n" << r.err;
    EXPECT_NE(r.err.find(": cannot write: ", at), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(reason), std::string::npos) << r.err;
  }

  // A folder this run may not write into, as for a user (root's capabilities dropped).
  fs::path read_only(const std::string& name) {
    const fs::path d = dir_ / name;
    fs::create_directories(d);
    fs::permissions(d, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                           fs::perms::others_read | fs::perms::others_exec);
    return d;
  }

  cullproof::testing::ScratchDir scratch_{"cullproof-failing-outputs"};
  const fs::path& dir_ = scratch_.path();
};

TEST_F(FailingOutputs, JsonToAFullDevice) {
  RunOptions o;
  o.args = verify({"--no-corpus", "--json", "/dev/full"});
  refused(run_program(o), "/dev/full", "No space left on device");
  struct stat st{};
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/full was replaced instead of written";
}

TEST_F(FailingOutputs, JsonOnAFullDiskLeavesTheOldFileAndNoOther) {
  const fs::path out = dir_ / "result.json";
  std::ofstream(out) << "the previous result\n";
  RunOptions o;
  o.args = verify({"--no-corpus", "--json", out.string()});
  o.file_size_limit = 1000;  // the result is larger: the write fails as on a full disk
  refused(run_program(o), out.string(), "File too large");
  EXPECT_EQ(contents(out), "the previous result\n");
  EXPECT_EQ(files_under(dir_), std::vector<std::string>{"result.json"});
}

TEST_F(FailingOutputs, JsonIntoAReadOnlyFolder) {
  const fs::path ro = read_only("read-only");
  RunOptions o;
  o.args = verify({"--no-corpus", "--json", (ro / "result.json").string()});
  o.permissions_apply = true;
  const RunResult r = run_program(o);
  if (r.could_not_drop_capabilities) GTEST_SKIP() << "running as root without CAP_SETPCAP: permissions cannot apply";
  refused(r, (ro / "result.json").string(), "Permission denied");
  EXPECT_TRUE(files_under(ro).empty());
}

TEST_F(FailingOutputs, JsonIntoAFolderThatCannotBeMade) {
  std::ofstream(dir_ / "a-file") << "x";
  const fs::path out = dir_ / "a-file" / "sub" / "result.json";
  RunOptions o;
  o.args = verify({"--no-corpus", "--json", out.string()});
  refused(run_program(o), out.string(), "cannot create its directory");
  EXPECT_EQ(files_under(dir_), std::vector<std::string>{"a-file"});
}

TEST_F(FailingOutputs, CorpusOnAFullDiskStopsTheRunWithoutHalfFiles) {
  const fs::path corpus = dir_ / "corpus";
  RunOptions o;
  o.args = verify({"--corpus", corpus.string()});
  o.file_size_limit = 300;  // a corpus case is larger
  const RunResult r = run_program(o);
  refused(r, (corpus / "hoff96" / "rod").string(), "File too large");
  EXPECT_TRUE(files_under(corpus).empty()) << "left: " << (files_under(corpus).empty() ? "" : files_under(corpus)[0]);
}

TEST_F(FailingOutputs, CorpusInAReadOnlyFolder) {
  const fs::path ro = read_only("read-only-corpus");
  RunOptions o;
  o.args = verify({"--corpus", ro.string()});
  o.permissions_apply = true;
  const RunResult r = run_program(o);
  if (r.could_not_drop_capabilities) GTEST_SKIP() << "running as root without CAP_SETPCAP: permissions cannot apply";
  refused(r, (ro / "hoff96" / "rod").string(), "Permission denied");
  EXPECT_TRUE(files_under(ro).empty());
}

TEST_F(FailingOutputs, CorpusInAFolderThatCannotBeMade) {
  std::ofstream(dir_ / "a-file") << "x";
  const fs::path corpus = dir_ / "a-file" / "corpus";
  RunOptions o;
  o.args = verify({"--corpus", corpus.string()});
  refused(run_program(o), corpus.string(), "cannot create its directory");
  EXPECT_EQ(files_under(dir_), std::vector<std::string>{"a-file"});
}

TEST_F(FailingOutputs, SimulateCsvAndJson) {
  const fs::path scene = dir_ / "floor.json";
  std::ofstream(scene) << R"({"format": "cullproof-scene/1", "name": "floor-only", "floor": {"size": [20, 20], "tiles": [4, 4]},
    "projection": {"kind": "perspective", "fovy": 60, "aspect": 1.5, "near": 0.1, "far": 50},
    "camera": {"path": "translation", "frames": 3, "eye": [0, 2, 8]}})";
  const std::vector<std::string> simulate = {CULLPROOF_BIN, "simulate", scene.string(), "--no-progress", "--no-corpus"};
  RunOptions o;
  o.args = simulate;
  o.args.insert(o.args.end(), {"--csv", "/dev/full"});
  refused(run_program(o), "/dev/full", "No space left on device");
  const fs::path out = dir_ / "simulation.json";
  o.args = simulate;
  o.args.insert(o.args.end(), {"--json", out.string()});
  o.file_size_limit = 2000;
  refused(run_program(o), out.string(), "File too large");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(files_under(dir_), std::vector<std::string>{"floor.json"});
}

TEST_F(FailingOutputs, StandardOutputToAFullDevice) {
  RunOptions o;
  o.args = {CULLPROOF_BIN, "classify", std::string(CULLPROOF_SOURCE_DIR) + "/examples/cases.jsonl"};
  o.stdout_path = "/dev/full";
  const RunResult r = run_program(o);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("cannot write the standard output: No space left on device"), std::string::npos) << r.err;
}

// The same program writes them all when nothing fails (the tests above fail for the fault alone).
TEST_F(FailingOutputs, TheSameOutputsAreWrittenWhenNothingFails) {
  const fs::path out = dir_ / "result.json", corpus = dir_ / "corpus";
  RunOptions o;
  o.args = verify({"--corpus", corpus.string(), "--json", out.string()});
  const RunResult r = run_program(o);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(out));
  EXPECT_FALSE(files_under(corpus).empty());
}

}  // namespace

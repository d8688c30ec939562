// The fuzz targets' committed inputs, replayed in every build (label unit): the seeds of each
// reader (tests/fuzz/corpus/<reader>/) and the inputs that once broke one
// (tests/fuzz/regressions/<reader>/), each through the same checks as under libFuzzer
// (fuzz_inputs.hpp). A reader that crashes, throws anything but its documented error, or breaks a
// promise on one of them fails here, named with the file.
#include "fuzz_inputs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> inputs(const std::string& kind, const std::string& reader) {
  std::vector<fs::path> out;
  const fs::path dir = fs::path(CULLPROOF_FUZZ_DIR) / kind / reader;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string bytes_of(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Every input of `reader` through `check`; returns how many there were.
std::size_t replay(const std::string& reader, const std::function<void(std::string_view)>& check) {
  std::size_t n = 0;
  for (const std::string kind : {"corpus", "regressions"})
    for (const fs::path& file : inputs(kind, reader)) {
      ++n;
      try {
        check(bytes_of(file));
      } catch (const std::exception& e) {
        ADD_FAILURE() << file << ": " << e.what();
      }
    }
  return n;
}

}  // namespace

TEST(FuzzInputs, CaseReader) { EXPECT_GE(replay("case_reader", cullproof::fuzz::case_reader), 10u); }
TEST(FuzzInputs, SceneReader) { EXPECT_GE(replay("scene_reader", cullproof::fuzz::scene_reader), 5u); }
TEST(FuzzInputs, CorpusReader) { EXPECT_GE(replay("corpus_reader", cullproof::fuzz::corpus_reader), 5u); }
TEST(FuzzInputs, ProtocolReader) { EXPECT_GE(replay("protocol_reader", cullproof::fuzz::protocol_reader), 5u); }

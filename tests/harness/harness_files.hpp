// Files the harness tests write and read back: a scratch folder, and every file under a folder.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>

namespace cullproof::test {

/// An empty folder under the temporary directory, named after `what` and this process.
inline std::filesystem::path temp_dir(const std::string& what) {
  const auto d = std::filesystem::temp_directory_path() / ("cullproof-" + what + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  return d;
}

/// Every file under `dir` (none when it does not exist), by its path relative to `dir` with '/'
/// between names, with its bytes.
inline std::map<std::string, std::string> files_under(const std::filesystem::path& dir) {
  std::map<std::string, std::string> out;
  if (!std::filesystem::exists(dir)) return out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) {
      std::ifstream in(e.path(), std::ios::binary);
      out[std::filesystem::relative(e.path(), dir).generic_string()] =
          std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
  return out;
}

}  // namespace cullproof::test

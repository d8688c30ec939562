// A libFuzzer target: CULLPROOF_FUZZ_ENTRY (set by tests/fuzz/CMakeLists.txt) is the reader's check
// of fuzz_inputs.hpp that this executable runs on every input.
#include "fuzz_inputs.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cullproof::fuzz::CULLPROOF_FUZZ_ENTRY(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}

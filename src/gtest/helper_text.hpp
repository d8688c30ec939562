// Internal to src/gtest: what claim_holds and system_holds share, the environment overrides and
// a case's numbers printed exactly.
#pragma once

#include "cullproof/io/case_io.hpp"

#include <cstdint>
#include <optional>
#include <string>

namespace cullproof::testing::detail {

/// The variable's value; nullopt when it is unset or empty.
std::optional<std::string> env(const char* name);
/// The variable as a non-negative integer, `fallback` when unset; throws std::invalid_argument
/// naming the variable and its value otherwise.
std::uint64_t env_number(const char* name, std::uint64_t fallback);
/// The case's frustum and volume as hex floats, a line per plane.
std::string hex_numbers(const Case& c);

}  // namespace cullproof::testing::detail

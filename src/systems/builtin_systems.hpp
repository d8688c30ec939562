// Internal to src/systems: the constructors of cullproof's own systems.
#pragma once

#include "cullproof/systems/system.hpp"

#include <vector>

namespace cullproof::detail {

/// The built-in systems in registry order (bvh_systems.cpp).
std::vector<System> make_builtin_systems();

}  // namespace cullproof::detail

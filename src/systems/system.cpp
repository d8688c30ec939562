// The system interface (cullproof/systems/system.hpp): a System from its description and
// builder, and the registry of cullproof's own systems.
#include "cullproof/systems/system.hpp"

#include "builtin_systems.hpp"

#include <stdexcept>

namespace cullproof {

System::System(SystemInfo info, Build build) : SystemInfo(std::move(info)), build_(std::move(build)) {
  if (name.empty()) throw std::invalid_argument("a system needs a name");
  if (!build_) throw std::invalid_argument("system '" + name + "' has no build function");
  if (tolerance < 0.0 || !(tolerance == tolerance))
    throw std::invalid_argument("system '" + name + "': tolerance must be >= 0, not " + std::to_string(tolerance));
}

const std::vector<System>& builtin_systems() {
  static const std::vector<System> all = detail::make_builtin_systems();
  return all;
}

std::vector<System> builtin_systems(const std::vector<std::string>& names) {
  const auto& all = builtin_systems();
  if (names.empty()) return all;
  std::vector<System> out;
  for (const std::string& n : names) {
    const System* found = nullptr;
    for (const System& s : all)
      if (s.name == n) found = &s;
    if (!found) {
      std::string known;
      for (const System& s : all) known += (known.empty() ? "" : ", ") + s.name;
      throw std::invalid_argument("unknown system '" + n + "' (known: " + known + ")");
    }
    out.push_back(*found);
  }
  return out;
}

}  // namespace cullproof

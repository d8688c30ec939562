// The method registry: the families register themselves; names are checked to be unique.
#include "cullproof/methods.hpp"

#include <set>
#include <stdexcept>

namespace cullproof {

std::string_view to_string(Claim c) noexcept {
  switch (c) {
    case Claim::certified_conservative: return "certified-conservative";
    case Claim::certified_exact: return "certified-exact";
    case Claim::conservative: return "conservative";
    case Claim::exact: return "exact";
    case Claim::none: return "none";
  }
  return "invalid";
}

namespace {

std::vector<Method> build() {
  std::vector<Method> out;
  detail::register_cull_methods(out);
  detail::register_exact_methods(out);
  detail::register_certified_methods(out);
  std::set<std::string> seen;
  for (const Method& m : out) {
    if (!seen.insert(m.name).second)
      throw std::logic_error("cullproof: method name registered twice: " + m.name);
    if (!m.classify) throw std::logic_error("cullproof: method without classify: " + m.name);
  }
  return out;
}

}  // namespace

const std::vector<Method>& methods() {
  static const std::vector<Method> all = build();
  return all;
}

const Method* find_method(std::string_view name) {
  for (const Method& m : methods())
    if (m.name == name) return &m;
  return nullptr;
}

}  // namespace cullproof

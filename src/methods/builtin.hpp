// The built-in methods' registration (not installed): each family of methods registers itself
// from its own file (src/methods/cull_registry.cpp, src/methods/exact_registry.cpp, src/methods/certified_registry.cpp),
// describing each method field by field with `describe`.
#pragma once

#include "cullproof/methods/methods.hpp"

#include <string>
#include <utility>
#include <vector>

namespace cullproof::detail {

/// A method's per-frame phase that takes the case's planes as they are.
inline const auto planes = [](const CaseFrustum& f) { return f.planes; };

/// A MethodInfo written one named field at a time:
///   describe("pn-vertex", Origin::published).as("...").from("...").claims(Claim::conservative, 1e-6)
///       .on(kAabbKind).touching("...")
class describe {
 public:
  describe(std::string name, Origin origin) {
    info_.name = std::move(name);
    info_.origin = origin;
  }
  describe& as(std::string description) {
    info_.description = std::move(description);
    return *this;
  }
  describe& from(std::string source) {
    info_.source = std::move(source);
    return *this;
  }
  describe& claims(Claim c, double tolerance) {
    info_.claim = c;
    info_.tolerance = tolerance;
    return *this;
  }
  describe& on(unsigned volume_kinds) {
    info_.volumes = volume_kinds;
    return *this;
  }
  describe& touching(std::string rule) {
    info_.touching = std::move(rule);
    return *this;
  }
  describe& two_way() {
    info_.three_way = false;
    return *this;
  }
  describe& stateful() {
    info_.stateful = true;
    return *this;
  }
  operator MethodInfo() const { return info_; }

 private:
  MethodInfo info_;
};

/// One classify for several volume kinds: overload{[](S&, const Aabb&) {...}, [](S&, const Obb&) {...}}.
template <class... F>
struct overload : F... {
  using F::operator()...;
};
template <class... F>
overload(F...) -> overload<F...>;

void register_cull_methods(std::vector<Method>& out);       // src/methods/cull_registry.cpp
void register_exact_methods(std::vector<Method>& out);      // src/methods/exact_registry.cpp
void register_certified_methods(std::vector<Method>& out);  // src/methods/certified_registry.cpp

}  // namespace cullproof::detail

// Planted-bug cullers: the verifier's own test. Each mutant is a culler a programmer could have
// written, with one plausible defect (a comparison, a vertex chosen on one axis, a plane
// forgotten, a sign, a normalisation, matrix rows mixed up, a stale cache, a mask leaking to the
// next volume), declared with the claim its correct version holds. Each control is a correct
// culler written the same way, which must never be flagged. They are user methods, verified
// through the same paths a user's culler takes (the method interface and the test helper).
#pragma once

#include "cullproof/methods/methods.hpp"

#include <string>
#include <vector>

namespace cullproof::mutants {

struct Mutant {
  Method method;
  std::string defect;   ///< one line: what is wrong (for a control: what it is)
  bool control = false; ///< a correct culler: must hold its claim
};

/// The planted-bug cullers, then the controls, in a stable order. Stateful ones keep their state
/// in the Method (copies share it).
std::vector<Mutant> all();
/// The one named `name` (a fresh copy: a stateful one with its own state); throws
/// std::invalid_argument for an unknown name.
Method find(const std::string& name);

}  // namespace cullproof::mutants

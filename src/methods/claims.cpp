// The names of claims and origins (cullproof/methods/methods.hpp), apart from the method registry so that
// a reader of method descriptions (the process protocol's handshake) needs nothing else.
#include "cullproof/methods/methods.hpp"

#include <stdexcept>
#include <string>

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

Claim claim_from_string(std::string_view s) {
  for (Claim c : {Claim::certified_conservative, Claim::certified_exact, Claim::conservative, Claim::exact, Claim::none})
    if (to_string(c) == s) return c;
  throw std::invalid_argument("unknown claim '" + std::string(s) +
                              "' (known: certified-conservative, certified-exact, conservative, exact, none)");
}

std::string_view to_string(Origin o) noexcept {
  switch (o) {
    case Origin::published: return "published";
    case Origin::own: return "own";
    case Origin::user: return "user";
  }
  return "invalid";
}

}  // namespace cullproof

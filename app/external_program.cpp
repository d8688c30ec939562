// The program under test through the process protocol (docs/protocol.md), for classify, verify
// and corpus replay alike: its options, and the methods of a run.
#include "commands.hpp"

#include "cullproof/protocol/external.hpp"

#include <algorithm>
#include <chrono>
#include <optional>
#include <stdexcept>

namespace cullproof::app {

namespace {

constexpr int kMaxExternalTimeoutMs = 3600000;  ///< an hour for one answer of an external program

}  // namespace

void ExternalProgram::add_options(CLI::App* cmd) {
  cmd->add_option("--external", names,
                  "Run method NAME of the program given after '--' (the process protocol, docs/protocol.md; "
                  "repeatable, 'all': every method it offers); --method adds built-in ones beside it");
  cmd->add_option("--external-timeout", timeout_ms, "Milliseconds to wait for each answer of the program")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxExternalTimeoutMs));
  cmd->add_option("--external-handshake-timeout", handshake_timeout_ms,
                  "Milliseconds to wait for the program's handshake (when it starts, and when it is started again "
                  "after a fault)")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxExternalTimeoutMs));
  cmd->add_option("--external-jobs", jobs,
                  "Copies of the program to run side by side, asked by whichever thread is free (stateful "
                  "methods always through the first)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
}

namespace {

// The entries of `offered` named by `names` ('all': every one), each once, in the order named,
// then those of `builtin`; std::invalid_argument naming a name the program does not offer.
template <class T>
std::vector<T> chosen(const std::vector<T>& offered, const std::vector<std::string>& names, std::vector<T> builtin,
                      const std::string& kind) {
  std::string on_offer;
  for (const T& x : offered) on_offer += (on_offer.empty() ? "" : ", ") + x.name;
  std::vector<T> out;
  for (const std::string& wanted : names) {
    bool found = false;
    for (const T& x : offered)
      if (wanted == "all" || x.name == wanted) {
        found = true;
        if (std::none_of(out.begin(), out.end(), [&](const T& o) { return o.name == x.name; })) out.push_back(x);
      }
    if (!found)
      throw std::invalid_argument("the program offers no " + kind + " named '" + wanted + "' (it offers: " +
                                  (on_offer.empty() ? std::string("none") : on_offer) + ")");
  }
  for (T& b : builtin) out.push_back(std::move(b));
  return out;
}

// The program's options, or nullopt when no program is named; std::invalid_argument for a program
// without --external or the reverse.
std::optional<ExternalOptions> options_of(const ExternalProgram& p, int instances) {
  if (p.names.empty()) {
    if (!p.command.empty()) throw std::invalid_argument("a program after '--' needs --external NAME");
    return std::nullopt;
  }
  if (p.command.empty()) throw std::invalid_argument("--external " + p.names[0] + " needs the program after '--'");
  ExternalOptions eo;
  eo.command = p.command;
  eo.timeout = std::chrono::milliseconds(p.timeout_ms);
  eo.handshake_timeout = std::chrono::milliseconds(p.handshake_timeout_ms);
  eo.instances = instances;
  return eo;
}

}  // namespace

std::vector<Method> ExternalProgram::methods(const std::vector<std::string>& builtin, int instances) const {
  const auto eo = options_of(*this, instances);
  if (!eo) return builtin_methods(builtin);
  return chosen(external_methods(*eo), names, builtin.empty() ? std::vector<Method>{} : builtin_methods(builtin), "method");
}

std::vector<System> ExternalProgram::systems(const std::vector<std::string>& builtin) const {
  const auto eo = options_of(*this, 1);
  if (!eo) return builtin_systems(builtin);
  return chosen(external_systems(*eo), names, builtin.empty() ? std::vector<System>{} : builtin_systems(builtin), "system");
}

}  // namespace cullproof::app

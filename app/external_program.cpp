// The program under test through the process protocol (docs/protocol.md), for classify, verify
// and corpus replay alike: its options, and the methods of a run.
#include "commands.hpp"

#include "cullproof/protocol/external.hpp"

#include <algorithm>
#include <chrono>
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
  cmd->add_option("--external-jobs", jobs,
                  "Copies of the program to run side by side, asked by whichever thread is free (stateful "
                  "methods always through the first)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
}

// The program's methods named by --external ('all': every one it offers), beside the built-in
// ones named by --method, if any; or the built-in ones.
std::vector<Method> ExternalProgram::methods(const std::vector<std::string>& builtin, int instances) const {
  if (names.empty()) {
    if (!command.empty()) throw std::invalid_argument("a program after '--' needs --external NAME");
    return builtin_methods(builtin);
  }
  if (command.empty()) throw std::invalid_argument("--external " + names[0] + " needs the program after '--'");
  ExternalOptions eo;
  eo.command = command;
  eo.timeout = std::chrono::milliseconds(timeout_ms);
  eo.instances = instances;
  std::vector<Method> offered = external_methods(eo);
  std::string on_offer;
  for (const Method& m : offered) on_offer += (on_offer.empty() ? "" : ", ") + m.name;
  std::vector<Method> out;
  for (const std::string& wanted : names) {
    bool found = false;
    for (const Method& m : offered)
      if (wanted == "all" || m.name == wanted) {
        found = true;
        if (std::none_of(out.begin(), out.end(), [&](const Method& o) { return o.name == m.name; })) out.push_back(m);
      }
    if (!found) throw std::invalid_argument("the program offers no method named '" + wanted + "' (it offers: " + on_offer + ")");
  }
  if (!builtin.empty())
    for (Method& b : builtin_methods(builtin)) out.push_back(std::move(b));
  return out;
}

}  // namespace cullproof::app

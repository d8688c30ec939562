// cullproof: run culling methods and the exact oracle side by side.
//
//   cullproof methods [--json]
//   cullproof classify FILE... [--method NAME ...] [--no-oracle]
//
// Machine interface (keep stable): `methods --json` prints a JSON array of objects with at least
// name, claim, source, volumes; `classify` prints one JSON object per case and line.
#include "cullproof/case_io.hpp"
#include "cullproof/methods.hpp"
#ifdef CULLPROOF_HAVE_ORACLE
#include "cullproof/oracle.hpp"
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

using namespace cullproof;
using nlohmann::json;

namespace {

json volume_names(unsigned bits) {
  json a = json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

int cmd_methods(bool as_json) {
  if (as_json) {
    json out = json::array();
    for (const Method& m : methods()) {
      out.push_back({{"name", m.name},
                     {"description", m.description},
                     {"source", m.source},
                     {"claim", std::string(to_string(m.claim))},
                     {"volumes", volume_names(m.volumes)},
                     {"touching", m.touching},
                     {"tolerance", m.tolerance},
                     {"stateful", m.stateful}});
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%-28s %-24s %-24s %s\n", "method", "claim", "volumes", "source");
  for (const Method& m : methods()) {
    std::string vols;
    for (const auto& v : volume_names(m.volumes)) vols += (vols.empty() ? "" : ",") + v.get<std::string>();
    std::printf("%-28s %-24s %-24s %s\n", m.name.c_str(), std::string(to_string(m.claim)).c_str(), vols.c_str(),
                m.source.c_str());
    std::printf("%-28s %s\n", "", m.description.c_str());
  }
  std::printf("%zu methods\n", methods().size());
  return 0;
}

int cmd_classify(const std::vector<std::string>& files, const std::vector<std::string>& names, bool no_oracle) {
  std::vector<const Method*> selected;
  for (const std::string& n : names) {
    const Method* m = find_method(n);
    if (!m) {
      std::string known;
      for (const Method& k : methods()) known += (known.empty() ? "" : ", ") + k.name;
      std::cerr << "cullproof classify: unknown method '" << n << "' (known: " << known << ")\n";
      return 2;
    }
    selected.push_back(m);
  }
  if (names.empty())
    for (const Method& m : methods()) selected.push_back(&m);
  for (const std::string& file : files) {
    const std::vector<Case> cases = read_cases(file);  // throws CaseError naming file/line/field
    for (const Case& c : cases) {
      validate(c.frustum.planes, "frustum");
      json line = {{"id", c.id}};
      json verdicts = json::object();
      for (const Method* m : selected) {
        if (!m->takes(c.volume)) continue;
        const std::optional<Visibility> v = m->classify(c.frustum, c.volume);
        if (v) verdicts[m->name] = std::string(to_string(*v));
      }
      line["verdicts"] = verdicts;
#ifdef CULLPROOF_HAVE_ORACLE
      if (!no_oracle) {
        const json truth = oracle::to_json(oracle::classify(c.frustum, c.volume));
        for (auto it = truth.begin(); it != truth.end(); ++it) line[it.key()] = it.value();
      }
#else
      (void)no_oracle;
#endif
      std::cout << line.dump() << "\n";
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cullproof: proves view-frustum culling correct and shows what correctness costs"};
  app.require_subcommand(1);

  bool methods_json = false;
  auto* methods_cmd = app.add_subcommand("methods", "List every method: name, claim, volumes, source");
  methods_cmd->add_flag("--json", methods_json, "Print a JSON array (name, description, source, claim, volumes, ...)");

  std::vector<std::string> files, method_names;
  bool no_oracle = false;
  auto* classify_cmd = app.add_subcommand("classify", "Classify the cases in FILE (JSON or JSON Lines) with every method and the oracle");
  classify_cmd->add_option("files", files, "Case files (.jsonl: one case per line; otherwise one case)")->required()->check(CLI::ExistingFile);
  classify_cmd->add_option("--method,-m", method_names, "Run only these methods (repeatable)");
  classify_cmd->add_flag("--no-oracle", no_oracle, "Skip the exact oracle (truth, witness, distance)");

  CLI11_PARSE(app, argc, argv);
  try {
    if (*methods_cmd) return cmd_methods(methods_json);
    if (*classify_cmd) return cmd_classify(files, method_names, no_oracle);
  } catch (const CaseError& e) {
    std::cerr << "cullproof: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cullproof: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

// `cullproof methods` and `cullproof classify`: the methods, and every method and the oracle on
// the cases of files. Machine interface (keep stable): `methods --json` prints a JSON array of
// objects with at least name, claim, source, volumes; `classify` prints one JSON object per case
// and line.
#include "commands.hpp"

#include "cullproof/io/case_io.hpp"
#ifdef CULLPROOF_HAVE_ORACLE
#include "cullproof/oracle/oracle.hpp"
#endif

#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

namespace cullproof::app {

namespace {

nlohmann::json volume_names(unsigned bits) {
  nlohmann::json a = nlohmann::json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

int cmd_methods(bool as_json) {
  if (as_json) {
    nlohmann::json out = nlohmann::json::array();
    for (const Method& m : builtin_methods()) {
      out.push_back({{"name", m.name},
                     {"description", m.description},
                     {"source", m.source},
                     {"claim", std::string(to_string(m.claim))},
                     {"volumes", volume_names(m.volumes)},
                     {"touching", m.touching},
                     {"tolerance", m.tolerance},
                     {"stateful", m.stateful},
                     {"three_way", m.three_way},
                     {"batch", m.has_batch()},
                     {"origin", std::string(to_string(m.origin))}});
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::printf("%-28s %-24s %-24s %s\n", "method", "claim", "volumes", "source");
  for (const Method& m : builtin_methods()) {
    std::string vols;
    for (const auto& v : volume_names(m.volumes)) vols += (vols.empty() ? "" : ",") + v.get<std::string>();
    const std::string claim = std::string(to_string(m.claim)) + (m.three_way ? "" : ", two-way");
    std::printf("%-28s %-24s %-24s %s\n", m.name.c_str(), claim.c_str(), vols.c_str(), m.source.c_str());
    std::printf("%-28s %s\n", "", m.description.c_str());
  }
  std::printf("%zu methods\n", builtin_methods().size());
  return 0;
}

int cmd_classify(const std::vector<std::string>& files, const std::vector<Method>& selected, bool no_oracle) {
  for (const std::string& file : files) {
    const std::vector<Case> cases = read_cases(file);  // throws CaseError naming file/line/field
    for (const Case& c : cases) {
      // What goes wrong after reading is reported at the case's line too; nothing is printed for it.
      try {
        validate(c.frustum.planes, "frustum");
      } catch (const ValidationError& e) {
        throw CaseError(file, c.line, c.frustum.matrix ? "frustum.matrix" : "frustum.planes",
                        std::string("the planes taken from it in float are not finite (") + e.what() + ")");
      }
      nlohmann::json line = {{"id", c.id}};
      try {
        nlohmann::json verdicts = nlohmann::json::object();
        for (const Method& m : selected) {
          if (!m.takes(c.volume)) continue;
          const std::optional<Visibility> v = m.classify(c.frustum, c.volume);
          if (v) verdicts[m.name] = std::string(to_string(*v));
        }
        line["verdicts"] = verdicts;
#ifdef CULLPROOF_HAVE_ORACLE
        if (!no_oracle) {
          const nlohmann::json truth = oracle::to_json(oracle::classify(c.frustum, c.volume));
          for (auto it = truth.begin(); it != truth.end(); ++it) line[it.key()] = it.value();
        }
#else
        (void)no_oracle;
#endif
      } catch (const std::exception& e) {
        throw CaseError(file, c.line, "", std::string("cannot classify this case: ") + e.what());
      }
      std::cout << line.dump() << "\n";
    }
  }
  return 0;
}

}  // namespace

void add_methods(CLI::App& app, MethodsCommand& c) {
  c.cmd = app.add_subcommand("methods", "List every method: name, claim, volumes, source");
  c.cmd->add_flag("--json", c.json, "Print a JSON array (name, description, source, claim, volumes, ...)");
}

int run_methods_command(const MethodsCommand& c) { return cmd_methods(c.json); }

void add_classify(CLI::App& app, ClassifyCommand& c) {
  c.cmd = app.add_subcommand("classify", "Classify the cases in FILE (JSON or JSON Lines) with every method and the oracle");
  c.cmd->add_option("files", c.files, "Case files (.jsonl: one case per line; otherwise one case)")->required()->check(CLI::ExistingFile);
  c.cmd->add_option("--method,-m", c.methods, "Run only these methods (repeatable)");
  c.cmd->add_flag("--no-oracle", c.no_oracle, "Skip the exact oracle (truth, witness, distance)");
}

int run_classify_command(const ClassifyCommand& c, const ExternalProgram& external) {
  std::vector<Method> selected;
  try {
#ifdef CULLPROOF_HAVE_ORACLE
    selected = external.methods(c.methods);
#else
    (void)external;
    selected = builtin_methods(c.methods);
#endif
  } catch (const std::invalid_argument& e) {
    std::cerr << "cullproof classify: " << e.what() << "\n";
    return 2;
  }
  return cmd_classify(c.files, selected, c.no_oracle);
}

}  // namespace cullproof::app

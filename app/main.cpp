// cullproof: run culling methods and the exact oracle side by side.
//
//   cullproof methods [--json]
//   cullproof classify FILE... [--method NAME ...] [--no-oracle] [--external NAME ... -- PROGRAM ARGS...]
//   cullproof verify [--cases N] [--seed S] [--distribution D ...] [--method M ...] [--threads T]
//                    [--external NAME|all ... [--external-timeout MS] -- PROGRAM ARGS...]
//                    [--corpus DIR | --no-corpus] [--json FILE] [--index I]
//   cullproof corpus list|show ID|replay [--dir DIR] [--strict] [--external NAME|all -- PROGRAM ARGS...]
//   cullproof report [--from FILE | verify's options] [--out FILE] [--corpus DIR | --no-corpus]
//   cullproof simulate [SCENE...] [--exhaustive] [--frames N] [--csv FILE] [--json FILE] [--table1]
//
// Machine interface (keep stable): `methods --json` prints a JSON array of objects with at least
// name, claim, source, volumes; `classify` prints one JSON object per case and line.
#include "cullproof/case_io.hpp"
#include "cullproof/cli_checks.hpp"
#include "cullproof/methods.hpp"
#ifdef CULLPROOF_HAVE_ORACLE
#include "cullproof/campaign.hpp"
#include "cullproof/corpus.hpp"
#include "cullproof/external.hpp"
#include "cullproof/oracle.hpp"
#endif
#ifdef CULLPROOF_HAVE_SIM
#include "cullproof/simulate_cli.hpp"
#endif
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/case_view.hpp"
#include "cullproof/report_cli.hpp"
#include "cullproof/summary.hpp"
#endif

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <type_traits>
#include <variant>
#include <iostream>
#include <string>
#include <vector>

using namespace cullproof;
using nlohmann::json;

namespace {

// Ranges of the numeric options: CLI11 refuses a value outside, naming the option and the range,
// before anything runs (seed and index take any 64-bit unsigned value).
/// Cases per distribution: a run keeps about 330 bytes a case, 3.3 GB at the limit (a hundred
/// times the default).
constexpr std::uint64_t kMaxCases = 10000000;
constexpr int kMaxThreads = 1024;  ///< worker threads (0: all cores)
constexpr int kMaxExternalTimeoutMs = 3600000;  ///< an hour for one answer of an external program
constexpr std::uint64_t kMaxUnsigned = std::numeric_limits<std::uint64_t>::max();

json volume_names(unsigned bits) {
  json a = json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

int cmd_methods(bool as_json) {
  if (as_json) {
    json out = json::array();
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
      json line = {{"id", c.id}};
      try {
        json verdicts = json::object();
        for (const Method& m : selected) {
          if (!m.takes(c.volume)) continue;
          const std::optional<Visibility> v = m.classify(c.frustum, c.volume);
          if (v) verdicts[m.name] = std::string(to_string(*v));
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
      } catch (const std::exception& e) {
        throw CaseError(file, c.line, "", std::string("cannot classify this case: ") + e.what());
      }
      std::cout << line.dump() << "\n";
    }
  }
  return 0;
}


#ifdef CULLPROOF_HAVE_ORACLE
std::string fmt_distance(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", d);
  return buf;
}

// The methods of a run: the external program's methods named by --external (`all`: every one it
// offers), beside the built-in ones named by --method, if any; or the built-in ones.
std::vector<Method> run_methods(const std::vector<std::string>& builtin, const std::vector<std::string>& external,
                                const std::vector<std::string>& command, int timeout_ms, int instances = 1) {
  if (external.empty()) {
    if (!command.empty()) throw std::invalid_argument("a program after '--' needs --external NAME");
    return builtin_methods(builtin);
  }
  if (command.empty()) throw std::invalid_argument("--external " + external[0] + " needs the program after '--'");
  ExternalOptions eo;
  eo.command = command;
  eo.timeout = std::chrono::milliseconds(timeout_ms);
  eo.instances = instances;
  std::vector<Method> offered = external_methods(eo);
  std::string names;
  for (const Method& m : offered) names += (names.empty() ? "" : ", ") + m.name;
  std::vector<Method> out;
  for (const std::string& wanted : external) {
    bool found = false;
    for (const Method& m : offered)
      if (wanted == "all" || m.name == wanted) {
        found = true;
        if (std::none_of(out.begin(), out.end(), [&](const Method& o) { return o.name == m.name; })) out.push_back(m);
      }
    if (!found) throw std::invalid_argument("the program offers no method named '" + wanted + "' (it offers: " + names + ")");
  }
  if (!builtin.empty())
    for (Method& b : builtin_methods(builtin)) out.push_back(std::move(b));
  return out;
}

int cmd_verify(VerifyOptions opt, const std::vector<std::string>& dists, const std::string& json_file,
               const std::vector<Method>& methods) {
  if (!dists.empty()) {
    opt.distributions.clear();
    for (const std::string& d : dists)
      for (gen::Distribution x : gen::parse_distributions(d))
        if (std::find(opt.distributions.begin(), opt.distributions.end(), x) == opt.distributions.end())
          opt.distributions.push_back(x);
  }
  VerifyResult r;
  try {
    r = run_verify(opt, methods);
  } catch (const MethodFault& e) {
    std::cerr << "cullproof verify: FAULT: " << e.what() << "\n";
    return 3;
  }
  print_tables(r, std::cout);
  if (!json_file.empty()) write_file_atomic(json_file, to_json(r).dump(2) + "\n");
  std::size_t written = 0;
  for (const auto& d : r.distributions)
    for (const auto& m : d.methods) written += m.corpus_written.size();
  if (opt.corpus) std::cout << "corpus: " << written << " new case(s) written under " << opt.corpus->string() << "\n";
#ifdef CULLPROOF_HAVE_REPORT
  report::print_summary(report::summarize(to_json(r)), std::cout);
#endif
  if (r.claim_broken()) {
    std::cout << "FAILED: a claim of one of cullproof's own methods or of a user's method was refuted (see REFUTED above)\n";
    return 1;
  }
  return 0;
}

// Where the volume lies relative to each plane: the range of the normalised plane function
// over the volume, in double.
std::string describe_planes(const Case& c) {
  std::string out;
  for (int i = 0; i < kPlaneCount; ++i) {
    const Plane& p = c.frustum.planes[i];
    const std::string name(plane_name(i));
    if (p.is_degenerate()) {
      out += "  " + name + ": " + (p.d >= 0 ? "contains all space" : "contains nothing") + "\n";
      continue;
    }
    const glm::dvec3 n(p.n);
    const double len = glm::length(n);
    double lo = 0, hi = 0;
    std::visit(
        [&](const auto& v) {
          using T = std::decay_t<decltype(v)>;
          if constexpr (std::is_same_v<T, Point>) {
            lo = hi = (glm::dot(n, glm::dvec3(v)) + p.d) / len;
          } else if constexpr (std::is_same_v<T, Sphere>) {
            const double s = (glm::dot(n, glm::dvec3(v.center)) + p.d) / len;
            lo = s - v.radius;
            hi = s + v.radius;
          } else {
            const Obb b = [&] {
              if constexpr (std::is_same_v<T, Aabb>) return to_obb(v); else return v;
            }();
            const double s = (glm::dot(n, glm::dvec3(b.center)) + p.d) / len;
            double r = 0;
            for (int a = 0; a < 3; ++a) r += double(b.half[a]) * std::abs(glm::dot(n, glm::dvec3(b.axes[a]))) / len;
            lo = s - r;
            hi = s + r;
          }
        },
        c.volume);
    std::string where = hi < 0 ? "outside, by " + format_float(float(-hi))
                        : lo > 0 ? "inside, clear by " + format_float(float(lo))
                        : lo == 0 ? "inside, touching"
                        : hi == 0 ? "outside, touching"
                                  : "straddles";
    out += "  " + name + ": " + where + "  (signed distance " + format_float(float(lo)) + " .. " + format_float(float(hi)) + ")\n";
  }
  return out;
}

// `methods`: what replay runs (the built-in ones, or a program's beside them); `only_external`:
// replay only the cases of the program's methods. `strict`: replay fails unless every case still
// fails as recorded.
int cmd_corpus(const std::string& action, const std::string& dir, const std::string& id, const std::vector<Method>& methods,
               bool only_external, bool strict) {
  std::vector<CorpusEntry> entries = load_corpus(dir);
  if (only_external) {
    const std::size_t all = entries.size();
    entries.erase(std::remove_if(entries.begin(), entries.end(),
                                 [&](const CorpusEntry& e) {
                                   return std::none_of(methods.begin(), methods.end(), [&](const Method& m) {
                                     return !m.program.empty() && m.name == e.method;
                                   });
                                 }),
                  entries.end());
    std::printf("%zu of %zu cases are of the program's methods\n", entries.size(), all);
  }
  if (action == "list") {
    std::printf("%-48s %-22s %-16s %-18s %s\n", "id", "method", "class", "distribution", "distance");
    for (const auto& e : entries) {
      const auto d = e.c.extra.find("distance");
      const std::string dist = d != e.c.extra.end() && d->is_number() ? fmt_distance(d->get<double>()) : "-";
      std::printf("%-48s %-22s %-16s %-18s %s\n", e.c.id.c_str(), e.method.c_str(), std::string(to_string(e.error)).c_str(),
                  e.distribution.c_str(), dist.c_str());
    }
    std::printf("%zu cases\n", entries.size());
    return 0;
  }
  if (action == "show") {
    for (const auto& e : entries) {
      if (e.c.id != id) continue;
      std::cout << "file: " << e.file.string() << "\n" << format_case(e.c, true) << "\n";
      const oracle::Result t = oracle::classify(e.c.frustum, e.c.volume);
      std::cout << "truth (oracle, now): " << to_string(t.truth) << "  distance " << t.distance << " ("
                << oracle::to_string(t.distance_kind) << ")\n";
      if (e.path)
        std::cout << "camera path: " << e.path->frames.size() << " frame(s) (" << e.path->motion << "), "
                  << e.path->objects.size() << " object(s); verdicts are taken over it\n";
      std::cout << "verdicts now:\n";
      for (const Method& m : builtin_methods()) {
        if (!m.takes(e.c.volume)) continue;
        const auto v = e.path ? checked_classify_path(m, *e.path) : m.classify(e.c.frustum, e.c.volume);
        if (!v) continue;
        const ErrorClass cls = error_class(*v, t.truth, m.three_way);
        std::printf("  %-26s %-13s %s\n", m.name.c_str(), std::string(to_string(*v)).c_str(),
                    cls == ErrorClass::correct ? "" : std::string(to_string(cls)).c_str());
      }
      std::cout << "where the volume lies, plane by plane (normalised):\n" << describe_planes(e.c);
      std::cout << "witness: " << oracle::to_json(t.witness).dump() << "\n";
      return 0;
    }
    std::cerr << "cullproof corpus show: no case with id '" << id << "' under " << dir << "\n";
    return 2;
  }
  if (action == "rerecord") {
    const Method* m = find_builtin(id);
    if (!m) {
      std::cerr << "cullproof corpus rerecord: no method named '" << id << "' (see cullproof methods)\n";
      return 2;
    }
    const std::vector<Rerecorded> changed = rerecord_verdicts(dir, *m);
    for (const Rerecorded& r : changed)
      std::printf("%s: %s %s -> %s\n", r.file.string().c_str(), m->name.c_str(), r.before.c_str(),
                  r.after.empty() ? "(does not apply)" : r.after.c_str());
    std::printf("%zu record(s) rewritten with %s's verdict now\n", changed.size(), m->name.c_str());
    return 0;
  }
  // replay
  std::size_t still = 0, fixed = 0, changed = 0, truth_changed = 0, regressed = 0;
  for (const auto& e : entries) {
    const ReplayResult r = replay(e, methods);
    const char* status = r.truth_changed ? "TRUTH CHANGED"
                         : r.reproduces  ? "still failing"
                         : r.fixed       ? "fixed"
                                         : "changed";
    if (r.truth_changed) ++truth_changed;
    else if (r.reproduces) ++still;
    else if (r.fixed) ++fixed;
    else ++changed;
    if (!r.regressed.empty()) ++regressed;
    std::string reg;
    for (const auto& m : r.regressed) reg += " " + m;
    std::printf("%-48s %-14s%s%s\n", e.c.id.c_str(), status, reg.empty() ? "" : "  regressed:", reg.c_str());
  }
  std::printf("%zu cases: %zu still failing, %zu fixed, %zu changed, %zu with regressions, %zu truth changed\n",
              entries.size(), still, fixed, changed, regressed, truth_changed);
  if (strict && still != entries.size()) {
    std::printf("FAILED: %zu case(s) no longer fail as recorded (--strict)\n", entries.size() - still);
    return 1;
  }
  return (truth_changed || regressed) ? 1 : 0;
}
#endif
}  // namespace

static int run(int argc, char** argv) {
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
  std::vector<std::string> external, external_command;
  int external_timeout = 10000, external_jobs = 1;
  // The process protocol (docs/protocol.md), for classify and verify alike.
  auto external_options = [&](CLI::App* cmd) {
    cmd->add_option("--external", external,
                    "Run method NAME of the program given after '--' (the process protocol, docs/protocol.md; "
                    "repeatable, 'all': every method it offers); --method adds built-in ones beside it");
    cmd->add_option("--external-timeout", external_timeout, "Milliseconds to wait for each answer of the program")
        ->capture_default_str()
        ->check(CLI::Range(1, kMaxExternalTimeoutMs));
    cmd->add_option("--external-jobs", external_jobs,
                    "Copies of the program to run side by side, asked by whichever thread is free (stateful "
                    "methods always through the first)")
        ->capture_default_str()
        ->check(CLI::Range(1, 256));
  };

#ifdef CULLPROOF_HAVE_ORACLE
  VerifyOptions vopt;
  vopt.corpus = std::filesystem::path("corpus");
  std::vector<std::string> dists;
  std::string json_file, corpus_dir = "corpus";
  bool no_corpus = false, no_progress = false;
  std::uint64_t index = 0;
  auto* verify_cmd = app.add_subcommand("verify", "The side-by-side verification run: every method and the oracle on generated cases");
  verify_cmd->add_option("--cases", vopt.cases, "Cases per distribution")
      ->capture_default_str()
      ->check(cli::UnsignedRange(1, kMaxCases));
  verify_cmd->add_option("--seed", vopt.seed, "Seed: the same seed gives the same cases and verdicts")
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, kMaxUnsigned));
  verify_cmd->add_option("--distribution,-d", dists, "Distributions (repeatable; 'all', 'all-generic', 'all-hard')");
  verify_cmd->add_option("--method,-m", vopt.methods, "Methods (repeatable; default: all)");
  verify_cmd->add_option("--threads", vopt.threads, "Worker threads (0: all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxThreads));
  verify_cmd->add_option("--corpus", corpus_dir, "Write new mismatches under DIR")->capture_default_str();
  verify_cmd->add_flag("--no-corpus", no_corpus, "Do not write the corpus");
  verify_cmd->add_option("--json", json_file, "Write the whole result as JSON to FILE");
  auto* index_opt = verify_cmd->add_option("--index", index, "Run only case INDEX of each distribution (reproduce)")
                        ->check(cli::UnsignedRange(0, kMaxUnsigned));
  external_options(verify_cmd);
  verify_cmd->add_flag("--no-progress", no_progress, "No progress bar");

  std::string corpus_action, corpus_id, corpus_root = "corpus";
  auto* corpus_cmd = app.add_subcommand("corpus", "Inspect and replay the mismatch corpus");
  corpus_cmd->add_option("action", corpus_action, "list | show ID | replay | rerecord METHOD (after a deliberate change to METHOD: its verdict in every record taken again)")
      ->required()
      ->check(CLI::IsMember({"list", "show", "replay", "rerecord"}));
  corpus_cmd->add_option("id", corpus_id, "Case id (show), method name (rerecord)");
  corpus_cmd->add_option("--dir", corpus_root, "Corpus directory")->capture_default_str();
  bool strict = false;
  corpus_cmd->add_flag("--strict", strict, "replay: fail unless every case still fails as recorded");
  std::string corpus_html, corpus_svg, corpus_zoom_svg;
#ifdef CULLPROOF_HAVE_REPORT
  corpus_cmd->add_option("--html", corpus_html, "show: write the case in 3D as a self-contained page to FILE");
  corpus_cmd->add_option("--svg", corpus_svg, "show: write its three-view drawing (front, top, side) to FILE");
  corpus_cmd->add_option("--zoom-svg", corpus_zoom_svg, "show: the same, magnified around the error, to FILE");
#endif
  external_options(corpus_cmd);
#endif

#ifdef CULLPROOF_HAVE_SIM
  cullproof::sim::SimulateOptions sim_opt;
  auto* simulate_cmd = cullproof::sim::add_simulate_subcommand(app, sim_opt);
#endif

#ifdef CULLPROOF_HAVE_ORACLE
  external_options(classify_cmd);
#endif
#ifdef CULLPROOF_HAVE_REPORT
  report::ReportOptions report_opt;
  auto* report_cmd = report::add_report_subcommand(app, report_opt);
#endif

  // Everything after the first '--' is the external program's command line, taken before the
  // subcommands' own positional arguments (classify's files) can claim it.
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--") {
      external_command.assign(argv + i + 1, argv + argc);
      argc = i;
      break;
    }
  CLI11_PARSE(app, argc, argv);
  try {
    if (*methods_cmd) return cmd_methods(methods_json);
    if (*classify_cmd) {
      std::vector<Method> selected;
      try {
#ifdef CULLPROOF_HAVE_ORACLE
        selected = run_methods(method_names, external, external_command, external_timeout);
#else
        selected = builtin_methods(method_names);
#endif
      } catch (const std::invalid_argument& e) {
        std::cerr << "cullproof classify: " << e.what() << "\n";
        return 2;
      }
      return cmd_classify(files, selected, no_oracle);
    }
#ifdef CULLPROOF_HAVE_SIM
    if (*simulate_cmd) return cullproof::sim::run_simulate_command(sim_opt);
#endif
#ifdef CULLPROOF_HAVE_REPORT
    if (*report_cmd) return report::run_report_command(report_opt);
#endif
#ifdef CULLPROOF_HAVE_ORACLE
    if (*verify_cmd) {
      vopt.corpus = no_corpus ? std::nullopt : std::optional<std::filesystem::path>(corpus_dir);
      vopt.progress = !no_progress;
      if (*index_opt) vopt.only_index = index;
      return cmd_verify(vopt, dists, json_file,
                        run_methods(vopt.methods, external, external_command, external_timeout, external_jobs));
    }
    if (*corpus_cmd) {
      if (corpus_action == "show" && corpus_id.empty()) {
        std::cerr << "cullproof corpus show: needs a case id (see 'cullproof corpus list')\n";
        return 2;
      }
      if (corpus_action == "rerecord" && corpus_id.empty()) {
        std::cerr << "cullproof corpus rerecord: needs a method name (see 'cullproof methods')\n";
        return 2;
      }
#ifdef CULLPROOF_HAVE_REPORT
      if (!(corpus_html.empty() && corpus_svg.empty() && corpus_zoom_svg.empty())) {
        if (corpus_action != "show") {
          std::cerr << "cullproof corpus: --html, --svg and --zoom-svg are for show\n";
          return 2;
        }
        return report::write_case_files(corpus_root, corpus_id, corpus_html, corpus_svg, corpus_zoom_svg);
      }
#endif
      if (!external.empty() && corpus_action != "replay") {
        std::cerr << "cullproof corpus: --external is for replay\n";
        return 2;
      }
      // A program's methods beside every built-in one (a case's other recorded verdicts replay too).
      std::vector<Method> methods = run_methods({}, external, external_command, external_timeout);
      if (!external.empty())
        for (const Method& b : builtin_methods()) methods.push_back(b);
      return cmd_corpus(corpus_action, corpus_root, corpus_id, methods, !external.empty(), strict);
    }
#endif
  } catch (const CaseError& e) {
    std::cerr << "cullproof: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "cullproof: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

// The standard output is an output like the others: a write to it that fails (a full disk, a closed
// pipe) is reported, naming it, and the status is non-zero.
int main(int argc, char** argv) {
  const int status = run(argc, argv);
  std::cout.flush();
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int err = errno;
    std::cerr << "cullproof: error: cannot write the standard output: " << std::strerror(err) << "\n";
    return status != 0 ? status : 1;
  }
  return status;
}

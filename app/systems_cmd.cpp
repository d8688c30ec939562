// `cullproof systems`: culling systems over the scene families, every object of every frame judged
// exactly (cullproof/scenes/scenes.hpp); a system whose claim breaks has its first failing run
// shrunk and recorded under <corpus>/systems/.
#include "commands.hpp"

#include "cli_checks.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/scenes/scenes.hpp"
#include "cullproof/sim/scene_run.hpp"
#include "cullproof/oracle/oracle.hpp"
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/report/case_view.hpp"
#include "cullproof/report/report.hpp"
#endif

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <iostream>
#include <limits>

namespace cullproof::app {

namespace {

constexpr std::uint64_t kMaxRuns = 1000000;     ///< runs per family
constexpr std::uint64_t kMaxFrames = 100000;    ///< frames per run
constexpr int kMaxShrink = 100000;              ///< system runs per shrink

std::string per_object(double seconds, std::uint64_t n) { return n ? fmt::format("{:.0f}", seconds * 1e9 / double(n)) : "-"; }

// A system's claim breaks the run when the system is the user's or cullproof's own.
bool fails_run(const System& s) { return s.origin != Origin::published; }

}  // namespace

void add_systems(CLI::App& app, SystemsCommand& c, ExternalProgram& external) {
  auto* cmd = c.cmd = app.add_subcommand(
      "systems", "Run culling systems (a hierarchy, masks, caches, moving objects) over the scene families and judge "
                 "every object of every frame against the oracle (docs/systems.md)");
  cmd->add_option("--system", c.systems, "Built-in system (repeatable; default: all of them)");
  cmd->add_option("--family", c.families, "Scene family or 'all' (repeatable; default: all, or none with --scene)");
  cmd->add_option("--scene", c.scene_files,
                  "A real-mesh scene file (corpus/scenes/*.json) as a run of its own: its leaves the objects, its "
                  "camera path the frames (repeatable)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--mesh-dir", c.mesh_dir, "Mesh directory of --scene (default: $CULLPROOF_MESH_DIR or the cache dir "
                                            "scripts/fetch-meshes fills)");
  cmd->add_option("--runs", c.runs, "Runs per family")->capture_default_str()->check(cli::UnsignedRange(1, kMaxRuns));
  cmd->add_option("--objects", c.objects, "Objects per scene")
      ->capture_default_str()
      ->check(cli::UnsignedRange(1, scenes::kMaxObjects));
  cmd->add_option("--frames", c.frames, "Frames per run")->capture_default_str()->check(cli::UnsignedRange(1, kMaxFrames));
  cmd->add_option("--seed", c.seed, "Seed")
      ->capture_default_str()
      ->check(cli::UnsignedRange(0, std::numeric_limits<std::uint64_t>::max()));
  c.index_option = cmd->add_option("--index", c.index, "Only run I of each family (as a failure's reproduce line gives it)")
                       ->check(cli::UnsignedRange(0, std::numeric_limits<std::uint64_t>::max()));
  cmd->add_option("--shrink-budget", c.shrink_budget, "System runs per shrink of a failing run")
      ->capture_default_str()
      ->check(CLI::Range(0, kMaxShrink));
  cmd->add_option("--json", c.json_file, "Write the results as JSON to FILE");
  cmd->add_option("--corpus", c.corpus_dir, "Record shrunk failing runs under DIR/systems")->capture_default_str();
  cmd->add_flag("--no-corpus", c.no_corpus, "Do not record failing runs");
  cmd->add_flag("--replay", c.replay, "Replay the records under DIR/systems (--corpus) with the systems named instead "
                                      "of drawing runs");
  cmd->add_option("--external", external.names,
                  "Run system NAME of the program given after '--' (the process protocol, version 2, docs/protocol.md; "
                  "repeatable, 'all': every system it offers); --system adds built-in ones beside it");
  cmd->add_option("--external-timeout", external.timeout_ms, "Milliseconds to wait for each answer of the program")
      ->capture_default_str()
      ->check(CLI::Range(1, 3600000));
}

namespace {

// Saves the run a fault happened on (a record without a finding) and says where.
void save_fault(const SystemsCommand& c, const System& s, const scenes::SystemFault& f) {
  std::cerr << "cullproof systems: FAULT: " << f.what() << "\n";
  if (!f.run() || c.no_corpus) return;
  const std::filesystem::path file = std::filesystem::path(c.corpus_dir) / "systems" / "faults" / s.name /
                                     fmt::format("{}-{}.json", f.run()->family, f.run()->index);
  write_file_atomic(file, nlohmann::json{{"system", s.name}, {"fault", f.what()}, {"frame", f.frame()},
                                         {"run", scenes::to_json(*f.run())}}.dump(1) + "\n");
  std::cerr << "cullproof systems: the run is saved in " << file.string() << "\n";
}

// The system's table, a line per family, and the same in JSON.
nlohmann::json print_tallies(const System& s, const std::vector<scenes::FamilyTally>& tallies) {
  fmt::print("{} ({}, claim {}, {})\n", s.name, to_string(s.origin), to_string(s.claim), s.description);
  std::size_t w = 13;  // the family column: as wide as the longest name (a scene's may be long)
  for (const scenes::FamilyTally& t : tallies) w = std::max(w, t.family.size());
  // A program's own time for its culls ("ns"), where it reports one: per object-frame and per
  // frame, beside cullproof's clock (which takes in the messages).
  bool own = false;
  for (const scenes::FamilyTally& t : tallies) own = own || t.own_culls > 0;
  fmt::print("  {:<{}} {:>6} {:>13} {:>7} {:>8} {:>8} {:>28} {:>9} {:>9}{}\n", "family", w, "runs", "object-frames", "broken",
             "F.rej", "F.ins", "false-intersect % [95%]", "cull ns", "judge ns",
             own ? fmt::format(" {:>9} {:>12}", "own ns", "own ns/frame") : std::string());
  nlohmann::json js = {{"system", s.name}, {"claim", std::string(to_string(s.claim))}, {"origin", std::string(to_string(s.origin))},
                       {"families", nlohmann::json::array()}};
  std::uint64_t broken = 0;
  for (const scenes::FamilyTally& t : tallies) {
    const std::uint64_t fi = t.by_class[int(ErrorClass::false_intersect)];
    fmt::print("  {:<{}} {:>6} {:>13} {:>7} {:>8} {:>8} {:>28} {:>9} {:>9}{}\n", t.family, w, t.runs, t.judged, t.claim_broken,
               t.by_class[int(ErrorClass::false_reject)], t.by_class[int(ErrorClass::false_inside)], percent_ci95(fi, t.truth_outside),
               per_object(t.cull_seconds, t.judged), per_object(t.judge_seconds, t.judged),
               !own                ? std::string()
               : t.own_culls == 0 ? fmt::format(" {:>9} {:>12}", "-", "-")
                                   : fmt::format(" {:>9.1f} {:>12.0f}", t.own_cull_ns / double(std::max<std::uint64_t>(t.own_object_frames, 1)),
                                                 t.own_cull_ns / double(t.own_culls)));
    js["families"].push_back({{"family", t.family},
                              {"runs", t.runs},
                              {"object_frames", t.judged},
                              {"claim_broken", t.claim_broken},
                              {"false_reject", t.by_class[int(ErrorClass::false_reject)]},
                              {"false_inside", t.by_class[int(ErrorClass::false_inside)]},
                              {"false_intersect", fi},
                              {"truth_outside", t.truth_outside},
                              {"under_inside", t.by_class[int(ErrorClass::under_inside)]},
                              {"cull_seconds", t.cull_seconds},
                              {"judge_seconds", t.judge_seconds},
                              {"own_cull_ns", t.own_cull_ns},
                              {"own_culls", t.own_culls},
                              {"own_object_frames", t.own_object_frames}});
    broken += t.claim_broken;
  }
  js["claim_broken"] = broken;
  fmt::print("\n");
  return js;
}

// The line that says where the claim broke and how to rerun it; the run shrunk and recorded
// (its file in js["record"]) unless --no-corpus.
std::string report_failure(const SystemsCommand& c, const System& s, const scenes::VerifyRuns& runs,
                           const std::map<std::string, std::string>& scene_file, const scenes::FamilyTally& first,
                           nlohmann::json& js) {
  // A program's system is named with --external and the program after '--'.
  const std::string which = s.program.empty() ? "--system " + s.name : "--external " + s.name;
  const std::string program = s.program.empty() ? std::string() : " -- " + s.program;
  const auto given = scene_file.find(first.family);
  const std::string again =
      given != scene_file.end()
          ? fmt::format("cullproof systems {} --scene {}{}{}", which, given->second,
                        c.mesh_dir.empty() ? std::string() : " --mesh-dir " + c.mesh_dir, program)
          : fmt::format("cullproof systems {} --family {} --index {} --seed {} --objects {} --frames {}{}", which,
                        first.family, first.broken_run->index, runs.seed, runs.size.objects, runs.size.frames, program);
  std::string line = fmt::format("{} breaks its claim '{}' on {} object-frame(s); first: {} run {}, frame {}, object {} "
                                 "({} where the truth is {}); reproduce: {}",
                                 s.name, to_string(s.claim), js["claim_broken"].get<std::uint64_t>(), first.family,
                                 first.broken_run->index, first.broken->frame, first.broken->id,
                                 to_string(first.broken->verdict), to_string(first.broken->truth), again);
  if (c.no_corpus) return line;
  scenes::ShrinkStats st;
  const scenes::SceneRun small = scenes::shrink_run(s, *first.broken_run, *first.broken, c.shrink_budget, &st);
  scenes::Finding f = *first.broken;
  try {
    if (const auto j = scenes::judge_run(s, small); j.first_broken) f = *j.first_broken;
  } catch (const scenes::SystemFault&) {
  }
  const auto file = scenes::write_system_record(std::filesystem::path(c.corpus_dir) / "systems", s, small, f, again);
  js["record"] = file.string();
  return line + fmt::format("\n  shrunk to {} object(s), {} frame(s) in {} system runs: {}", small.scene.objects.size(),
                            small.frames.size(), st.tries, file.string());
}

}  // namespace

int run_systems_command(const SystemsCommand& c, const ExternalProgram& external) {
  std::vector<System> systems;
  scenes::VerifyRuns runs;
  std::map<std::string, std::string> scene_file;  // a given scene's family: its file
  try {
    systems = external.systems(c.systems);
    runs.families.clear();
    const bool drawn = !c.families.empty() || c.scene_files.empty();
    for (const std::string& f : c.families.empty() ? std::vector<std::string>{"all"} : c.families)
      for (const std::string& name : scenes::parse_families(f))
        if (drawn && std::find(runs.families.begin(), runs.families.end(), name) == runs.families.end())
          runs.families.push_back(name);
    const std::filesystem::path mesh_dir = c.mesh_dir.empty() ? sim::default_mesh_dir() : std::filesystem::path(c.mesh_dir);
    for (const std::string& file : c.scene_files) {
      runs.given.push_back(sim::mesh_scene_run(sim::load_scene(file), mesh_dir));
      if (!scene_file.emplace(runs.given.back().family, file).second)
        throw std::invalid_argument("--scene " + file + ": a scene named '" + runs.given.back().scene.name +
                                    "' is given twice");
    }
  } catch (const std::exception& e) {
    std::cerr << "cullproof systems: " << e.what() << "\n";
    return 2;
  }
  if (c.replay) {
    std::size_t records = 0;
    const std::size_t bad = replay_system_records(c.corpus_dir, systems, records);
    if (records == 0) fmt::print("no system records under {}/systems\n", c.corpus_dir);
    return bad ? 1 : 0;
  }
  runs.runs = c.runs, runs.seed = c.seed;
  runs.size.objects = c.objects, runs.size.frames = c.frames;
  if (c.index_option && c.index_option->count()) runs.only_index = c.index;

  nlohmann::json out = {{"seed", runs.seed},          {"runs", runs.runs},     {"objects", runs.size.objects},
                        {"frames", runs.size.frames}, {"scenes", c.scene_files}, {"systems", nlohmann::json::array()}};
  std::vector<std::string> broken_lines;
  bool failed = false;
  std::vector<std::string> fault_lines;
  for (const System& s : systems) {
    // Family by family (then each given scene), so that a fault stops this system only and keeps
    // what it was judged on before.
    std::vector<scenes::FamilyTally> tallies;
    std::optional<std::string> fault;
    std::vector<scenes::VerifyRuns> parts;
    for (const std::string& f : runs.families) {
      scenes::VerifyRuns one = runs;
      one.families = {f};
      one.given.clear();
      parts.push_back(std::move(one));
    }
    for (const scenes::SceneRun& g : runs.given) {
      scenes::VerifyRuns one = runs;
      one.families.clear();
      one.given = {g};
      parts.push_back(std::move(one));
    }
    for (const scenes::VerifyRuns& part : parts) {
      try {
        for (scenes::FamilyTally& t : scenes::verify_system(s, part)) tallies.push_back(std::move(t));
      } catch (const scenes::SystemFault& f) {
        save_fault(c, s, f);
        fault = f.what();
        break;
      }
    }
    nlohmann::json js = print_tallies(s, tallies);
    if (fault) {
      fmt::print("  FAULT (the system stopped; the families above were judged before it): {}\n\n", *fault);
      js["fault"] = *fault;
      fault_lines.push_back(fmt::format("{} faulted: {}", s.name, *fault));
    }
    const auto first = std::find_if(tallies.begin(), tallies.end(), [](const scenes::FamilyTally& t) { return t.broken.has_value(); });
    if (first != tallies.end()) {
      broken_lines.push_back(report_failure(c, s, runs, scene_file, *first, js));
      failed = failed || fails_run(s);
    }
    out["systems"].push_back(std::move(js));
  }
  if (broken_lines.empty() && fault_lines.empty()) fmt::print("every system held its claim\n");
  for (const std::string& l : broken_lines) fmt::print("{}\n", l);
  for (const std::string& l : fault_lines) fmt::print("{}\n", l);
  if (!c.json_file.empty()) write_file_atomic(c.json_file, out.dump(1) + "\n");
  return !fault_lines.empty() ? 3 : failed ? 1 : 0;
}

namespace {

// The record files under <dir>/systems/, faults/ aside, in name order.
std::vector<std::filesystem::path> system_record_files(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path root = std::filesystem::path(dir) / "systems";
  if (!std::filesystem::exists(root)) return files;
  for (auto it = std::filesystem::recursive_directory_iterator(root); it != std::filesystem::recursive_directory_iterator(); ++it) {
    if (it.depth() == 0 && it->is_directory() && it->path().filename() == "faults") {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && it->path().extension() == ".json") files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

std::size_t replay_system_records(const std::string& dir, const std::vector<System>& systems, std::size_t& records) {
  const std::vector<std::filesystem::path> files = system_record_files(dir);
  records = files.size();
  std::size_t still = 0, known = 0;
  for (const std::filesystem::path& file : files) {
    const scenes::SystemRecord rec = scenes::read_system_record(file);
    const auto s = std::find_if(systems.begin(), systems.end(), [&](const System& x) { return x.name == rec.system; });
    std::string status;
    if (s == systems.end()) {
      status = "not replayed: system '" + rec.system + "' is not among those run here";
    } else {
      ++known;
      try {
        const scenes::RunJudgement j = scenes::judge_run(*s, rec.run);
        if (!j.first_broken) status = "fixed";
        else if (j.first_broken->frame == rec.failure.frame && j.first_broken->id == rec.failure.id) status = "still failing", ++still;
        else status = fmt::format("changed (now frame {}, object {})", j.first_broken->frame, j.first_broken->id);
      } catch (const scenes::SystemFault& f) {
        status = std::string("FAULT: ") + f.what();
      }
    }
    fmt::print("{:<72} {}\n", file.lexically_relative(dir).string(), status);
  }
  if (records) fmt::print("{} system record(s): {} of {} replayed still failing as recorded\n", records, still, known);
  return known - still;
}

bool show_system_record(const std::string& dir, const std::string& id) {
  for (const std::filesystem::path& file : system_record_files(dir)) {
    if (file.stem() != id) continue;
    const scenes::SystemRecord rec = scenes::read_system_record(file);
    const scenes::Finding& f = rec.failure;
    fmt::print("file: {}\nsystem: {} (claim {})\n", file.string(), rec.system, rec.record.value("claim", std::string("?")));
    fmt::print("run: {} of {}, seed {} ({} object(s), {} frame(s), moving: {})\n", rec.run.index, rec.run.family, rec.run.seed,
               rec.run.scene.objects.size(), rec.run.frames.size(), rec.run.motion);
    fmt::print("frame {} (camera: {}), object {}: {} where the truth was {} ({})\n", f.frame, rec.run.frames[f.frame].camera,
               f.id, to_string(f.verdict), to_string(f.truth), rec.record.value("error", std::string("?")));
    fmt::print("case: {}\n", format_case(scenes::case_of(rec.run, f.frame, f.object)));
    fmt::print("reproduce: {}\n", rec.record.value("reproduce", std::string("-")));
    return true;
  }
  return false;
}

#ifdef CULLPROOF_HAVE_REPORT
namespace {

// A system record's failing object-frame as a corpus entry (the oracle's witness) and the view the
// 3D viewer draws of it: the case, the frame's other objects, what the run was.
struct RecordView {
  CorpusEntry entry;
  std::vector<Volume> others;
  nlohmann::json system;
};

RecordView record_view(const std::filesystem::path& file) {
  const scenes::SystemRecord rec = scenes::read_system_record(file);
  const scenes::Finding& f = rec.failure;
  const scenes::SceneRun& run = rec.run;
  RecordView out;
  CorpusEntry& e = out.entry;
  e.file = file;
  e.c = scenes::case_of(run, f.frame, f.object);
  e.c.id = file.stem().string();
  e.c.truth = f.truth;
  e.method = rec.system;
  e.verdict = f.verdict;
  e.error = f.error;
  e.distribution = run.family;
  const oracle::Result truth = oracle::classify(e.c.frustum, e.c.volume);
  const oracle::VerdictDistance vd = oracle::distance_to_verdict(e.c.frustum, e.c.volume, f.verdict);
  const auto number = [](double d) { return std::isfinite(d) ? nlohmann::json(d) : nlohmann::json(nullptr); };
  e.c.extra = {{"claim", rec.record.value("claim", std::string())},
               {"violates_claim", true},
               {"reproduce", rec.record.value("reproduce", std::string())},
               {"distance", number(truth.distance)},
               {"distance_kind", std::string(oracle::to_string(truth.distance_kind))},
               {"verdict_distance", number(vd.distance)},
               {"verdict_distance_kind", std::string(oracle::to_string(vd.shift))},
               {"witness", oracle::to_json(truth.witness)}};
  for (std::size_t k = 0; k < run.scene.objects.size(); ++k)  // as they are on that frame
    if (k != f.object) out.others.push_back(scenes::case_of(run, f.frame, k).volume);
  out.system = {{"name", rec.system},           {"claim", rec.record.value("claim", std::string())},
                {"family", run.family},         {"index", run.index},
                {"seed", run.seed},             {"objects", run.scene.objects.size()},
                {"frames", run.frames.size()},  {"motion", run.motion},
                {"frame", f.frame},             {"camera", run.frames.at(f.frame).camera},
                {"object", f.id}};
  return out;
}

}  // namespace

nlohmann::json system_record_views(const std::string& dir) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::filesystem::path& file : system_record_files(dir)) {
    const RecordView r = record_view(file);
    out.push_back(report::system_view_json(r.entry, r.others, r.system));
  }
  return out;
}

int write_system_record_page(const std::string& dir, const std::string& id, const std::string& html_file,
                             const std::string& svg_file, const std::string& zoom_svg_file) {
  for (const std::filesystem::path& file : system_record_files(dir)) {
    if (file.stem() != id) continue;
    try {
      const RecordView r = record_view(file);
      const nlohmann::json view = report::system_view_json(r.entry, r.others, r.system);
      if (!html_file.empty()) {
        write_file_atomic(html_file, report::system_html(id, r.entry, view, report::load_web_asset("case.js")));
        std::cout << "page: " << html_file << "\n";
      }
      report::write_case_drawings(view, svg_file, zoom_svg_file);
      return 0;
    } catch (const std::exception& ex) {
      std::cerr << "cullproof corpus show: " << file.string() << ": " << ex.what() << "\n";
      return 2;
    }
  }
  return -1;
}
#endif

}  // namespace cullproof::app

// `cullproof corpus`: list, show, replay and rerecord the mismatch corpus (src/corpus/corpus.cpp).
#include "commands.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/oracle/oracle.hpp"
#ifdef CULLPROOF_HAVE_REPORT
#include "cullproof/report/case_view.hpp"
#endif

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <type_traits>
#include <variant>

namespace cullproof::app {

namespace {

std::string fmt_distance(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", d);
  return buf;
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
                                     return (!m.program.empty() || !m.reproduce.empty()) && m.name == e.method;
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
        const ErrorClass cls = error_class(*v, t.truth, m.three_way_on(e.c.volume));
        std::printf("  %-26s %-13s %s\n", m.name.c_str(), std::string(to_string(*v)).c_str(),
                    cls == ErrorClass::correct ? "" : std::string(to_string(cls)).c_str());
      }
      std::cout << "where the volume lies, plane by plane (normalised):\n" << describe_planes(e.c);
      std::cout << "witness: " << oracle::to_json(t.witness).dump() << "\n";
      return 0;
    }
#ifdef CULLPROOF_HAVE_SCENES
    if (show_system_record(dir, id)) return 0;
#endif
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
  if (action == "rejudge") {
    const std::vector<Rejudged> changed = rejudge(dir, methods);
    std::size_t flipped = 0;
    for (const Rejudged& r : changed) {
      const bool flip = r.violated_before != r.violates_now;
      flipped += flip;
      std::printf("%-56s %s  distance %.6g, allowance %.6g\n", r.id.c_str(),
                  flip ? (r.violates_now ? "now breaks its claim" : "no longer breaks its claim") : "fields updated",
                  r.distance, r.allowance);
    }
    std::printf("%zu record(s) rewritten, %zu whose claim judgement changed\n", changed.size(), flipped);
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
  std::size_t systems_not_failing = 0;
#ifdef CULLPROOF_HAVE_SCENES
  std::size_t system_records = 0;
  systems_not_failing = replay_system_records(dir, builtin_systems(), system_records);
#endif
  if (strict && (still != entries.size() || systems_not_failing)) {
    std::printf("FAILED: %zu case(s) no longer fail as recorded (--strict)\n", entries.size() - still + systems_not_failing);
    return 1;
  }
  return (truth_changed || regressed) ? 1 : 0;
}
}  // namespace

void add_corpus(CLI::App& app, CorpusCommand& c, ExternalProgram& external) {
  c.cmd = app.add_subcommand("corpus", "Inspect and replay the mismatch corpus");
  c.cmd->add_option("action", c.action, "list | show ID | replay | rerecord METHOD (after a deliberate change to METHOD: its verdict in every record taken again) | rejudge (after a change to the judge: every record's claim judgement taken again)")
      ->required()
      ->check(CLI::IsMember({"list", "show", "replay", "rerecord", "rejudge"}));
  c.cmd->add_option("id", c.id, "Case id (show), method name (rerecord)");
  c.cmd->add_option("--dir", c.dir, "Corpus directory")->capture_default_str();
  c.cmd->add_flag("--strict", c.strict, "replay: fail unless every case still fails as recorded");
#ifdef CULLPROOF_HAVE_REPORT
  c.cmd->add_option("--html", c.html, "show: write the case in 3D as a self-contained page to FILE");
  c.cmd->add_option("--svg", c.svg, "show: write its three-view drawing (front, top, side) to FILE");
  c.cmd->add_option("--zoom-svg", c.zoom_svg, "show: the same, magnified around the error, to FILE");
#endif
  external.add_options(c.cmd);
}

int run_corpus_command(const CorpusCommand& c, const ExternalProgram& external) {
  if (c.action == "show" && c.id.empty()) {
    std::cerr << "cullproof corpus show: needs a case id (see 'cullproof corpus list')\n";
    return 2;
  }
  if (c.action == "rerecord" && c.id.empty()) {
    std::cerr << "cullproof corpus rerecord: needs a method name (see 'cullproof methods')\n";
    return 2;
  }
#ifdef CULLPROOF_HAVE_REPORT
  if (!(c.html.empty() && c.svg.empty() && c.zoom_svg.empty())) {
    if (c.action != "show") {
      std::cerr << "cullproof corpus: --html, --svg and --zoom-svg are for show\n";
      return 2;
    }
#ifdef CULLPROOF_HAVE_SCENES
    if (const int r = write_system_record_page(c.dir, c.id, c.html, c.svg, c.zoom_svg); r >= 0) return r;
#endif
    return report::write_case_files(c.dir, c.id, c.html, c.svg, c.zoom_svg);
  }
#endif
  if (external.any() && c.action != "replay" && c.action != "rejudge") {
    std::cerr << "cullproof corpus: --external and --shader are for replay and rejudge\n";
    return 2;
  }
  // A program's methods and shaders beside every built-in one (a case's other recorded verdicts
  // replay too).
  std::vector<Method> methods = external.methods({});
  if (external.any())
    for (const Method& b : builtin_methods()) methods.push_back(b);
  return cmd_corpus(c.action, c.dir, c.id, methods, external.any(), c.strict);
}

}  // namespace cullproof::app

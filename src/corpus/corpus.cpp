// The mismatch corpus (see cullproof/corpus/corpus.hpp).
#include "cullproof/corpus/corpus.hpp"

#include "cullproof/gen/generators.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace cullproof {

std::string geometry_hash(const CaseFrustum& f, const Volume& v) {
  const std::string text = format_frustum(f) + "|" + format_volume(v);
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char ch : text) {
    h ^= ch;
    h *= 0x100000001b3ull;
  }
  return fmt::format("{:012x}", h & 0xffffffffffffull);
}

std::vector<std::filesystem::path> corpus_case_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> files;
  if (!std::filesystem::exists(dir)) return files;
  for (auto it = std::filesystem::recursive_directory_iterator(dir); it != std::filesystem::recursive_directory_iterator();
       ++it) {
    // corpus/scenes/ (scene files), corpus/scenes-*/, corpus/faults/ (the cases that made a
    // method fault, without a truth or a verdict) and corpus/systems/ (culling systems' shrunk
    // runs, cullproof/scenes/scenes.hpp) are not mismatch cases.
    const std::string name = it->path().filename().string();
    if (it.depth() == 0 && it->is_directory() && (name.rfind("scenes", 0) == 0 || name == "faults" || name == "systems")) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file() && it->path().extension() == ".json") files.push_back(it->path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<CorpusEntry> load_corpus(const std::filesystem::path& dir) {
  const std::vector<std::filesystem::path> files = corpus_case_files(dir);
  std::vector<CorpusEntry> out;
  for (const auto& file : files) out.push_back(corpus_entry(read_case_file(file), file));
  return out;
}

ReplayResult replay(const CorpusEntry& e) { return replay(e, builtin_methods()); }

ReplayResult replay(const CorpusEntry& e, const std::vector<Method>& methods) {
  auto find = [&](const std::string& name) -> const Method* {
    for (const Method& m : methods)
      if (m.name == name) return &m;
    return nullptr;
  };
  ReplayResult r;
  r.entry = &e;
  r.truth_now = oracle::truth(e.c.frustum, e.c.volume);
  r.truth_changed = r.truth_now != *e.c.truth;
  auto answer = [&](const Method& m) {
    return e.path ? checked_classify_path(m, *e.path) : checked_classify(m, e.c.frustum, e.c.volume);
  };
  if (const Method* m = find(e.method)) r.verdict_now = answer(*m);
  r.reproduces = r.verdict_now && *r.verdict_now == e.verdict;
  r.fixed = r.verdict_now && *r.verdict_now == r.truth_now;
  if (auto it = e.c.extra.find("verdicts"); it != e.c.extra.end() && it->is_object()) {
    for (auto v = it->begin(); v != it->end(); ++v) {
      const Method* m = find(v.key());
      if (!m || !v->is_string()) continue;
      const auto now = answer(*m);
      const Visibility recorded = visibility_from_string(v->get<std::string>());
      if (!now || *now != recorded) r.changed.push_back(v.key());
      if (recorded == *e.c.truth && (!now || *now != r.truth_now)) r.regressed.push_back(v.key());
    }
  }
  return r;
}

std::vector<Rerecorded> rerecord_verdicts(const std::filesystem::path& dir, const Method& m) {
  std::vector<Rerecorded> out;
  for (CorpusEntry& e : load_corpus(dir)) {
    if (e.method == m.name) continue;
    auto it = e.c.extra.find("verdicts");
    if (it == e.c.extra.end() || !it->is_object() || !it->contains(m.name)) continue;
    const Answer now = e.path ? checked_classify_path(m, *e.path) : checked_classify(m, e.c.frustum, e.c.volume);
    const std::string before = (*it)[m.name].is_string() ? (*it)[m.name].get<std::string>() : (*it)[m.name].dump();
    const std::string after = now ? std::string(to_string(*now)) : std::string();
    if (before == after) continue;
    if (now) (*it)[m.name] = after;
    else it->erase(m.name);
    write_case_file(e.file, e.c, /*overwrite=*/true);
    out.push_back(Rerecorded{e.file, before, after});
  }
  return out;
}

std::vector<Rejudged> rejudge(const std::filesystem::path& dir, const std::vector<Method>& methods) {
  std::vector<Rejudged> out;
  for (CorpusEntry& e : load_corpus(dir)) {
    const auto m = std::find_if(methods.begin(), methods.end(), [&](const Method& x) { return x.name == e.method; });
    if (m == methods.end()) continue;
    const oracle::VerdictDistance vd = oracle::distance_to_verdict(e.c.frustum, e.c.volume, e.verdict);
    if (vd.truth != *e.c.truth) continue;
    const double scale = gen::case_scale(e.c.frustum, e.c.volume);
    const bool exact_case = gen::float_exact(e.c.frustum, e.c.volume);
    const ErrorClass cls = error_class(e.verdict, vd.truth, m->three_way_on(e.c.volume));
    nlohmann::json x = e.c.extra;
    x["violates_claim"] = violates_claim(m->claim, cls, vd.distance, m->tolerance, scale, exact_case);
    detail::set_judgement(x, vd, *m, scale, exact_case);
    if (x == e.c.extra) continue;
    Rejudged r;
    r.file = e.file;
    r.id = e.c.id;
    const auto before = e.c.extra.find("violates_claim");
    r.violated_before = before != e.c.extra.end() && before->is_boolean() && before->get<bool>();
    r.violates_now = x["violates_claim"].get<bool>();
    r.distance = vd.distance;
    r.allowance = x["allowance"].is_number() ? x["allowance"].get<double>() : 0.0;
    e.c.extra = std::move(x);
    write_case_file(e.file, e.c, /*overwrite=*/true);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace cullproof

// The corpus case of an error, as the campaign writes it (cullproof/corpus/corpus.hpp): the
// record, its judgement fields and the command that reproduces it.
#include "cullproof/corpus/corpus.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/io/limits.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace cullproof::detail {

using gen::GenCase;

namespace {

// A held record's file under its corpus folder (<method>/<distribution>/<name>) and its text.
std::string held_file(const CorpusEntry& e) {
  return (e.file.parent_path().parent_path().filename() / e.file.parent_path().filename() / e.file.filename()).generic_string();
}
std::string read_text_file(const std::filesystem::path& file) {
  return read_file_limited(file, kMaxCaseFileBytes, "a corpus record");
}

}  // namespace

std::string reproduce_command(std::uint64_t seed, gen::Distribution d, std::uint64_t index, const Method& m) {
  // A user's method is not in the command-line program: its test reruns the case from the
  // environment (cullproof/gtest/gtest.hpp).
  if (!m.reproduce.empty())
    return fmt::format("cullproof verify --seed {} --distribution {} --index {} {}", seed, gen::to_string(d), index, m.reproduce);
  if (!m.program.empty())
    return fmt::format("cullproof verify --seed {} --distribution {} --index {} --external {} -- {}", seed, gen::to_string(d),
                       index, m.name, m.program);
  if (m.origin == Origin::user)
    return fmt::format("CULLPROOF_SEED={} CULLPROOF_DISTRIBUTION={} CULLPROOF_INDEX={} (environment of the test that verifies {})",
                       seed, gen::to_string(d), index, m.name);
  return fmt::format("cullproof verify --seed {} --distribution {} --index {} --method {}", seed, gen::to_string(d), index,
                     m.name);
}

void set_judgement(nlohmann::json& x, const oracle::VerdictDistance& vd, const Method& m, double scale, bool float_exact) {
  x.erase("backward_distance");
  x["float_exact"] = float_exact;
  x["verdict_distance"] = std::isfinite(vd.distance) ? nlohmann::json(vd.distance) : nlohmann::json(nullptr);
  x["verdict_distance_kind"] = std::string(oracle::to_string(vd.shift));
  x["tolerance"] = m.tolerance;
  switch (m.claim) {
    case Claim::certified_exact: x["allowance"] = m.tolerance * scale; break;
    case Claim::conservative:
    case Claim::exact: x["allowance"] = float_exact ? 0.0 : m.tolerance * scale; break;
    default: x["allowance"] = nullptr; break;
  }
}

CorpusRecord write_corpus_case(const std::filesystem::path& dir, const GenCase& g, const Method& m, Visibility verdict,
                              gen::Distribution d, std::uint64_t seed, std::uint64_t index,
                              const std::vector<Method>& all, const PathCase* path) {
  const oracle::Result r = oracle::classify(g.frustum, g.volume);
  const ErrorClass cls = error_class(verdict, r.truth, m.three_way_on(g.volume));
  const std::string hash = geometry_hash(g.frustum, g.volume);
  Case c;
  c.id = fmt::format("{}-{}-{}", m.name, to_string(cls), hash);
  c.frustum = g.frustum;
  c.volume = g.volume;
  c.truth = r.truth;
  c.note = fmt::format("{} says {} where the truth is {} ({}); found by the {} distribution", m.name,
                       to_string(verdict), to_string(r.truth), to_string(cls), gen::to_string(d));
  nlohmann::json& x = c.extra;
  x["method"] = m.name;
  x["verdict"] = std::string(to_string(verdict));
  x["class"] = to_string(cls);
  x["claim"] = std::string(to_string(m.claim));
  x["origin"] = std::string(to_string(m.origin));
  if (!m.three_way_on(g.volume)) x["two_way"] = true;
  const double scale = gen::case_scale(g.frustum, g.volume);
  const bool exact_case = gen::float_exact(g.frustum, g.volume);
  const oracle::VerdictDistance vd = oracle::distance_to_verdict(g.frustum, g.volume, verdict);
  const bool violates = violates_claim(m.claim, cls, vd.distance, m.tolerance, scale, exact_case);
  x["violates_claim"] = violates;
  x["float_exact"] = exact_case;
  set_judgement(x, vd, m, scale, exact_case);
  x["distribution"] = std::string(gen::to_string(d));
  x["distance"] = std::isfinite(r.distance) ? nlohmann::json(r.distance) : nlohmann::json(nullptr);
  x["distance_kind"] = oracle::to_string(r.distance_kind);
  x["scale"] = scale;
  x["scene_size"] = g.scene_size;
  x["witness"] = oracle::to_json(r.witness);
  x["seed"] = seed;
  x["index"] = index;
  x["reproduce"] = reproduce_command(seed, d, index, m);
  if (path) x["path"] = to_json(*path);
  // Every method's verdict on the case; a method that faults on it (its own fault, which its own
  // run reports) is named with the problem instead, and the record is written all the same.
  nlohmann::json verdicts = nlohmann::json::object(), faults = nlohmann::json::object();
  for (const Method& o : all) {
    try {
      if (auto v = path ? checked_classify_path(o, *path) : run_method(o, g)) verdicts[o.name] = std::string(to_string(*v));
    } catch (const std::exception& e) {
      faults[o.name] = e.what();
    }
  }
  x["verdicts"] = verdicts;
  if (!faults.empty()) x["verdict_faults"] = faults;
  const std::string relative = fmt::format("{}/{}/{}-{}.json", m.name, gen::to_string(d), to_string(cls), hash);
  const auto file = dir / relative;
  CorpusRecord rec{c.id, false, violates, relative, format_case(c, /*pretty=*/true)};
  if (std::filesystem::exists(file)) return rec;
  try {
    write_file_atomic(file, rec.text, /*overwrite=*/false);
  } catch (const std::runtime_error&) {
    if (std::filesystem::exists(file)) return rec;  // written meanwhile: the same geometry
    throw;
  }
  rec.written = true;
  return rec;
}

CorpusSources::CorpusSources(const std::filesystem::path& dir, const std::string& method, gen::Distribution d) {
  const std::filesystem::path sub = dir / method / gen::to_string(d);
  std::error_code ec;
  if (!std::filesystem::is_directory(sub, ec)) return;
  std::vector<std::filesystem::path> files;
  for (const auto& f : std::filesystem::directory_iterator(sub, ec))
    if (f.is_regular_file() && f.path().extension() == ".json") files.push_back(f.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    try {
      CorpusEntry e = corpus_entry(read_case_file(f), f);
      if (e.method == method && e.distribution == gen::to_string(d)) entries_.push_back(std::move(e));
    } catch (const std::exception&) {
      // Not a readable record: no source of any error (see the class's contract).
    }
  }
}

std::optional<CorpusRecord> CorpusSources::held(const Method& m, std::uint64_t seed, std::uint64_t index, ErrorClass cls,
                                                 bool judge) const {
  auto number = [](const nlohmann::json& x, const char* key) -> std::optional<std::uint64_t> {
    const auto it = x.find(key);
    if (it == x.end() || !it->is_number_unsigned()) return std::nullopt;
    return it->get<std::uint64_t>();
  };
  for (const CorpusEntry& e : entries_) {
    if (e.error != cls || number(e.c.extra, "seed") != seed || number(e.c.extra, "index") != index) continue;
    Answer now;
    try {
      now = e.path ? checked_classify_path(m, *e.path) : checked_classify(m, e.c.frustum, e.c.volume);
    } catch (const std::exception&) {
      continue;  // the fault is the run's to find, on the case shrunk again
    }
    if (!now || *now != e.verdict) continue;
    if (!judge) {
      const Visibility truth = oracle::truth(e.c.frustum, e.c.volume);
      if (truth != *e.c.truth || error_class(e.verdict, truth, m.three_way_on(e.c.volume)) != cls) continue;
      return CorpusRecord{e.c.id, false, false, held_file(e), read_text_file(e.file)};
    }
    const oracle::VerdictDistance vd = oracle::distance_to_verdict(e.c.frustum, e.c.volume, e.verdict);
    if (vd.truth != *e.c.truth || error_class(e.verdict, vd.truth, m.three_way_on(e.c.volume)) != cls) continue;
    const double scale = gen::case_scale(e.c.frustum, e.c.volume);
    const bool exact_case = gen::float_exact(e.c.frustum, e.c.volume);
    return CorpusRecord{e.c.id, false, violates_claim(m.claim, cls, vd.distance, m.tolerance, scale, exact_case),
                        held_file(e), read_text_file(e.file)};
  }
  return std::nullopt;
}


}  // namespace cullproof::detail

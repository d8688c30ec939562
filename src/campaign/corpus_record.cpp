// The corpus's records, read and written without the oracle (see cullproof/campaign/corpus.hpp): the names
// of the error classes, a recorded camera path, and the checks that make a case a mismatch record.
// Reading a record needs only the case reader, so the record reader can be tested on any text.
#include "cullproof/campaign/corpus.hpp"
#include "cullproof/io/limits.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace cullproof {

std::string_view to_string(ErrorClass e) noexcept {
  switch (e) {
    case ErrorClass::correct: return "correct";
    case ErrorClass::false_reject: return "false-reject";
    case ErrorClass::false_inside: return "false-inside";
    case ErrorClass::false_intersect: return "false-intersect";
    case ErrorClass::under_inside: return "under-inside";
  }
  return "invalid";
}

nlohmann::json to_json(const PathCase& p) {
  nlohmann::json j;
  j["motion"] = p.motion;
  j["object"] = p.object;
  j["frames"] = nlohmann::json::array();
  for (const CaseFrustum& f : p.frames) j["frames"].push_back(nlohmann::json::parse(format_frustum(f)));
  j["objects"] = nlohmann::json::array();
  for (const Volume& v : p.objects) j["objects"].push_back(nlohmann::json::parse(format_volume(v)));
  return j;
}

PathCase path_from_json(const nlohmann::json& j, const std::string& where) {
  auto bad = [&](const std::string& field, const std::string& why) {
    return std::runtime_error(where + ": field 'path." + field + "': " + why);
  };
  if (!j.is_object()) throw bad("", "not an object");
  PathCase p;
  if (auto it = j.find("motion"); it != j.end() && it->is_string()) p.motion = it->get<std::string>();
  const auto fr = j.find("frames"), ob = j.find("objects"), at = j.find("object");
  if (fr == j.end() || !fr->is_array() || fr->empty()) throw bad("frames", "missing or not a non-empty array");
  if (ob == j.end() || !ob->is_array() || ob->empty()) throw bad("objects", "missing or not a non-empty array");
  if (at == j.end() || !at->is_number_unsigned()) throw bad("object", "missing or not an index");
  // Each frame and object is read by the case reader, with its checks, as a case of its own: a
  // frame with a point, an object with the first frame as the reader wrote it (so the cost stays
  // linear in the record, whatever the first frame holds beside its planes).
  const nlohmann::json any_volume = {{"point", {0, 0, 0}}};
  for (std::size_t k = 0; k < fr->size(); ++k) {
    try {
      p.frames.push_back(parse_case(nlohmann::json{{"id", "path"}, {"frustum", (*fr)[k]}, {"volume", any_volume}}.dump(), "recorded path").frustum);
    } catch (const std::exception& e) {
      throw bad(fmt::format("frames[{}]", k), e.what());
    }
  }
  const nlohmann::json any_frustum = nlohmann::json::parse(format_frustum(p.frames[0]));
  for (std::size_t k = 0; k < ob->size(); ++k) {
    try {
      p.objects.push_back(parse_case(nlohmann::json{{"id", "path"}, {"frustum", any_frustum}, {"volume", (*ob)[k]}}.dump(), "recorded path").volume);
    } catch (const std::exception& e) {
      throw bad(fmt::format("objects[{}]", k), e.what());
    }
  }
  p.object = at->get<std::size_t>();
  if (p.object >= p.objects.size())
    throw bad("object", fmt::format("{} is not among the {} objects", p.object, p.objects.size()));
  return p;
}

namespace {

ErrorClass class_from_string(const std::string& s, const std::string& file) {
  for (ErrorClass e : {ErrorClass::correct, ErrorClass::false_reject, ErrorClass::false_inside,
                       ErrorClass::false_intersect, ErrorClass::under_inside})
    if (s == to_string(e)) return e;
  throw std::runtime_error(file + ": field 'class': unknown error class \"" + printable_text(s) + "\"");
}

std::string need_string(const nlohmann::json& x, const char* key, const std::string& file) {
  auto it = x.find(key);
  if (it == x.end() || !it->is_string())
    throw std::runtime_error(file + ": field '" + key + "': missing (a corpus case records it as a string)");
  return it->get<std::string>();
}

}  // namespace

CorpusEntry corpus_entry(Case c, const std::filesystem::path& file) {
  CorpusEntry e;
  e.file = file;
  e.c = std::move(c);
  const std::string f = file.string();
  if (!e.c.truth) throw std::runtime_error(f + ": field 'truth': missing (a corpus case records the truth)");
  e.method = need_string(e.c.extra, "method", f);
  const std::string verdict = need_string(e.c.extra, "verdict", f);
  if (verdict != "outside" && verdict != "intersecting" && verdict != "inside")
    throw std::runtime_error(f + ": field 'verdict': unknown visibility \"" + printable_text(verdict) +
                             "\" (expected outside, intersecting or inside)");
  e.verdict = visibility_from_string(verdict);
  e.error = class_from_string(need_string(e.c.extra, "class", f), f);
  e.distribution = need_string(e.c.extra, "distribution", f);
  if (auto it = e.c.extra.find("path"); it != e.c.extra.end()) {
    e.path = path_from_json(*it, f);
    if (format_frustum(e.path->frustum()) != format_frustum(e.c.frustum) ||
        format_volume(e.path->volume()) != format_volume(e.c.volume))
      throw std::runtime_error(f + ": field 'path': its last frame and its object are not the case's frustum and volume");
  }
  return e;
}

CorpusEntry parse_corpus_entry(std::string_view text, const std::filesystem::path& file) {
  return corpus_entry(parse_case(text, file.string()), file);
}

}  // namespace cullproof

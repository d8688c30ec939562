// The judge's results as a record holds them, with no oracle: the names of the error classes, and
// a case on a camera path (field "path"), written and read back.
#include "cullproof/judge/judge.hpp"

#include "cullproof/io/case_io.hpp"

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

}  // namespace cullproof

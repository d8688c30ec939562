// The corpus's records, read without the oracle (see cullproof/corpus/corpus.hpp): the checks that
// make a case a mismatch record. Reading a record needs only the case reader, so the record reader
// can be tested on any text.
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/io/limits.hpp"

#include <fmt/format.h>

#include <stdexcept>

namespace cullproof {

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

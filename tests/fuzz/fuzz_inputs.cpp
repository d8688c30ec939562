// What the readers of untrusted input promise (see fuzz_inputs.hpp).
#include "fuzz_inputs.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/protocol/protocol.hpp"
#include "cullproof/sim/scene.hpp"

#include <algorithm>
#include <string>

namespace cullproof::fuzz {

namespace {

[[noreturn]] void broken(const std::string& promise, std::string_view detail) {
  throw FuzzFailure(promise + ": " + std::string(detail.substr(0, 2000)));
}

// An error message names where the input came from, first.
void names_source(const std::exception& e, const std::string& prefix) {
  const std::string what = e.what();
  if (what.compare(0, prefix.size(), prefix) != 0 || what.size() <= prefix.size())
    broken("an error that does not start with '" + prefix + "' and a problem", what);
}

int lines_of(std::string_view text) { return 1 + int(std::count(text.begin(), text.end(), '\n')); }

// A case error names the source, a line of the text (0: the text as a whole) and the problem.
void well_placed(const CaseError& e, const std::string& source, std::string_view text, int first_line = 1) {
  names_source(e, source + (e.line() > 0 ? ":" : ""));
  if (e.file() != source) broken("a case error naming another file than " + source, e.what());
  if (e.line() < 0 || (e.line() > 0 && (e.line() < first_line || e.line() > first_line - 1 + lines_of(text))))
    broken("a case error on a line outside the text (" + std::to_string(lines_of(text)) + " lines)", e.what());
}

// What the writer writes of a case read, the reader reads back as the same case.
void round_trips(const Case& c) {
  for (bool pretty : {false, true}) {
    const std::string once = format_case(c, pretty);
    if (once.size() > kMaxCaseBytes) continue;  // the writer may spell numbers longer than the input
    std::string twice;
    try {
      twice = format_case(parse_case(once, "written"), pretty);
    } catch (const CaseError& e) {
      broken("a case written by format_case that the reader refuses", std::string(e.what()) + "\n" + once);
    }
    if (twice != once) broken("a case that reads back differently from what was written", once + "\n" + twice);
  }
}

}  // namespace

void case_reader(std::string_view bytes) {
  std::optional<Case> one;
  try {
    one = parse_case(bytes, "fuzz.json");
  } catch (const CaseError& e) {
    well_placed(e, "fuzz.json", bytes);
  }
  if (one) round_trips(*one);

  std::vector<Case> many;
  try {
    many = parse_cases_jsonl(bytes, "fuzz.jsonl");
  } catch (const CaseError& e) {
    well_placed(e, "fuzz.jsonl", bytes);
  }
  for (const Case& c : many) {
    if (c.line < 1 || c.line > lines_of(bytes)) broken("a JSON Lines case on a line outside the text", c.id);
    round_trips(c);
  }
}

void scene_reader(std::string_view bytes) {
  try {
    const sim::SceneDesc s = sim::parse_scene_text(bytes, "fuzz-scene.json");
    if (s.name.empty()) broken("a scene without a name", bytes);
    if (s.groups.empty() && !s.floor) broken("a scene without geometry", bytes);
    if (s.camera.frames < 1) broken("a scene without frames", bytes);
  } catch (const sim::SceneError& e) {
    names_source(e, "fuzz-scene.json: ");
  }
}

void corpus_reader(std::string_view bytes) {
  std::optional<CorpusEntry> e;
  try {
    e = parse_corpus_entry(bytes, "fuzz-corpus.json");
  } catch (const CaseError& error) {
    well_placed(error, "fuzz-corpus.json", bytes);
  } catch (const std::runtime_error& error) {
    names_source(error, "fuzz-corpus.json: field '");
  }
  if (!e) return;
  round_trips(e->c);
  if (e->path) {
    const PathCase& p = *e->path;
    if (p.frames.empty() || p.object >= p.objects.size()) broken("a camera path without its case", e->c.id);
    // The record the campaign would write of this path reads back as the same path.
    const PathCase q = path_from_json(to_json(p), "written");
    if (to_json(q) != to_json(p)) broken("a camera path that reads back differently", to_json(p).dump());
  }
}

void protocol_reader(std::string_view bytes) {
  const std::string program = "fuzz-program";
  try {
    const std::vector<protocol::OfferedMethod> offered = protocol::parse_handshake(bytes, program);
    // Version 2 may offer systems alone; then the same line reads as systems.
    if (offered.empty() && protocol::parse_offered_systems(bytes, program).empty())
      broken("a handshake read without methods or systems", bytes);
    for (std::size_t i = 0; i < offered.size(); ++i) {
      const MethodInfo& m = offered[i].info;
      if (m.name.empty() || m.volumes == 0 || !(m.tolerance >= 0.0)) broken("a method read without its name, kinds or tolerance", bytes);
      for (std::size_t k = 0; k < i; ++k)
        if (offered[k].info.name == m.name) broken("a handshake read with a method named twice", m.name);
    }
  } catch (const std::runtime_error& e) {
    names_source(e, "external program '" + program + "': ");
  }
  try {
    const std::vector<SystemInfo> systems = protocol::parse_offered_systems(bytes, program);
    for (std::size_t i = 0; i < systems.size(); ++i) {
      const SystemInfo& s = systems[i];
      if (s.name.empty() || s.volumes == 0 || !(s.tolerance >= 0.0)) broken("a system read without its name, kinds or tolerance", bytes);
      for (std::size_t k = 0; k < i; ++k)
        if (systems[k].name == s.name) broken("a handshake read with a system named twice", s.name);
    }
  } catch (const std::runtime_error& e) {
    names_source(e, "external program '" + program + "': ");
  }
  for (const bool three_way : {true, false}) {
    try {
      const protocol::VisibleReply r = protocol::parse_visible(bytes, 1, 3, three_way, "cull message 1");
      const VisibleSet& v = r.set;
      if (v.indices.size() > 3) broken("a visible set read with more ids than objects", bytes);
      if (!v.verdicts.empty() && v.verdicts.size() != v.indices.size()) broken("a visible set read with another number of verdicts", bytes);
      if (three_way && v.verdicts.size() != v.indices.size()) broken("a three-way visible set read without its verdicts", bytes);
      for (const Visibility x : v.verdicts)
        if (x == Visibility::outside || (!three_way && x == Visibility::inside)) broken("a visible set read with a verdict it may not hold", bytes);
      if (r.ns && !(*r.ns >= 0.0)) broken("a visible set read with a negative time", bytes);
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (what.rfind("answered ", 0) != 0 && what.rfind("reported an error for cull message 1", 0) != 0)
        broken("a visible set refused without saying which message", what);
    }
  }
  // As a binary answer: to one frame of as many volumes as the bytes hold, and to two frames
  // sharing them (so that every header field, not only the size, meets the input).
  if (bytes.size() >= protocol::kBinaryAnswerHeader + 2 * protocol::kBinaryAnswerFrameHeader) {
    const std::size_t n = bytes.size() - protocol::kBinaryAnswerHeader - protocol::kBinaryAnswerFrameHeader;
    const std::size_t m = n - protocol::kBinaryAnswerFrameHeader;
    for (const std::vector<protocol::AskedFrame>& frames :
         {std::vector<protocol::AskedFrame>{{1, n}}, std::vector<protocol::AskedFrame>{{1, m / 2}, {2, m - m / 2}}}) {
      try {
        const std::vector<protocol::Reply> r = protocol::parse_binary_answer(bytes, frames, "message 1");
        if (r.size() != frames.size()) broken("a binary answer read with another number of frames", bytes);
        for (std::size_t j = 0; j < r.size(); ++j) {
          if (r[j].verdicts.size() != frames[j].volumes) broken("a binary answer read with another number of verdicts", bytes);
          if (r[j].ns && !(*r[j].ns >= 0.0)) broken("a binary answer read with a negative time", bytes);
          for (const Answer& a : r[j].verdicts)
            if (a && unsigned(*a) > 2) broken("a binary answer read with a verdict that is not one", bytes);
        }
      } catch (const std::runtime_error& e) {
        if (std::string(e.what()).rfind("answered ", 0) != 0) broken("a binary answer refused without saying which message", e.what());
      }
    }
  }
  for (std::size_t volumes : {std::size_t(1), std::size_t(3)}) {
    try {
      const protocol::Reply r = protocol::parse_answer(bytes, 1, volumes, "frame 1");
      if (r.verdicts.size() != volumes) broken("an answer read with another number of verdicts", bytes);
      if (r.ns && !(*r.ns >= 0.0)) broken("an answer read with a negative time", bytes);
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (what.rfind("answered ", 0) != 0 && what.rfind("reported an error for frame 1", 0) != 0)
        broken("an answer refused without saying which frame", what);
    }
  }
}

}  // namespace cullproof::fuzz

// The planted-bug cullers and their controls (mutants.hpp) behind the process protocol
// (docs/protocol.md): one program offering every one of them, so that the verifier's own test runs
// each through the path a culler in another language takes. Frames are read into cullproof's
// case form (a matrix frustum is rebuilt from its matrix, as a culler that extracts its own planes
// would), each volume answered by the mutant's array form where it has one, else one by one.
#include "mutants.hpp"

#include "cullproof/io/case_io.hpp"

#include <nlohmann/json.hpp>

#include <iostream>
#include <string>
#include <vector>

using nlohmann::json;
using namespace cullproof;

namespace {

json kinds(unsigned bits) {
  json a = json::array();
  for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
    if (bits & k) a.push_back(std::string(volume_kind_name(k)));
  return a;
}

// The frame's frustum in the case format: the matrix when there is one, else the planes.
json case_frustum(const json& f) {
  if (!f.contains("matrix")) return json{{"planes", f.at("planes")}};
  return json{{"matrix", f.at("matrix")}, {"depth", f.at("depth")}, {"reversed_z", f.value("reversed_z", false)}};
}

json verdict(const Answer& a) { return a ? json(std::string(to_string(*a))) : json(nullptr); }

}  // namespace

int main() {
  std::ios::sync_with_stdio(false);
  std::vector<mutants::Mutant> all = mutants::all();
  json methods = json::array();
  for (const mutants::Mutant& m : all)
    methods.push_back({{"name", m.method.name},
                       {"claim", std::string(to_string(m.method.claim))},
                       {"tolerance", m.method.tolerance},
                       {"volumes", kinds(m.method.volumes)},
                       {"three_way", m.method.three_way},
                       {"stateful", m.method.stateful},
                       {"description", m.defect}});
  std::cout << json{{"protocol", 1}, {"methods", methods}}.dump() << "\n" << std::flush;

  std::string line;
  while (std::getline(std::cin, line)) {
    const json msg = json::parse(line);
    if (msg.value("bye", false)) break;
    const std::uint64_t frame = msg.at("frame").get<std::uint64_t>();
    const Method* method = nullptr;
    for (const mutants::Mutant& m : all)
      if (m.method.name == msg.at("method").get<std::string>()) method = &m.method;
    if (!method) {
      std::cout << json{{"frame", frame}, {"error", "no method " + msg.at("method").dump()}}.dump() << "\n" << std::flush;
      continue;
    }
    if (msg.value("reset", false)) method->reset();
    const json& volumes = msg.at("volumes");
    const json frustum = case_frustum(msg.at("frustum"));
    std::vector<Volume> v;
    CaseFrustum f;
    for (std::size_t i = 0; i < volumes.size(); ++i) {
      const Case c = parse_case(json{{"id", "frame"}, {"frustum", frustum}, {"volume", volumes[i]}}.dump(), "frame", int(frame));
      if (i == 0) f = c.frustum;
      v.push_back(c.volume);
    }
    json verdicts = json::array();
    const auto p = method->prepare(f);
    if (!p) {
      for (std::size_t i = 0; i < v.size(); ++i) verdicts.push_back(nullptr);
    } else if (method->has_batch() && !v.empty() && std::holds_alternative<Aabb>(v[0])) {
      std::vector<Aabb> boxes;
      for (const Volume& x : v) boxes.push_back(std::get<Aabb>(x));
      std::vector<Answer> a(boxes.size());
      p->classify_batch(boxes.data(), boxes.size(), a.data());
      for (const Answer& x : a) verdicts.push_back(verdict(x));
    } else {
      for (const Volume& x : v) verdicts.push_back(verdict(p->classify(x)));
    }
    std::cout << json{{"frame", frame}, {"verdicts", verdicts}}.dump() << "\n" << std::flush;
  }
  return 0;
}

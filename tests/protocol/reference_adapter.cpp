// A reference adapter for the cullproof process protocol (docs/protocol.md), written from that
// page alone with a JSON library and nothing of cullproof: the n/p-vertex test (Assarsson &
// Moller 2000, §3.1) on the planes of each frame, for AABBs. With a mode argument it plants one
// protocol fault, for the protocol tests: crash, hang, wrong-count, garbage, bad-verdict,
// out-of-order, bad-version, bad-ns, long-answer (16 MiB on one line), deep-answer (nested 100
// deep), long-handshake (a 2 MiB description), deep-handshake; or the planted culling bug
// reject-touching (`<= 0` rejects),
// which the verifier must find through the protocol as it does in process. `published` declares
// the method a text under test, `matrix` asks for matrix frusta only, `unstable` describes itself
// differently in every process. `several` offers two more methods beside it: the same test as
// `reference-fragile`, which aborts (signal 6) on a box whose min.x, as a float, has bits divisible
// by 61 (a known set of cases), and the two-way `reference-p-vertex`. `slow-start` waits two
// seconds before its handshake (an engine loading). It reports its own time.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include <unistd.h>

using nlohmann::json;

int main(int argc, char** argv) {
  // Modes combine: `reject-touching published`.
  auto is = [&](const char* mode) {
    for (int i = 1; i < argc; ++i)
      if (std::string(argv[i]) == mode) return true;
    return false;
  };
  std::ios::sync_with_stdio(false);
  json hello = {{"protocol", is("bad-version") ? 99 : 1},
                {"methods",
                 {{{"name", "reference-pn-vertex"},
                   {"claim", "conservative"},
                   {"tolerance", 1e-6},
                   {"volumes", {"aabb"}},
                   {"three_way", true},
                   {"stateful", false},
                   {"origin", is("published") ? "published" : is("bad-origin") ? "own" : "user"},
                   {"description", is("unstable") ? "process " + std::to_string(::getpid()) : "the n/p-vertex test"},
                   {"frustum", is("matrix") ? "matrix" : "planes"}}}}};
  if (is("several")) {
    json fragile = hello["methods"][0], two_way = hello["methods"][0];
    fragile["name"] = "reference-fragile";
    two_way["name"] = "reference-p-vertex";
    two_way["three_way"] = false;
    hello["methods"].push_back(fragile);
    hello["methods"].push_back(two_way);
  }
  if (is("slow-start")) std::this_thread::sleep_for(std::chrono::seconds(2));
  if (is("long-handshake")) hello["methods"][0]["description"] = std::string(2 << 20, 'x');
  if (is("deep-handshake")) hello["methods"][0]["more"] = json::parse(std::string(100, '[') + std::string(100, ']'));
  std::cout << hello.dump() << "\n" << std::flush;
  std::string line;
  long frames = 0;
  while (std::getline(std::cin, line)) {
    const json m = json::parse(line);
    if (m.value("bye", false)) break;
    ++frames;
    if (frames == 3) {  // the planted faults strike on the third frame
      if (is("crash")) std::abort();
      if (is("hang")) std::this_thread::sleep_for(std::chrono::hours(1));
      if (is("garbage")) {
        std::cout << "segfault? no, just text\n" << std::flush;
        continue;
      }
      if (is("long-answer")) {  // far more verdicts than volumes, on one line
        std::cout << "{\"frame\": " << m["frame"].get<long>() << ", \"verdicts\": [";
        for (int i = 0; i < (16 << 20) / 11; ++i) std::cout << "\"outside\", ";
        std::cout << "\"outside\"]}\n" << std::flush;
        continue;
      }
      if (is("deep-answer")) {
        std::cout << "{\"frame\": " << m["frame"].get<long>() << ", \"verdicts\": [\"outside\"], \"x\": "
                  << std::string(100, '[') << std::string(100, ']') << "}\n" << std::flush;
        continue;
      }
    }
    if (is("matrix") && !m["frustum"].contains("matrix")) {
      std::cout << json{{"frame", m["frame"]}, {"error", "asked about a frustum without a matrix"}}.dump() << "\n" << std::flush;
      continue;
    }
    json verdicts = json::array();
    const auto start = std::chrono::steady_clock::now();
    const std::string method = m["method"];
    for (const json& v : m["volumes"]) {
      const json& b = v["aabb"];
      float lo[3], hi[3];
      for (int i = 0; i < 3; ++i) lo[i] = float(b["min"][i].get<double>()), hi[i] = float(b["max"][i].get<double>());
      std::uint32_t bits = 0;
      std::memcpy(&bits, &lo[0], sizeof bits);
      if (method == "reference-fragile" && bits % 61 == 0) std::abort();
      bool inside = true, outside = false;
      for (const json& p : m["frustum"]["planes"]) {
        float n[3], d = float(p[3].get<double>());
        for (int i = 0; i < 3; ++i) n[i] = float(p[i].get<double>());
        float pv = d, nv = d;
        for (int i = 0; i < 3; ++i) {
          pv += n[i] * (n[i] >= 0 ? hi[i] : lo[i]);
          nv += n[i] * (n[i] >= 0 ? lo[i] : hi[i]);
        }
        if (is("reject-touching") ? pv <= 0 : pv < 0) {
          outside = true;
          break;
        }
        if (nv < 0) inside = false;
      }
      verdicts.push_back(outside ? "outside" : inside && method != "reference-p-vertex" ? "inside" : "intersecting");
    }
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    if (frames == 3 && is("wrong-count")) verdicts.push_back("outside");
    if (frames == 3 && is("bad-verdict")) verdicts[0] = "visible";
    const long id = m["frame"].get<long>();
    json answer = {{"frame", frames == 3 && is("out-of-order") ? id + 1 : id}, {"verdicts", verdicts}, {"ns", ns}};
    if (frames == 3 && is("bad-ns")) answer["ns"] = "fast";
    std::cout << answer.dump() << "\n" << std::flush;
  }
  return 0;
}

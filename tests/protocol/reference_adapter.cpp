// A reference adapter for the cullproof process protocol (docs/protocol.md), written from that
// page alone with a JSON library and nothing of cullproof: the n/p-vertex test (Assarsson &
// Moller 2000, §3.1) on the planes of each frame, for AABBs. With a mode argument it plants one
// protocol fault, for the protocol tests: crash, hang, wrong-count, garbage, bad-verdict,
// out-of-order, bad-version; or the planted culling bug reject-touching (`<= 0` rejects), which
// the verifier must find through the protocol as it does in process.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

using nlohmann::json;

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "ok";
  std::ios::sync_with_stdio(false);
  json hello = {{"protocol", mode == "bad-version" ? 99 : 1},
                {"methods",
                 {{{"name", "reference-pn-vertex"},
                   {"claim", "conservative"},
                   {"tolerance", 1e-6},
                   {"volumes", {"aabb"}},
                   {"three_way", true},
                   {"stateful", false}}}}};
  std::cout << hello.dump() << "\n" << std::flush;
  std::string line;
  long frames = 0;
  while (std::getline(std::cin, line)) {
    const json m = json::parse(line);
    if (m.value("bye", false)) break;
    ++frames;
    if (frames == 3) {  // the planted faults strike on the third frame
      if (mode == "crash") std::abort();
      if (mode == "hang") std::this_thread::sleep_for(std::chrono::hours(1));
      if (mode == "garbage") {
        std::cout << "segfault? no, just text\n" << std::flush;
        continue;
      }
    }
    json verdicts = json::array();
    for (const json& v : m["volumes"]) {
      const json& b = v["aabb"];
      float lo[3], hi[3];
      for (int i = 0; i < 3; ++i) lo[i] = float(b["min"][i].get<double>()), hi[i] = float(b["max"][i].get<double>());
      bool inside = true, outside = false;
      for (const json& p : m["frustum"]["planes"]) {
        float n[3], d = float(p[3].get<double>());
        for (int i = 0; i < 3; ++i) n[i] = float(p[i].get<double>());
        float pv = d, nv = d;
        for (int i = 0; i < 3; ++i) {
          pv += n[i] * (n[i] >= 0 ? hi[i] : lo[i]);
          nv += n[i] * (n[i] >= 0 ? lo[i] : hi[i]);
        }
        if (mode == "reject-touching" ? pv <= 0 : pv < 0) {
          outside = true;
          break;
        }
        if (nv < 0) inside = false;
      }
      verdicts.push_back(outside ? "outside" : inside ? "inside" : "intersecting");
    }
    if (frames == 3 && mode == "wrong-count") verdicts.push_back("outside");
    if (frames == 3 && mode == "bad-verdict") verdicts[0] = "visible";
    const long id = m["frame"].get<long>();
    std::cout << json{{"frame", frames == 3 && mode == "out-of-order" ? id + 1 : id}, {"verdicts", verdicts}}.dump() << "\n"
              << std::flush;
  }
  return 0;
}

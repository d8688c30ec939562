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
// seconds before its handshake (an engine loading). It reports its own time. `binary` speaks
// version 3 with the binary encoding of frames and answers; its faults (on the third message)
// are crash, hang, wrong-count, garbage, bad-verdict (byte 7), out-of-order, bad-ns (NaN), error
// (a JSON error line), long-answer (bytes past the answer) and truncated (half an answer, then
// exit).
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <vector>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <iostream>
#include <string>
#include <thread>

#include <unistd.h>

using nlohmann::json;

namespace {

// The n/p-vertex test of one box against six planes (a, b, c, d): 0 outside, 1 intersecting,
// 2 inside. `touching_rejects` plants the `<= 0` bug.
int pn_vertex(const float planes[6][4], const float lo[3], const float hi[3], bool touching_rejects) {
  bool inside = true;
  for (int k = 0; k < 6; ++k) {
    const float* n = planes[k];
    float pv = n[3], nv = n[3];
    for (int i = 0; i < 3; ++i) {
      pv += n[i] * (n[i] >= 0 ? hi[i] : lo[i]);
      nv += n[i] * (n[i] >= 0 ? lo[i] : hi[i]);
    }
    if (touching_rejects ? pv <= 0 : pv < 0) return 0;
    if (nv < 0) inside = false;
  }
  return inside ? 2 : 1;
}

template <class T>
T take(const char*& p) {
  T x;
  std::memcpy(&x, p, sizeof x);
  p += sizeof x;
  return x;
}
template <class T>
void give(std::string& out, T x) {
  out.append(reinterpret_cast<const char*>(&x), sizeof x);
}

// The binary encoding (docs/protocol.md, version 3): read messages until the JSON "bye".
int serve_binary(bool (*is)(const char*), const std::vector<std::string>& names) {
  long messages = 0;
  for (;;) {
    const int first = std::cin.peek();
    if (first == EOF) return 0;
    if (first == '{') {  // the JSON "bye"
      std::string line;
      std::getline(std::cin, line);
      if (json::parse(line).value("bye", false)) return 0;
      continue;
    }
    char header[12];
    if (!std::cin.read(header, sizeof header)) return 0;
    if (std::memcmp(header, "CP3F", 4) != 0) {
      std::fprintf(stderr, "not a binary frame message\n");
      return 1;
    }
    const char* h = header + 4;
    const auto frames = take<std::uint32_t>(h);
    const auto length = take<std::uint32_t>(h);
    static std::string body, answer;  // reused message after message
    body.resize(length);
    if (!std::cin.read(body.data(), length)) return 0;
    ++messages;
    const bool third = messages == 3;  // the planted faults strike on the third message
    if (third && is("crash")) std::abort();
    if (third && is("hang")) std::this_thread::sleep_for(std::chrono::hours(1));
    if (third && is("garbage")) {
      std::cout << "segfault? no, just text\n" << std::flush;
      continue;
    }
    answer = "CP3A";
    give(answer, frames);
    const char* p = body.data();
    for (std::uint32_t f = 0; f < frames; ++f) {
      const auto id = take<std::uint64_t>(p);
      const auto method = take<std::uint32_t>(p);
      const auto count = take<std::uint32_t>(p);
      const auto kind = take<std::uint8_t>(p);
      const auto flags = take<std::uint8_t>(p);
      p += 2;  // the depth convention and reversed-Z, read with the matrix
      float planes[6][4];
      for (auto& pl : planes)
        for (float& x : pl) x = take<float>(p);
      if (flags & 2) p += 16 * sizeof(float);  // the matrix: this culler uses the planes
      if (third && is("error")) {
        std::cout << json{{"frame", id}, {"error", "cannot cull this frame"}}.dump() << "\n" << std::flush;
        answer.clear();
        break;
      }
      const auto start = std::chrono::steady_clock::now();
      static std::string verdicts;
      verdicts.clear();
      for (std::uint32_t v = 0; v < count; ++v) {
        float lo[3], hi[3];
        for (float& x : lo) x = take<float>(p);
        for (float& x : hi) x = take<float>(p);
        if (kind != 2) return 2;  // it declared AABBs only
        std::uint32_t bits = 0;
        std::memcpy(&bits, &lo[0], sizeof bits);
        if (names.at(method) == "reference-fragile" && bits % 61 == 0) std::abort();
        int verdict = pn_vertex(planes, lo, hi, is("reject-touching"));
        if (verdict == 2 && names.at(method) == "reference-p-vertex") verdict = 1;
        verdicts += char(third && is("bad-verdict") && v == 0 ? 7 : verdict);
      }
      double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
      if (third && is("bad-ns")) ns = std::nan("");
      give(answer, third && is("out-of-order") ? id + 1 : id);
      give(answer, std::uint32_t(third && is("wrong-count") ? count + 1 : count));
      give(answer, ns);
      answer += verdicts;
      if (third && is("wrong-count")) answer += char(0);
    }
    if (third && is("long-answer")) answer += std::string(100, 'x');
    if (third && is("truncated")) {
      std::cout.write(answer.data(), std::streamsize(answer.size() / 2)) << std::flush;
      return 0;
    }
    std::cout.write(answer.data(), std::streamsize(answer.size())) << std::flush;
  }
}

std::vector<std::string> g_modes;
bool mode_is(const char* mode) {
  for (const std::string& m : g_modes)
    if (m == mode) return true;
  return false;
}

}  // namespace

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
  if (is("binary")) {
    hello["protocol"] = 3;
    hello["encoding"] = "binary";
  }
  std::cout << hello.dump() << "\n" << std::flush;
  if (is("binary")) {
    g_modes.assign(argv + 1, argv + argc);
    std::vector<std::string> names;
    for (const json& m : hello["methods"]) names.push_back(m["name"]);
    return serve_binary(mode_is, names);
  }
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

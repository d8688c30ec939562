// A culling system behind the process protocol, version 2, written from docs/protocol.md alone
// (nothing of cullproof linked): a flat loop over the scene's objects, each tested by its
// enclosing box (worked out in double, rounded outward to float) with the n/p-vertex test. Its
// answers report its own time for the loop ("ns").
//
// argv[1] plants a fault for the tests: "drop-near" (the near plane forgotten: a claim to refute),
// "crash-on-scene", "hang-on-cull", "wrong-count" (one verdict fewer than ids), "unknown-id".
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

using nlohmann::json;

namespace {

struct Box {
  float lo[3], hi[3];
};

float down(double x) {
  float f = static_cast<float>(x);
  if (double(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float up(double x) {
  float f = static_cast<float>(x);
  if (double(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// The volume's box: its extreme coordinates in double, one double step outward (more than the
// double sums round), then to float outward.
Box box_of(const json& v) {
  Box b{};
  auto set = [&](int k, double lo, double hi) {
    b.lo[k] = down(std::nextafter(lo, -INFINITY));
    b.hi[k] = up(std::nextafter(hi, INFINITY));
  };
  if (v.contains("point")) {
    for (int k = 0; k < 3; ++k) b.lo[k] = b.hi[k] = v["point"][k].get<float>();
  } else if (v.contains("aabb")) {
    for (int k = 0; k < 3; ++k) b.lo[k] = v["aabb"]["min"][k].get<float>(), b.hi[k] = v["aabb"]["max"][k].get<float>();
  } else if (v.contains("sphere")) {
    const double r = v["sphere"]["radius"].get<float>();
    for (int k = 0; k < 3; ++k) {
      const double c = v["sphere"]["center"][k].get<float>();
      set(k, c - r, c + r);
    }
  } else {
    const json& o = v["obb"];
    for (int k = 0; k < 3; ++k) {
      double e = 0.0;
      for (int i = 0; i < 3; ++i) e += double(o["half"][i].get<float>()) * std::abs(double(o["axes"][i][k].get<float>()));
      const double c = o["center"][k].get<float>();
      set(k, c - e, c + e);
    }
  }
  return b;
}

// 0 outside, 1 intersecting, 2 inside.
int classify(const std::array<std::array<float, 4>, 6>& planes, const Box& b, bool drop_near) {
  bool straddles = false;
  for (int i = 0; i < 6; ++i) {
    if (drop_near && i == 4) continue;
    const auto& p = planes[i];
    float pv = p[3], nv = p[3];
    for (int k = 0; k < 3; ++k) {
      pv += p[k] * (p[k] > 0 ? b.hi[k] : b.lo[k]);
      nv += p[k] * (p[k] > 0 ? b.lo[k] : b.hi[k]);
    }
    if (pv < 0) return 0;
    if (nv < 0) straddles = true;
  }
  return straddles ? 1 : 2;
}

void answer(const json& a) { std::cout << a.dump() << "\n" << std::flush; }

}  // namespace

int main(int argc, char** argv) {
  const std::string fault = argc > 1 ? argv[1] : "";
  answer({{"protocol", 2},
          {"systems", {{{"name", "reference-flat"},
                        {"claim", "conservative"},
                        {"tolerance", 1e-6},
                        {"volumes", {"point", "sphere", "aabb", "obb"}},
                        {"three_way", true},
                        {"description", "every object's box, n/p-vertex test, in a flat loop"}}}}});
  std::unordered_map<std::uint32_t, Box> boxes;
  std::vector<std::uint32_t> order;
  for (std::string line; std::getline(std::cin, line);) {
    const json m = json::parse(line);
    if (m.contains("bye")) return 0;
    const auto frame = m["frame"].get<std::uint64_t>();
    if (m.contains("scene")) {
      if (fault == "crash-on-scene") std::abort();
      boxes.clear(), order.clear();
      for (const json& o : m["scene"]["objects"]) {
        const auto id = o["id"].get<std::uint32_t>();
        boxes[id] = box_of(o["world"]);
        order.push_back(id);
      }
      answer({{"frame", frame}, {"built", true}});
    } else if (m.contains("moved")) {
      for (const json& o : m["moved"]) boxes[o["id"].get<std::uint32_t>()] = box_of(o["world"]);
      answer({{"frame", frame}, {"updated", true}});
    } else if (m.contains("view")) {
      if (fault == "hang-on-cull") std::this_thread::sleep_for(std::chrono::hours(1));
      std::array<std::array<float, 4>, 6> planes{};
      for (int i = 0; i < 6; ++i)
        for (int k = 0; k < 4; ++k) planes[i][k] = m["view"]["frustum"]["planes"][i][k].get<float>();
      json visible = json::array(), verdicts = json::array();
      const auto t0 = std::chrono::steady_clock::now();
      for (std::uint32_t id : order) {
        const int r = classify(planes, boxes[id], fault == "drop-near");
        if (r == 0) continue;
        visible.push_back(id);
        verdicts.push_back(r == 2 ? "inside" : "intersecting");
      }
      if (fault == "unknown-id") visible.push_back(4000000000u), verdicts.push_back("inside");
      if (fault == "wrong-count") {
        if (verdicts.empty()) verdicts.push_back("inside");
        else verdicts.erase(verdicts.size() - 1);
      }
      const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
      answer({{"frame", frame}, {"visible", visible}, {"verdicts", verdicts}, {"ns", ns}});
    } else {
      answer({{"frame", frame}, {"error", "unknown message"}});
    }
  }
  return 0;
}

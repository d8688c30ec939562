// The cullproof process protocol, version 1 (docs/protocol.md), for C++ engine adapters: the
// handshake, the frame loop, the answers. An adapter describes its methods and gives two calls
// per method:
//   prepare(frame)            untimed: build the engine's own objects from the frame (a plane
//                             set, a tree of the frame's volumes);
//   classify(frame, verdicts) timed: the engine's culling calls for all of the frame's volumes,
//                             one verdict per volume (left as Verdict::none, sent as null, for a
//                             volume the method does not take).
// Every number is read as a double and rounded to float: that float is the geometry. The answer
// carries "ns", the steady_clock nanoseconds spent in classify (not parsing, not formatting).
//
// Planes are given to the adapter in double. For a frustum given by a clip matrix they are the
// Gribb-Hartmann row sums of the float matrix computed in double (docs/semantics.md), as an
// engine extracts its planes from its own projection matrix, rather than the frame's planes,
// which are those sums rounded to float: the truth is the exact extraction, and an engine that
// computes in double is judged on its own arithmetic, not on the rounding of cullproof's. A sum
// of two floats is exact in double unless their exponents differ by more than 29, so an engine
// that takes float planes gets the frame's planes back when it rounds these.
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cullproof_adapter {

using json = nlohmann::json;
using Vec3 = std::array<float, 3>;

enum class Verdict { none, outside, intersecting, inside };

struct Plane {
  double a, b, c, d;  // a x + b y + c z + d >= 0 inside; order left, right, bottom, top, near, far
};

struct Volume {
  enum class Kind { point, sphere, aabb, obb } kind;
  Vec3 p{};                   // point; sphere centre; aabb min; obb centre
  Vec3 q{};                   // aabb max; obb half-extents
  float radius = 0;           // sphere
  std::array<Vec3, 3> axes{};  // obb axis columns
};

struct Frame {
  std::int64_t id = 0;
  std::string method;
  bool reset = false;
  std::array<Plane, 6> planes{};
  std::vector<Volume> volumes;
};

struct Method {
  json description;  // the handshake entry
  std::function<void(const Frame&)> prepare;
  std::function<void(const Frame&, std::vector<Verdict>&)> classify;
};

// A handshake entry: a stateless method of a published engine (origin "published": a refuted
// claim is a finding about the engine, not a failure of the adapter).
inline json describe(const std::string& name, const std::string& claim, double tolerance,
                     std::vector<std::string> volumes, bool three_way, const std::string& description,
                     const std::string& source, const std::string& touching) {
  return {{"name", name},           {"claim", claim},     {"tolerance", tolerance},
          {"volumes", volumes},     {"three_way", three_way}, {"stateful", false},
          {"origin", "published"},  {"description", description}, {"source", source},
          {"touching", touching}};
}

namespace detail {

// A number as a double rounded to float; a C99 hex-float string is accepted too.
inline float number(const json& j) {
  if (j.is_string()) return float(std::strtod(j.get_ref<const std::string&>().c_str(), nullptr));
  return float(j.get<double>());
}

inline Vec3 vec3(const json& j) { return {number(j.at(0)), number(j.at(1)), number(j.at(2))}; }

inline Volume volume(const json& j) {
  Volume v{};
  if (j.contains("point")) {
    v.kind = Volume::Kind::point;
    v.p = vec3(j["point"]);
  } else if (j.contains("sphere")) {
    v.kind = Volume::Kind::sphere;
    v.p = vec3(j["sphere"].at("center"));
    v.radius = number(j["sphere"].at("radius"));
  } else if (j.contains("aabb")) {
    v.kind = Volume::Kind::aabb;
    v.p = vec3(j["aabb"].at("min"));
    v.q = vec3(j["aabb"].at("max"));
  } else if (j.contains("obb")) {
    v.kind = Volume::Kind::obb;
    v.p = vec3(j["obb"].at("center"));
    for (int i = 0; i < 3; ++i) v.axes[i] = vec3(j["obb"].at("axes").at(i));
    v.q = vec3(j["obb"].at("half"));
  } else {
    throw std::runtime_error("a volume of no known kind: " + j.dump());
  }
  return v;
}

// Rows r1..r4 of the column-major clip matrix (clip = M x): left r4 + r1, right r4 - r1, bottom
// r4 + r2, top r4 - r2, far r4 - r3, near r4 + r3 (depth [-1, 1]) or r3 (depth [0, 1]);
// reversed-Z exchanges near and far. Sums in double of the float entries.
inline std::array<Plane, 6> matrix_planes(const json& frustum) {
  const json& m = frustum.at("matrix");
  if (m.size() != 16) throw std::runtime_error("a matrix of " + std::to_string(m.size()) + " numbers");
  auto row = [&](int r) {
    return std::array<double, 4>{number(m[r]), number(m[4 + r]), number(m[8 + r]), number(m[12 + r])};
  };
  const auto r1 = row(0), r2 = row(1), r3 = row(2), r4 = row(3);
  auto sum = [&](const std::array<double, 4>& p, double s, const std::array<double, 4>& q) {
    return Plane{p[0] + s * q[0], p[1] + s * q[1], p[2] + s * q[2], p[3] + s * q[3]};
  };
  const bool zero_to_one = frustum.at("depth").get<std::string>() == "zero_to_one";
  const Plane lower = zero_to_one ? Plane{r3[0], r3[1], r3[2], r3[3]} : sum(r4, 1, r3);
  const Plane upper = sum(r4, -1, r3);
  const bool reversed = frustum.value("reversed_z", false);
  return {sum(r4, 1, r1), sum(r4, -1, r1), sum(r4, 1, r2), sum(r4, -1, r2), reversed ? upper : lower,
          reversed ? lower : upper};
}

inline Frame frame(const json& m) {
  Frame f;
  f.id = m.at("frame").get<std::int64_t>();
  f.method = m.at("method").get<std::string>();
  f.reset = m.value("reset", false);
  const json& frustum = m.at("frustum");
  if (frustum.contains("matrix")) {
    f.planes = matrix_planes(frustum);
  } else {
    const json& planes = frustum.at("planes");
    if (planes.size() != 6) throw std::runtime_error("a frustum of " + std::to_string(planes.size()) + " planes");
    for (std::size_t i = 0; i < 6; ++i) {
      const json& p = planes[i];
      f.planes[i] = {number(p.at(0)), number(p.at(1)), number(p.at(2)), number(p.at(3))};
    }
  }
  for (const json& v : m.at("volumes")) f.volumes.push_back(volume(v));
  return f;
}

inline const char* name(Verdict v) {
  switch (v) {
    case Verdict::outside: return "outside";
    case Verdict::intersecting: return "intersecting";
    case Verdict::inside: return "inside";
    case Verdict::none: break;
  }
  return nullptr;
}

inline void send(const json& j) { std::cout << j.dump() << '\n' << std::flush; }

}  // namespace detail

// Speaks the protocol on stdin/stdout until {"bye": true} or the end of input; returns the exit
// status. A frame that cannot be answered (bad message, unknown method, an exception) is answered
// with "error", which stops cullproof's run.
inline int run(const std::vector<Method>& methods) {
  std::ios::sync_with_stdio(false);
  json hello = {{"protocol", 1}, {"methods", json::array()}};
  for (const Method& m : methods) hello["methods"].push_back(m.description);
  detail::send(hello);

  std::string line;
  std::vector<Verdict> verdicts;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    json id;  // the frame number, once known
    json answer;
    try {
      const json m = json::parse(line);
      if (m.value("bye", false)) break;
      id = m.at("frame");
      const Frame f = detail::frame(m);
      const Method* method = nullptr;
      for (const Method& c : methods)
        if (c.description["name"] == f.method) method = &c;
      if (!method) throw std::runtime_error("no method named " + f.method);

      method->prepare(f);
      verdicts.assign(f.volumes.size(), Verdict::none);
      const auto t0 = std::chrono::steady_clock::now();
      method->classify(f, verdicts);
      const auto t1 = std::chrono::steady_clock::now();

      json out = json::array();
      for (Verdict v : verdicts) out.push_back(v == Verdict::none ? json() : json(detail::name(v)));
      answer = {{"frame", id}, {"verdicts", std::move(out)},
                {"ns", std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count()}};
    } catch (const std::exception& e) {
      answer = {{"frame", id}, {"error", e.what()}};
    }
    detail::send(answer);
  }
  return 0;
}

}  // namespace cullproof_adapter

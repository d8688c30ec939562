// The cullproof process protocol, versions 1 and 2 (docs/protocol.md), for C++ engine adapters:
// the handshake, the frame loop, the answers. An adapter describes its methods and gives two calls
// per method:
//   prepare(frame)            untimed: build the engine's own objects from the frame (a plane
//                             set, a tree of the frame's volumes);
//   classify(frame, verdicts) timed: the engine's culling calls for all of the frame's volumes,
//                             one verdict per volume (left as Verdict::none, sent as null, for a
//                             volume the method does not take).
// and, for a culling system (version 2), four calls:
//   build(objects)            the scene's objects, replacing any scene held;
//   update(moved)             the objects that moved, with their new bounds;
//   prepare(view)             untimed: what the engine does each frame before it culls (a physics
//                             step, a matrix to planes);
//   cull(view, visible)       timed: the visible set, ids (and for a three-way system their
//                             verdicts, inside or intersecting); an id not listed is outside.
// Every number is read as a double and rounded to float: that float is the geometry. The answer
// carries "ns", the steady_clock nanoseconds spent in classify or cull (not parsing, not
// formatting).
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
  // A frustum given by a clip matrix: the float matrix (column-major, clip = M x), its depth
  // range ("negative_one_to_one" or "zero_to_one") and whether it is reversed-Z.
  bool has_matrix = false;
  std::array<float, 16> matrix{};
  std::string depth;
  bool reversed_z = false;
};

struct Method {
  json description;  // the handshake entry
  std::function<void(const Frame&)> prepare;
  std::function<void(const Frame&, std::vector<Verdict>&)> classify;
};

// A scene object: its stable id, its world volume (the truth is decided on it), its local volume
// and the column-major transform from local to world.
struct Object {
  std::uint32_t id = 0;
  Volume world{};
  Volume local{};
  std::array<float, 16> transform{};
};

// A frame of a system: the planes as a method frame's (from the clip matrix, in double, where
// there is one), the clip matrix with its depth convention as a method frame's, the camera's
// matrices (column-major), its eye and axes (right, up, back, column by column; it looks along
// -back).
struct View {
  std::int64_t id = 0;
  std::array<Plane, 6> planes{};
  bool has_matrix = false;
  std::array<float, 16> matrix{};
  std::string depth;
  bool reversed_z = false;
  std::array<float, 16> view{}, projection{};
  Vec3 eye{};
  std::array<Vec3, 3> axes{};
  bool perspective = true;
};

// The answer to a view: the ids drawn; for a three-way system one verdict per id (inside or
// intersecting), for a two-way one none.
struct VisibleSet {
  std::vector<std::uint32_t> ids;
  std::vector<Verdict> verdicts;
};

struct System {
  json description;  // the handshake entry
  std::function<void(const std::vector<Object>&)> build;
  std::function<void(const std::vector<Object>&)> update;
  std::function<void(const View&)> prepare;
  std::function<void(const View&, VisibleSet&)> cull;
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

// A system's handshake entry (as a method's, without "stateful": a system's state is its own).
inline json describe_system(const std::string& name, const std::string& claim, double tolerance,
                            std::vector<std::string> volumes, bool three_way, const std::string& description,
                            const std::string& source, const std::string& touching) {
  json j = describe(name, claim, tolerance, std::move(volumes), three_way, description, source, touching);
  j.erase("stateful");
  return j;
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

inline std::array<Plane, 6> planes_of(const json& frustum) {
  if (frustum.contains("matrix")) return matrix_planes(frustum);
  const json& planes = frustum.at("planes");
  if (planes.size() != 6) throw std::runtime_error("a frustum of " + std::to_string(planes.size()) + " planes");
  std::array<Plane, 6> out{};
  for (std::size_t i = 0; i < 6; ++i) {
    const json& p = planes[i];
    out[i] = {number(p.at(0)), number(p.at(1)), number(p.at(2)), number(p.at(3))};
  }
  return out;
}

template <std::size_t N>
std::array<float, N> numbers(const json& j) {
  if (j.size() != N) throw std::runtime_error(std::to_string(j.size()) + " numbers where " + std::to_string(N) + " belong");
  std::array<float, N> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = number(j[i]);
  return out;
}

// A Frame's or a View's clip matrix and its depth convention, where the frustum has one.
template <class T>
void clip_of(const json& frustum, T& out) {
  if (!frustum.contains("matrix")) return;
  out.has_matrix = true;
  out.matrix = numbers<16>(frustum.at("matrix"));
  out.depth = frustum.at("depth").get<std::string>();
  out.reversed_z = frustum.value("reversed_z", false);
}

inline std::vector<Object> objects(const json& list) {
  std::vector<Object> out;
  for (const json& o : list) {
    Object x;
    x.id = o.at("id").get<std::uint32_t>();
    x.world = volume(o.at("world"));
    x.local = volume(o.at("local"));
    x.transform = numbers<16>(o.at("transform"));
    out.push_back(x);
  }
  return out;
}

inline View view(std::int64_t id, const json& v) {
  View out;
  out.id = id;
  const json& frustum = v.at("frustum");
  out.planes = planes_of(frustum);
  clip_of(frustum, out);
  out.view = numbers<16>(v.at("view"));
  out.projection = numbers<16>(v.at("projection"));
  out.eye = vec3(v.at("eye"));
  const auto axes = numbers<9>(v.at("axes"));
  for (int i = 0; i < 3; ++i) out.axes[std::size_t(i)] = {axes[std::size_t(3 * i)], axes[std::size_t(3 * i + 1)], axes[std::size_t(3 * i + 2)]};
  out.perspective = v.at("perspective").get<bool>();
  return out;
}

inline Frame frame(const json& m) {
  Frame f;
  f.id = m.at("frame").get<std::int64_t>();
  f.method = m.at("method").get<std::string>();
  f.reset = m.value("reset", false);
  const json& frustum = m.at("frustum");
  f.planes = planes_of(frustum);
  clip_of(frustum, f);
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

// The points an engine that bounds a point list is given for a volume: the point; a box's or an
// OBB's 8 corners (corner i takes the maximum, or +half, along axis k when bit k of i is set); a
// sphere's 6 extreme points, c -+ r along each axis. In float, as the engines' own vectors compute.
inline std::vector<Vec3> volume_points(const Volume& v) {
  std::vector<Vec3> out;
  switch (v.kind) {
    case Volume::Kind::point: out.push_back(v.p); break;
    case Volume::Kind::aabb:
      for (unsigned i = 0; i < 8; ++i)
        out.push_back({(i & 1u) ? v.q[0] : v.p[0], (i & 2u) ? v.q[1] : v.p[1], (i & 4u) ? v.q[2] : v.p[2]});
      break;
    case Volume::Kind::sphere:
      for (std::size_t axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
          Vec3 x = v.p;
          x[axis] += sign * v.radius;
          out.push_back(x);
        }
      break;
    case Volume::Kind::obb:
      for (unsigned i = 0; i < 8; ++i) {
        Vec3 x = v.p;
        for (std::size_t k = 0; k < 3; ++k) {
          const float s = (i >> k & 1u) ? v.q[k] : -v.q[k];
          for (std::size_t j = 0; j < 3; ++j) x[j] += v.axes[k][j] * s;
        }
        out.push_back(x);
      }
      break;
  }
  return out;
}

// Entry (3, c) of a column-major clip matrix of depth convention `depth` (reversed or not) made
// OpenGL's (depth in [-1, 1], near at -1), for engines that take only that convention: from
// [0, 1], 2 r3 - r4 (reversed: r4 - 2 r3); from reversed [-1, 1], -r3. r3 and r4 are column c's
// entries of rows 3 and 4; the same planes, so the same frustum.
inline double opengl_depth_row(double r3, double r4, const std::string& depth, bool reversed_z) {
  if (depth == "zero_to_one") return reversed_z ? r4 - 2 * r3 : 2 * r3 - r4;
  return reversed_z ? -r3 : r3;
}

// Speaks the protocol on stdin/stdout until {"bye": true} or the end of input; returns the exit
// status. Version 1 when there are no systems, else 2. A message that cannot be answered (bad
// message, unknown method or system, an exception) is answered with "error", which stops
// cullproof's run.
inline int run(const std::vector<Method>& methods, const std::vector<System>& systems = {}) {
  std::ios::sync_with_stdio(false);
  json hello = {{"protocol", systems.empty() ? 1 : 2}};
  if (!methods.empty() || systems.empty()) {
    hello["methods"] = json::array();
    for (const Method& m : methods) hello["methods"].push_back(m.description);
  }
  if (!systems.empty()) {
    hello["systems"] = json::array();
    for (const System& s : systems) hello["systems"].push_back(s.description);
  }
  detail::send(hello);

  std::string line;
  std::vector<Verdict> verdicts;
  VisibleSet visible;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    json id;  // the frame number, once known
    json answer;
    try {
      const json m = json::parse(line);
      if (m.value("bye", false)) break;
      id = m.at("frame");
      if (m.contains("system")) {
        const std::string wanted = m.at("system").get<std::string>();
        const System* system = nullptr;
        for (const System& c : systems)
          if (c.description["name"] == wanted) system = &c;
        if (!system) throw std::runtime_error("no system named " + wanted);
        if (m.contains("scene")) {
          system->build(detail::objects(m.at("scene").at("objects")));
          answer = {{"frame", id}, {"built", true}};
        } else if (m.contains("moved")) {
          system->update(detail::objects(m.at("moved")));
          answer = {{"frame", id}, {"updated", true}};
        } else {
          const View v = detail::view(id.get<std::int64_t>(), m.at("view"));
          system->prepare(v);
          visible.ids.clear();
          visible.verdicts.clear();
          const auto t0 = std::chrono::steady_clock::now();
          system->cull(v, visible);
          const auto t1 = std::chrono::steady_clock::now();
          answer = {{"frame", id}, {"visible", visible.ids},
                    {"ns", std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count()}};
          if (!visible.verdicts.empty()) {
            json out = json::array();
            for (Verdict x : visible.verdicts) out.push_back(detail::name(x));
            answer["verdicts"] = std::move(out);
          }
        }
        detail::send(answer);
        continue;
      }
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

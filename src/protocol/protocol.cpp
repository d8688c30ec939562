// Reading the process protocol's messages (see cullproof/protocol/protocol.hpp and docs/protocol.md). Every
// field is checked for its type before it is read, so a message of the wrong shape is refused with
// the field named, never with a JSON library's type error.
#include "cullproof/protocol/protocol.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/io/limits.hpp"
#include "cullproof/protocol/external.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <set>
#include <stdexcept>
#include <vector>

namespace cullproof::protocol {

using nlohmann::json;

std::string excerpt(std::string_view line) {
  return printable_text(line.substr(0, 200)) + (line.size() > 200 ? "..." : "");
}

namespace {

// The optional field `key` of the object `m`: its value, `fallback` when absent; `at` names the
// object in the error for a value of the wrong type.
std::string string_field(const json& m, const char* key, const std::string& fallback, const std::string& at) {
  const auto it = m.find(key);
  if (it == m.end()) return fallback;
  if (!it->is_string()) throw std::runtime_error(fmt::format("{}: \"{}\" {} is not a string", at, key, excerpt(it->dump())));
  return it->get<std::string>();
}

bool bool_field(const json& m, const char* key, bool fallback, const std::string& at) {
  const auto it = m.find(key);
  if (it == m.end()) return fallback;
  if (!it->is_boolean()) throw std::runtime_error(fmt::format("{}: \"{}\" {} is not true or false", at, key, excerpt(it->dump())));
  return it->get<bool>();
}

unsigned kinds_of(const json& j, const std::string& where) {
  unsigned k = 0;
  if (!j.is_array() || j.empty()) throw std::runtime_error(where + ": \"volumes\" must be a non-empty array of kinds");
  for (const json& x : j) {
    const std::string s = x.is_string() ? x.get<std::string>() : std::string();
    if (s == "point") k |= kPointKind;
    else if (s == "sphere") k |= kSphereKind;
    else if (s == "aabb") k |= kAabbKind;
    else if (s == "obb") k |= kObbKind;
    else throw std::runtime_error(where + ": unknown volume kind " + excerpt(x.dump()) + " (point, sphere, aabb, obb)");
  }
  return k;
}

// Refuses a field of `m` not in `known` (a misspelt "claim" would otherwise leave the claim
// `none`, which nothing can refute).
void known_fields(const json& m, const std::vector<const char*>& known, const std::string& what, const std::string& at) {
  for (const auto& item : m.items()) {
    if (std::any_of(known.begin(), known.end(), [&](const char* k) { return item.key() == k; })) continue;
    std::string list;
    for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
    throw std::runtime_error(fmt::format("{}: unknown field {} ({}: {})", at, excerpt(json(item.key()).dump()), what, list));
  }
}

// The handshake line as JSON, its version checked (1 or 2); `version` gets it.
json read_handshake(std::string_view line, const std::string& program, int& version) {
  const std::string who = "external program '" + program + "': ";
  json h;
  try {
    h = parse_json_limited(line, kMaxProtocolDepth, "a protocol message");
  } catch (const InputLimitError& limit) {
    throw std::runtime_error(who + "its handshake has " + limit.what() + ": " + excerpt(line));
  } catch (const json::exception&) {
    throw std::runtime_error(who + "its handshake is not JSON: " + excerpt(line));
  }
  const std::string where = who + "handshake";
  if (!h.is_object() || !h.contains("protocol") || !h["protocol"].is_number_integer())
    throw std::runtime_error(where + ": no \"protocol\" version number");
  // Compared as the number written (an unsigned 64-bit or a signed one), never narrowed to int.
  const json& v = h["protocol"];
  version = 0;
  for (int known = 1; known <= kProtocolVersion; ++known)
    if (v.is_number_unsigned() ? v.get<std::uint64_t>() == std::uint64_t(known) : v.get<std::int64_t>() == known) version = known;
  if (version == 0)
    throw std::runtime_error(
        fmt::format("{}: protocol version {}, this cullproof speaks versions 1 to {}", where, v.dump(), kProtocolVersion));
  const bool methods = h.contains("methods") && h["methods"].is_array() && !h["methods"].empty();
  const bool systems = version >= 2 && h.contains("systems") && h["systems"].is_array() && !h["systems"].empty();
  if (version == 1 && !methods) throw std::runtime_error(where + ": no \"methods\" array");
  if (!methods && !systems) throw std::runtime_error(where + ": neither \"methods\" nor \"systems\" offered");
  if (h.contains("methods") && !h["methods"].is_array()) throw std::runtime_error(where + ": \"methods\" is not an array");
  if (h.contains("systems") && !h["systems"].is_array()) throw std::runtime_error(where + ": \"systems\" is not an array");
  std::vector<const char*> fields{"protocol", "methods"};
  if (version >= 2) fields.push_back("systems");
  if (version >= 3) fields.push_back("encoding");
  known_fields(h, fields, fmt::format("a version-{} handshake's fields", version), where);
  if (const auto e = h.find("encoding"); e != h.end() && !(e->is_string() && (*e == "json" || *e == "binary")))
    throw std::runtime_error(where + ": \"encoding\" " + excerpt(e->dump()) + " is not \"json\" or \"binary\"");
  return h;
}

// "three_way" of a method: true or false, or an object naming kinds it takes, each true or false
// (the kinds not named are three-way).
void read_three_way(const json& m, MethodInfo& info, const std::string& at) {
  const auto t = m.find("three_way");
  if (t == m.end() || !t->is_object()) {
    info.three_way = bool_field(m, "three_way", true, at);
    return;
  }
  for (const auto& [kind, value] : t->items()) {
    const unsigned bit = kinds_of(json::array({kind}), at + ": \"three_way\"");
    if (!(info.volumes & bit))
      throw std::runtime_error(fmt::format("{}: \"three_way\" names {}, which is not among its \"volumes\"", at,
                                           excerpt(json(kind).dump())));
    if (!value.is_boolean())
      throw std::runtime_error(fmt::format("{}: \"three_way\" {} {} is not true or false", at, excerpt(json(kind).dump()),
                                           excerpt(value.dump())));
    if (!value.get<bool>()) info.two_way_kinds |= bit;
  }
  if (info.two_way_kinds == info.volumes) {  // two-way on every kind it takes
    info.three_way = false;
    info.two_way_kinds = 0;
  }
}

// What a method and a system describe alike: claim, tolerance, volumes, three_way (per kind for a
// method), touching, origin, description and source.
void read_description(const json& m, MethodInfo& info, const std::string& program, const std::string& at, bool per_kind) {
  info.origin = Origin::user;
  info.description = string_field(m, "description", "external program: " + program, at);
  info.source = string_field(m, "source", program, at);
  const std::string claim = string_field(m, "claim", "none", at);
  try {
    info.claim = claim_from_string(claim);
  } catch (const std::invalid_argument&) {
    std::string known;
    for (Claim c : {Claim::certified_conservative, Claim::certified_exact, Claim::conservative, Claim::exact, Claim::none})
      known += (known.empty() ? "" : ", ") + std::string(to_string(c));
    throw std::runtime_error(at + ": \"claim\" " + excerpt(json(claim).dump()) + " is not a claim (" + known + ")");
  }
  if (const auto t = m.find("tolerance"); t != m.end()) {
    if (!t->is_number() || !(t->get<double>() >= 0.0))
      throw std::runtime_error(at + ": \"tolerance\" " + excerpt(t->dump()) + " is not a number >= 0");
    info.tolerance = t->get<double>();
  }
  info.volumes = kinds_of(m.contains("volumes") ? m["volumes"] : json(), at);
  if (per_kind) read_three_way(m, info, at);
  else info.three_way = bool_field(m, "three_way", true, at);
  info.touching = string_field(m, "touching", std::string(), at);
  const std::string origin = string_field(m, "origin", "user", at);
  if (origin == "published") info.origin = Origin::published;
  else if (origin != "user")
    throw std::runtime_error(at + ": \"origin\" " + excerpt(json(origin).dump()) + " is not \"user\" or \"published\"");
}

// The entry's "name": present, a non-empty string, not offered before.
std::string name_of(const json& m, std::set<std::string>& names, const std::string& at) {
  if (!m.is_object() || !m.contains("name") || !m["name"].is_string() || m["name"].get<std::string>().empty())
    throw std::runtime_error(at + ": no \"name\"");
  const std::string name = m["name"].get<std::string>();
  if (!names.insert(name).second) throw std::runtime_error(at + ": \"name\" " + excerpt(json(name).dump()) + " is offered twice");
  return name;
}

}  // namespace

std::vector<OfferedMethod> parse_handshake(std::string_view line, const std::string& program) {
  int version = 0;
  const json h = read_handshake(line, program, version);
  const std::string where = "external program '" + program + "': handshake";
  std::vector<OfferedMethod> out;
  std::set<std::string> names;
  const json methods = h.contains("methods") ? h["methods"] : json::array();
  for (std::size_t i = 0; i < methods.size(); ++i) {
    const json& m = methods[i];
    const std::string at = fmt::format("{}, methods[{}]", where, i);
    OfferedMethod o;
    o.index = std::uint32_t(i);
    o.binary = h.value("encoding", std::string("json")) == "binary";
    MethodInfo& info = o.info;
    info.name = name_of(m, names, at);
    read_description(m, info, program, at, /*per_kind=*/true);
    known_fields(m,
                 {"name", "description", "source", "claim", "tolerance", "volumes", "three_way", "touching", "origin",
                  "stateful", "frustum", "depth"},
                 "a method's fields", at);
    info.stateful = bool_field(m, "stateful", false, at);
    const std::string frustum = string_field(m, "frustum", "planes", at);
    if (frustum == "matrix") o.wants_matrix = true;
    else if (frustum != "planes")
      throw std::runtime_error(at + ": \"frustum\" " + excerpt(json(frustum).dump()) + " is not \"planes\" or \"matrix\"");
    if (const auto d = m.find("depth"); d != m.end()) {
      if (!o.wants_matrix) throw std::runtime_error(at + ": \"depth\" is declared by a method with \"frustum\": \"matrix\" only");
      static const char* kNames[] = {"negative_one_to_one", "zero_to_one", "reversed_negative_one_to_one", "reversed_zero_to_one"};
      const std::string kinds = "negative_one_to_one, zero_to_one, reversed_negative_one_to_one, reversed_zero_to_one";
      if (!d->is_array() || d->empty())
        throw std::runtime_error(at + ": \"depth\" must be a non-empty array of depth conventions (" + kinds + ")");
      o.depths = 0;
      for (const json& x : *d) {
        unsigned bit = 0;
        for (unsigned k = 0; k < 4; ++k)
          if (x.is_string() && x.get<std::string>() == kNames[k]) bit = 1u << k;
        if (!bit) throw std::runtime_error(at + ": \"depth\" " + excerpt(x.dump()) + " is not a depth convention (" + kinds + ")");
        o.depths |= bit;
      }
    }
    out.push_back(std::move(o));
  }
  return out;
}

MethodDescription parse_method_description(std::string_view text, const std::string& where,
                                           const std::vector<std::string>& extra) {
  json m;
  try {
    m = parse_json_limited(text, kMaxProtocolDepth, "a method's description");
  } catch (const InputLimitError& limit) {
    throw std::runtime_error(where + ": " + limit.what());
  } catch (const json::exception&) {
    throw std::runtime_error(where + ": not JSON: " + excerpt(text));
  }
  if (!m.is_object()) throw std::runtime_error(where + ": not a JSON object: " + excerpt(text));
  MethodDescription out;
  std::set<std::string> names;
  out.info.name = name_of(m, names, where);
  read_description(m, out.info, where, where, /*per_kind=*/true);
  std::vector<const char*> known{"name", "description", "source", "claim", "tolerance", "volumes", "three_way", "touching", "origin"};
  for (const std::string& x : extra) known.push_back(x.c_str());
  known_fields(m, known, "a method's fields", where);
  for (const std::string& x : extra)
    if (const auto v = m.find(x); v != m.end()) {
      if (!v->is_string()) throw std::runtime_error(where + ": \"" + x + "\" " + excerpt(v->dump()) + " is not a string");
      out.strings.emplace_back(x, v->get<std::string>());
    }
  return out;
}

unsigned depth_convention_bit(const DepthConvention& d) noexcept {
  return (d.range == DepthRange::negative_one_to_one ? 1u : 2u) << (d.reversed_z ? 2 : 0);
}

std::vector<SystemInfo> parse_offered_systems(std::string_view line, const std::string& program) {
  int version = 0;
  const json h = read_handshake(line, program, version);
  const std::string where = "external program '" + program + "': handshake";
  std::vector<SystemInfo> out;
  if (version < 2 || !h.contains("systems")) return out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < h["systems"].size(); ++i) {
    const json& m = h["systems"][i];
    const std::string at = fmt::format("{}, systems[{}]", where, i);
    SystemInfo info;
    info.name = name_of(m, names, at);
    known_fields(m, {"name", "description", "source", "claim", "tolerance", "volumes", "three_way", "touching", "origin"},
                 "a system's fields", at);
    read_description(m, info, program, at, /*per_kind=*/false);
    out.push_back(std::move(info));
  }
  return out;
}

namespace {

// A line of an answer as JSON, its frame number checked and a reported error thrown.
json answer_json(std::string_view line, std::uint64_t frame, const std::string& what) {
  json a;
  try {
    a = parse_json_limited(line, kMaxProtocolDepth, "a protocol message");
  } catch (const InputLimitError& limit) {
    throw std::runtime_error(fmt::format("answered {} with {}: {}", what, limit.what(), excerpt(line)));
  } catch (const json::exception&) {
    throw std::runtime_error(fmt::format("answered {} with a line that is not JSON: {}", what, excerpt(line)));
  }
  if (!a.is_object() || !a.contains("frame") || !a["frame"].is_number_unsigned())
    throw std::runtime_error(fmt::format("answered {} without a \"frame\" number: {}", what, excerpt(line)));
  if (a["frame"].get<std::uint64_t>() != frame)
    throw std::runtime_error(fmt::format("answered frame {} when {} was asked (answers must come in order): {}",
                                         a["frame"].get<std::uint64_t>(), what, excerpt(line)));
  if (a.contains("error") && a["error"].is_string())
    throw std::runtime_error(fmt::format("reported an error for {}: {}", what, excerpt(a["error"].get<std::string>())));
  return a;
}

std::optional<double> ns_of(const json& a, const std::string& what) {
  const auto t = a.find("ns");
  if (t == a.end()) return std::nullopt;
  if (!t->is_number() || !(t->get<double>() >= 0.0))
    throw std::runtime_error(
        fmt::format("answered {} with \"ns\" {}, which is not a number of nanoseconds", what, excerpt(t->dump())));
  return t->get<double>();
}

}  // namespace

void parse_acknowledgement(std::string_view line, std::uint64_t frame, const char* key, const std::string& what) {
  const json a = answer_json(line, frame, what);
  const auto k = a.find(key);
  if (k == a.end() || !k->is_boolean() || !k->get<bool>())
    throw std::runtime_error(fmt::format("answered {} without \"{}\": true: {}", what, key, excerpt(line)));
}

VisibleReply parse_visible(std::string_view line, std::uint64_t frame, std::size_t objects, bool three_way,
                           const std::string& what) {
  const json a = answer_json(line, frame, what);
  const auto ids = a.find("visible");
  if (ids == a.end() || !ids->is_array())
    throw std::runtime_error(fmt::format("answered {} without a \"visible\" array: {}", what, excerpt(line)));
  if (ids->size() > objects)
    throw std::runtime_error(
        fmt::format("answered {} with {} visible id(s) for a scene of {} object(s): {}", what, ids->size(), objects, excerpt(line)));
  VisibleReply r;
  r.ns = ns_of(a, what);
  r.set.indices.reserve(ids->size());
  for (std::size_t i = 0; i < ids->size(); ++i) {
    const json& x = (*ids)[i];
    if (!x.is_number_unsigned() || x.get<std::uint64_t>() > 0xffffffffull)
      throw std::runtime_error(
          fmt::format("answered {} with visible[{}] = {}, which is not an id (0 to 2^32 - 1)", what, i, excerpt(x.dump())));
    r.set.indices.push_back(x.get<std::uint32_t>());
  }
  const auto v = a.find("verdicts");
  if (v == a.end()) {
    if (three_way)
      throw std::runtime_error(fmt::format("answered {} without \"verdicts\" (a three-way system gives one per id): {}", what,
                                           excerpt(line)));
    return r;
  }
  if (!v->is_array() || v->size() != ids->size())
    throw std::runtime_error(fmt::format("answered {} with {} verdict(s) for {} visible id(s): {}", what,
                                         v->is_array() ? v->size() : 0, ids->size(), excerpt(line)));
  r.set.verdicts.reserve(v->size());
  for (std::size_t i = 0; i < v->size(); ++i) {
    const json& x = (*v)[i];
    if (!(x.is_string() && (x == "intersecting" || (x == "inside" && three_way))))
      throw std::runtime_error(fmt::format("answered {} with verdicts[{}] = {}, which is not {} (a visible set lists the "
                                           "objects drawn)",
                                           what, i, excerpt(x.dump()), three_way ? "\"inside\" or \"intersecting\"" : "\"intersecting\" (a two-way system)"));
    r.set.verdicts.push_back(visibility_from_string(x.get<std::string>()));
  }
  return r;
}

Reply parse_answer(std::string_view line, std::uint64_t frame, std::size_t volumes, const std::string& what) {
  const json a = answer_json(line, frame, what);
  const auto v = a.find("verdicts");
  if (v == a.end() || !v->is_array())
    throw std::runtime_error(fmt::format("answered {} without a \"verdicts\" array: {}", what, excerpt(line)));
  if (v->size() != volumes)
    throw std::runtime_error(
        fmt::format("answered {} with {} verdict(s) for {} volume(s): {}", what, v->size(), volumes, excerpt(line)));
  Reply r;
  r.ns = ns_of(a, what);
  r.verdicts.reserve(volumes);
  for (std::size_t i = 0; i < volumes; ++i) {
    const json& x = (*v)[i];
    if (x.is_null()) {
      r.verdicts.push_back(std::nullopt);
    } else if (x.is_string() && (x == "outside" || x == "intersecting" || x == "inside")) {
      r.verdicts.push_back(visibility_from_string(x.get<std::string>()));
    } else {
      throw std::runtime_error(fmt::format("answered {} with verdict {} for volume {}, which is not \"outside\", "
                                           "\"intersecting\", \"inside\" or null",
                                           what, excerpt(x.dump()), i));
    }
  }
  return r;
}

// ---- binary frames and answers

namespace {

template <class T>
void put(std::string& out, T x) {
  char b[sizeof(T)];
  std::memcpy(b, &x, sizeof(T));
  out.append(b, sizeof(T));
}
template <class T>
T get(std::string_view bytes, std::size_t at) {
  T x;
  std::memcpy(&x, bytes.data() + at, sizeof(T));
  return x;
}
void put3(std::string& out, const glm::vec3& v) {
  for (int i = 0; i < 3; ++i) put(out, v[i]);
}
static_assert(sizeof(float) == 4 && sizeof(double) == 8, "the binary encoding is of 32- and 64-bit IEEE floats");
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the binary encoding is little-endian, as the machine is");

// The kind byte of a binary frame: 0 point, 1 sphere, 2 aabb, 3 obb (Volume's alternatives).
std::uint8_t kind_byte(const Volume& v) { return std::uint8_t(v.index()); }

}  // namespace

std::size_t binary_answer_size(const std::vector<AskedFrame>& frames) noexcept {
  std::size_t n = kBinaryAnswerHeader;
  for (const AskedFrame& f : frames) n += kBinaryAnswerFrameHeader + f.volumes;
  return n;
}

void append_binary_frame(std::string& out, std::uint64_t frame, std::uint32_t method, bool reset, const CaseFrustum& f,
                         const Volume* volumes, std::size_t n) {
  const std::uint8_t kind = n ? kind_byte(volumes[0]) : 0;
  put(out, frame);
  put(out, method);
  put(out, std::uint32_t(n));
  put(out, kind);
  put(out, std::uint8_t((reset ? 1 : 0) | (f.matrix ? 2 : 0)));
  put(out, std::uint8_t(f.depth.range == DepthRange::zero_to_one ? 1 : 0));
  put(out, std::uint8_t(f.depth.reversed_z ? 1 : 0));
  for (int k = 0; k < kPlaneCount; ++k) {
    put3(out, f.planes[k].n);
    put(out, f.planes[k].d);
  }
  if (f.matrix)
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) put(out, (*f.matrix)[c][r]);
  for (std::size_t i = 0; i < n; ++i) {
    if (kind_byte(volumes[i]) != kind) throw std::invalid_argument("a binary frame holds volumes of one kind");
    std::visit(
        [&](const auto& x) {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, Point>) put3(out, x);
          else if constexpr (std::is_same_v<T, Sphere>) put3(out, x.center), put(out, x.radius);
          else if constexpr (std::is_same_v<T, Aabb>) put3(out, x.min), put3(out, x.max);
          else put3(out, x.center), put3(out, x.axes[0]), put3(out, x.axes[1]), put3(out, x.axes[2]), put3(out, x.half);
        },
        volumes[i]);
  }
}

void put_binary_header(std::string& message, std::size_t frames) {
  const std::uint32_t count = std::uint32_t(frames), body = std::uint32_t(message.size() - kBinaryFramesHeader);
  std::memcpy(message.data(), kBinaryFramesMagic, 4);
  std::memcpy(message.data() + 4, &count, 4);
  std::memcpy(message.data() + 8, &body, 4);
}

void check_binary_answer_header(std::string_view bytes, const std::vector<AskedFrame>& frames, const std::string& what) {
  if (bytes.size() < kBinaryAnswerHeader)
    throw std::runtime_error(fmt::format("answered {} with {} byte(s), shorter than a binary answer's header ({})", what,
                                         bytes.size(), kBinaryAnswerHeader));
  if (bytes.substr(0, 4) != std::string_view(kBinaryAnswerMagic, 4))
    throw std::runtime_error(fmt::format("answered {} with a binary answer that does not begin with \"CP3A\": {}", what,
                                         excerpt(bytes.substr(0, 4))));
  if (get<std::uint32_t>(bytes, 4) != frames.size())
    throw std::runtime_error(fmt::format("answered {} with {} frame(s) where {} were asked", what,
                                         get<std::uint32_t>(bytes, 4), frames.size()));
}

std::vector<Reply> parse_binary_answer(std::string_view bytes, const std::vector<AskedFrame>& frames, const std::string& what) {
  check_binary_answer_header(bytes, frames, what);
  const std::size_t size = binary_answer_size(frames);
  if (bytes.size() != size)
    throw std::runtime_error(fmt::format("answered {} with {} byte(s) where the binary answer has {}", what, bytes.size(), size));
  std::vector<Reply> out(frames.size());
  std::size_t at = kBinaryAnswerHeader;
  // A frame of a message of several is named with the message; a message of one frame names it.
  auto frame_of = [&](std::uint64_t id) { return frames.size() == 1 ? what : fmt::format("frame {} of {}", id, what); };
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const std::uint64_t id = get<std::uint64_t>(bytes, at);
    const std::uint32_t n = get<std::uint32_t>(bytes, at + 8);
    const double ns = get<double>(bytes, at + 12);
    if (id != frames[j].frame)
      throw std::runtime_error(fmt::format("answered frame {} when frame {} of {} was asked (answers come in order)", id,
                                           frames[j].frame, what));
    // The size matched, so a count that differs here shifts another frame's: named as this one's.
    if (n != frames[j].volumes)
      throw std::runtime_error(fmt::format("answered {} with {} verdict(s) for {} volume(s)", frame_of(id), n, frames[j].volumes));
    if (!(ns >= 0.0) && ns != -1.0)
      throw std::runtime_error(
          fmt::format("answered {} with ns {}, which is not a number of nanoseconds (or -1)", frame_of(id), ns));
    Reply& r = out[j];
    if (ns >= 0.0) r.ns = ns;
    at += kBinaryAnswerFrameHeader;
    r.verdicts.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint8_t v = std::uint8_t(bytes[at + i]);
      if (v == kBinaryNotApplying) continue;
      if (v > 2)
        throw std::runtime_error(fmt::format("answered {} with verdict byte {} for volume {}, which is not 0 (outside), 1 "
                                             "(intersecting), 2 (inside) or 255 (does not apply)",
                                             frame_of(id), v, i));
      r.verdicts[i] = Visibility(v);
    }
    at += n;
  }
  return out;
}

void refuse_json_instead_of_binary(std::string_view line, std::uint64_t first_frame, const std::string& what) {
  answer_json(line, first_frame, what);  // throws the error the program reports
  throw std::runtime_error(
      fmt::format("answered {} with a JSON line where a binary answer (\"CP3A\") was due: {}", what, excerpt(line)));
}

}  // namespace cullproof::protocol

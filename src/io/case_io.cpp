// Case files: reading with exact float rounding and file/line/field errors, and writing.
//
// nlohmann::json parses the text through its SAX interface so that (1) every number keeps its
// original text, which is rounded once to float (a DOM would round to double first, and
// decimal -> double -> float can double-round), and (2) every value keeps the line it stood on.
// The same interface enforces kMaxCaseDepth as the parser goes.
#include "cullproof/io/case_io.hpp"

#include "cullproof/io/files.hpp"
#include "cullproof/io/limits.hpp"
#include "line_counting.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <system_error>

namespace cullproof {

using nlohmann::json;
using io_detail::CountingIterator;
using io_detail::LineState;

CaseError::CaseError(std::string file, int line, std::string field, const std::string& problem)
    : std::runtime_error(printable_text(file) + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " +
                         (field.empty() ? std::string() : "field '" + printable_text(field) + "': ") +
                         printable_text(problem)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}


// ---------------------------------------------------------------------------------------------
// Numbers

namespace {

bool is_hex_digit(char ch) { return std::isxdigit(static_cast<unsigned char>(ch)) != 0; }

// Rounds a value parsed by strtof (correctly rounded in glibc) when std::from_chars reports a
// range error: underflow rounds to zero or a subnormal as docs/semantics.md asks; overflow is an error.
float strtof_checked(const std::string& s) {
  errno = 0;
  char* end = nullptr;
  const float v = std::strtof(s.c_str(), &end);
  if (end != s.c_str() + s.size()) throw std::invalid_argument("is not a number: \"" + printable_text(s) + "\"");
  if (std::isinf(v)) throw std::invalid_argument("\"" + printable_text(s) + "\" overflows float");
  return v;
}

}  // namespace

float parse_case_float(std::string_view text, bool is_string) {
  std::string s(text);
  if (!is_string) {
    float v = 0.0f;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec == std::errc() && r.ptr == s.data() + s.size()) return v;
    if (r.ec == std::errc::result_out_of_range) return strtof_checked(s);
    throw std::invalid_argument("is not a number: \"" + printable_text(s) + "\"");
  }
  // C99 hexadecimal float: [+-]0x<hex digits>[.<hex digits>][p[+-]<decimal digits>]
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  const bool prefix = i + 1 < s.size() && s[i] == '0' && (s[i + 1] == 'x' || s[i + 1] == 'X');
  bool digits = false;
  std::size_t j = i + 2;
  if (prefix) {
    while (j < s.size() && is_hex_digit(s[j])) { ++j; digits = true; }
    if (j < s.size() && s[j] == '.') {
      ++j;
      while (j < s.size() && is_hex_digit(s[j])) { ++j; digits = true; }
    }
    if (j < s.size() && (s[j] == 'p' || s[j] == 'P')) {
      ++j;
      if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
      const std::size_t k = j;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
      if (j == k) digits = false;
    }
  }
  if (!prefix || !digits || j != s.size())
    throw std::invalid_argument("string \"" + printable_text(s) +
                                "\" is not a C99 hexadecimal float (e.g. \"0x1.8p+3\")");
  return strtof_checked(s);
}

std::string format_float(float x) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, r.ptr);
}

std::string format_hex_float(float x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%a", double(x));
  return buf;
}

// ---------------------------------------------------------------------------------------------
// SAX reader: a DOM plus the line and raw text of every value, keyed by a readable path.

namespace {

struct ValueMeta {
  int line = 0;
  std::string raw;  // number text, for numbers
};

// Values are recorded in Reader::meta only while their path is at most this long: every field the
// case format reads has a short path (the longest, "volume.obb.axes[2][2]", has 21 characters),
// and a path per value of a free field under long keys or deep nesting would cost the product of
// the path's length and the number of values (a 1 MiB case could ask for terabytes). An
// unrecorded value's line is its nearest recorded ancestor's.
constexpr std::size_t kRecordedPathChars = 64;

class Reader : public nlohmann::json_sax<json> {
 public:
  Reader(std::string source, LineState* st) : source_(std::move(source)), st_(st) {}

  json root;
  std::map<std::string, ValueMeta> meta;  // path -> line and raw number text

  bool null() override { return put(json(nullptr), {}); }
  bool boolean(bool v) override { return put(json(v), {}); }
  bool number_integer(number_integer_t v) override {
    // "-0" arrives as the integer 0: its sign is read from the text, so that it is -0.0f as the
    // case format says (and as format_float writes it), and a free field keeps it as -0.0.
    if (v == 0 && negative_zero()) return put(json(-0.0), "-0");
    return put(json(v), std::to_string(v));
  }
  bool number_unsigned(number_unsigned_t v) override { return put(json(v), std::to_string(v)); }
  bool number_float(number_float_t v, const string_t& s) override { return put(json(v), s); }
  bool string(string_t& v) override { return put(json(v), {}); }
  bool binary(binary_t&) override { return put(json(nullptr), {}); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool end_object() override { stack_.pop_back(); return true; }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { stack_.pop_back(); return true; }
  // Whether the integer token just read is "-0". nlohmann's lexer reads one character past a
  // number (its end), except at the end of the text; the token is "0" or "-0" (JSON allows no
  // other spelling of an integer zero).
  bool negative_zero() const {
    const char* q = st_->next;
    if (q == nullptr || q <= st_->begin) return false;
    if (q[-1] != '0') --q;  // the character that ended the number
    return q - st_->begin >= 2 && q[-1] == '0' && q[-2] == '-';
  }
  bool key(string_t& k) override {
    Frame& f = stack_.back();
    if (f.node->contains(k)) throw CaseError(source_, st_->token_line, join(full_path(), k), "duplicate field");
    key_ = k;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception& ex) override {
    std::string msg = ex.what();
    // nlohmann's messages start with "[json.exception.parse_error.101] parse error at line L, column C: ";
    // keep the part after the bracket tag, and name our own line.
    const auto pos = msg.find("] ");
    if (pos != std::string::npos) msg = msg.substr(pos + 2);
    // "parse error at line L, column C: ..." counts lines from the start of this case, not of the
    // file: keep the column beside the file's line.
    const std::string at = "parse error at line ";
    const auto column = msg.find(", column ");
    if (msg.compare(0, at.size(), at) == 0 && column != std::string::npos) msg = msg.substr(column + 2);
    throw CaseError(source_, st_->line, "", "invalid JSON: " + msg);
  }

 private:
  struct Frame {
    json* node;
    std::string step;  // the key or "[i]" that leads to it from its parent ("" at the root)
    bool recorded;     // its path is within kRecordedPathChars (then `path` is it)
    std::string path;
  };
  std::vector<Frame> stack_;
  std::string key_;
  std::string source_;
  LineState* st_;

  static std::string join(const std::string& base, const std::string& k) {
    return base.empty() ? k : base + "." + k;
  }

  // The path of the open container, for messages (any length).
  std::string full_path() const {
    std::string p;
    for (std::size_t i = 1; i < stack_.size(); ++i)
      p = stack_[i].step[0] == '[' ? p + stack_[i].step : join(p, stack_[i].step);
    return p;
  }

  struct Placed {
    json* node;
    std::string step;  // containers only
    bool recorded;
    std::string path;  // when recorded
  };
  // Adds a value at the current position.
  Placed place(json v, bool container) {
    if (stack_.empty()) {
      root = std::move(v);
      return {&root, {}, true, {}};
    }
    Frame& f = stack_.back();
    const bool in_object = f.node->is_object();
    const std::string index = in_object ? std::string() : "[" + std::to_string(f.node->size()) + "]";
    const std::size_t length =
        in_object ? f.path.size() + (f.path.empty() ? 0 : 1) + key_.size() : f.path.size() + index.size();
    Placed p{nullptr, {}, f.recorded && length <= kRecordedPathChars, {}};
    if (p.recorded) p.path = in_object ? join(f.path, key_) : f.path + index;
    if (container) p.step = in_object ? key_ : index;
    if (in_object) {
      json& slot = (*f.node)[key_];
      slot = std::move(v);
      p.node = &slot;
    } else {
      f.node->push_back(std::move(v));
      p.node = &f.node->back();
    }
    return p;
  }
  bool put(json v, std::string raw) {
    const Placed p = place(std::move(v), false);
    if (p.recorded) meta[p.path] = ValueMeta{st_->token_line, std::move(raw)};
    return true;
  }
  bool open(json v) {
    if (stack_.size() >= std::size_t(kMaxCaseDepth))
      throw CaseError(source_, st_->token_line, "",
                      "arrays and objects nested deeper than " + std::to_string(kMaxCaseDepth) +
                          ", the limit for one case");
    Placed p = place(std::move(v), true);
    if (p.recorded) meta[p.path] = ValueMeta{st_->token_line, {}};
    stack_.push_back(Frame{p.node, std::move(p.step), p.recorded, std::move(p.path)});
    return true;
  }
};

class CaseParser {
 public:
  CaseParser(const Reader& r, std::string source) : r_(r), source_(std::move(source)) {}

  Case parse() {
    const json& root = r_.root;
    if (!root.is_object()) fail("", "a case must be a JSON object");
    Case c;
    c.id = get_string(root, "", "id");
    c.frustum = parse_frustum(need(root, "", "frustum"), "frustum");
    c.volume = parse_volume(need(root, "", "volume"), "volume");
    if (root.contains("truth")) {
      const std::string t = get_string(root, "", "truth");
      if (t != "outside" && t != "intersecting" && t != "inside")
        fail("truth", "unknown visibility \"" + t + "\" (expected outside, intersecting or inside)");
      c.truth = visibility_from_string(t);
    }
    if (root.contains("note")) c.note = get_string(root, "", "note");
    for (auto it = root.begin(); it != root.end(); ++it) {
      const std::string& k = it.key();
      if (k != "id" && k != "frustum" && k != "volume" && k != "truth" && k != "note")
        c.extra[k] = it.value();
    }
    return c;
  }

 private:
  const Reader& r_;
  std::string source_;

  int line_of(const std::string& path) const {
    // The value's own line, or the nearest enclosing value's line.
    std::string p = path;
    while (true) {
      auto it = r_.meta.find(p);
      if (it != r_.meta.end()) return it->second.line;
      if (p.empty()) return 1;
      const auto cut = p.find_last_of(".[");
      p = cut == std::string::npos ? std::string() : p.substr(0, cut);
    }
  }
  [[noreturn]] void fail(const std::string& path, const std::string& problem) const {
    throw CaseError(source_, line_of(path), path, problem);
  }
  static std::string join(const std::string& base, const std::string& k) {
    return base.empty() ? k : base + "." + k;
  }
  static std::string idx(const std::string& base, std::size_t i) {
    return base + "[" + std::to_string(i) + "]";
  }
  const json& need(const json& obj, const std::string& path, const char* key) const {
    if (!obj.is_object()) fail(path, "must be an object");
    auto it = obj.find(key);
    if (it == obj.end()) fail(join(path, key), "missing field");
    return *it;
  }
  std::string get_string(const json& obj, const std::string& path, const char* key) const {
    const json& v = need(obj, path, key);
    if (!v.is_string()) fail(join(path, key), "must be a string");
    return v.get<std::string>();
  }
  float number(const json& v, const std::string& path) const {
    if (!v.is_number() && !v.is_string())
      fail(path, "must be a number or a hexadecimal-float string");
    try {
      if (v.is_string()) return parse_case_float(v.get<std::string>(), true);
      auto it = r_.meta.find(path);
      const std::string raw = it != r_.meta.end() && !it->second.raw.empty() ? it->second.raw : v.dump();
      return parse_case_float(raw, false);
    } catch (const std::invalid_argument& e) {
      fail(path, e.what());
    }
  }
  const json& array_of(const json& v, const std::string& path, std::size_t n) const {
    if (!v.is_array()) fail(path, "must be an array of " + std::to_string(n) + " numbers");
    if (v.size() != n)
      fail(path, "must have " + std::to_string(n) + " elements, has " + std::to_string(v.size()));
    return v;
  }
  glm::vec3 vec3(const json& v, const std::string& path) const {
    array_of(v, path, 3);
    glm::vec3 out;
    for (std::size_t i = 0; i < 3; ++i) out[int(i)] = number(v[i], idx(path, i));
    return out;
  }

  CaseFrustum parse_frustum(const json& f, const std::string& path) const {
    if (!f.is_object()) fail(path, "must be an object with \"planes\" or \"matrix\"");
    const bool has_planes = f.contains("planes"), has_matrix = f.contains("matrix");
    if (has_planes == has_matrix)
      fail(path, "must have exactly one of \"planes\" and \"matrix\"");
    if (has_planes) {
      const std::string pp = join(path, "planes");
      const json& planes = f["planes"];
      if (!planes.is_array() || planes.size() != 6)
        fail(pp, "must be an array of 6 planes [a,b,c,d] (left, right, bottom, top, near, far), has " +
                     (planes.is_array() ? std::to_string(planes.size()) : std::string("no array")));
      Frustum fr;
      for (std::size_t i = 0; i < 6; ++i) {
        const std::string ip = idx(pp, i);
        array_of(planes[i], ip, 4);
        float abcd[4];
        for (std::size_t k = 0; k < 4; ++k) abcd[k] = number(planes[i][k], idx(ip, k));
        fr[int(i)] = Plane{glm::vec3(abcd[0], abcd[1], abcd[2]), abcd[3]};
      }
      return frustum_spec(fr);
    }
    const std::string mp = join(path, "matrix");
    array_of(f["matrix"], mp, 16);
    glm::mat4 m;
    for (std::size_t i = 0; i < 16; ++i) m[int(i / 4)][int(i % 4)] = number(f["matrix"][i], idx(mp, i));
    DepthConvention depth;
    const std::string d = get_string(f, path, "depth");
    if (d == "negative_one_to_one") depth.range = DepthRange::negative_one_to_one;
    else if (d == "zero_to_one") depth.range = DepthRange::zero_to_one;
    else fail(join(path, "depth"), "must be \"negative_one_to_one\" or \"zero_to_one\", got \"" + d + "\"");
    if (f.contains("reversed_z")) {
      if (!f["reversed_z"].is_boolean()) fail(join(path, "reversed_z"), "must be true or false");
      depth.reversed_z = f["reversed_z"].get<bool>();
    }
    return frustum_spec(m, depth);
  }

  Volume parse_volume(const json& v, const std::string& path) const {
    if (!v.is_object() || v.size() != 1)
      fail(path, "must be an object with exactly one of \"aabb\", \"obb\", \"sphere\", \"point\"");
    const std::string kind = v.begin().key();
    const std::string kp = join(path, kind);
    const json& body = v.begin().value();
    if (kind == "point") return vec3(body, kp);
    if (kind == "aabb") {
      Aabb b{vec3(need(body, kp, "min"), join(kp, "min")), vec3(need(body, kp, "max"), join(kp, "max"))};
      for (int i = 0; i < 3; ++i)
        if (b.min[i] > b.max[i])
          fail(join(kp, "min") + "[" + std::to_string(i) + "]",
               "min > max (" + format_float(b.min[i]) + " > " + format_float(b.max[i]) + ")");
      return b;
    }
    if (kind == "sphere") {
      Sphere s{vec3(need(body, kp, "center"), join(kp, "center")), number(need(body, kp, "radius"), join(kp, "radius"))};
      if (s.radius < 0.0f) fail(join(kp, "radius"), "is negative (" + format_float(s.radius) + ")");
      return s;
    }
    if (kind == "obb") {
      Obb b;
      b.center = vec3(need(body, kp, "center"), join(kp, "center"));
      const std::string ap = join(kp, "axes");
      const json& axes = need(body, kp, "axes");
      if (!axes.is_array() || axes.size() != 3)
        fail(ap, "must be an array of 3 axes [[x,y,z],[x,y,z],[x,y,z]]");
      for (std::size_t i = 0; i < 3; ++i) {
        b.axes[int(i)] = vec3(axes[i], idx(ap, i));
        if (b.axes[int(i)] == glm::vec3(0.0f)) fail(idx(ap, i), "is a zero-length axis");
      }
      b.half = vec3(need(body, kp, "half"), join(kp, "half"));
      for (std::size_t i = 0; i < 3; ++i)
        if (b.half[int(i)] < 0.0f)
          fail(idx(join(kp, "half"), i), "is negative (" + format_float(b.half[int(i)]) + ")");
      return b;
    }
    fail(path, "unknown volume kind \"" + kind + "\" (expected aabb, obb, sphere or point)");
  }
};

// read_file_limited for the case readers: its limit errors as CaseErrors.
std::string read_case_text(const std::filesystem::path& file, std::uintmax_t max_bytes, std::string_view what) {
  try {
    return read_file_limited(file, max_bytes, what);
  } catch (const InputLimitError& e) {
    throw CaseError(file.string(), e.line(), "", e.what());
  }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Reading cases

Case parse_case(std::string_view text, std::string_view source, int first_line) {
  if (text.size() > kMaxCaseBytes)
    throw CaseError(std::string(source), first_line, "",
                    "a case of " + std::to_string(text.size()) + " bytes, over the limit of " +
                        byte_count_text(kMaxCaseBytes) + " for one case (a line of JSON Lines, or a one-case file)");
  LineState st;
  st.line = st.token_line = first_line;
  st.begin = st.next = text.data();
  Reader reader{std::string(source), &st};
  CountingIterator b{text.data(), &st}, e{text.data() + text.size(), &st};
  json::sax_parse(b, e, &reader);
  Case c = CaseParser(reader, std::string(source)).parse();
  c.line = first_line;
  return c;
}

Case read_case_file(const std::filesystem::path& file) {
  const std::string text = read_case_text(file, kMaxCaseBytes, "a one-case file");
  return parse_case(text, file.string(), 1);
}

std::vector<Case> parse_cases_jsonl(std::string_view text, std::string_view source) {
  if (text.size() > kMaxCaseFileBytes)
    throw CaseError(std::string(source), 0, "",
                    "a text of " + std::to_string(text.size()) + " bytes, over the limit of " +
                        byte_count_text(kMaxCaseFileBytes) + " for a JSON Lines case file");
  std::vector<Case> out;
  std::size_t pos = 0;
  int line = 1;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view l(text.data() + pos, end - pos);
    bool blank = true;
    for (char ch : l) blank = blank && std::isspace(static_cast<unsigned char>(ch));
    if (!blank) out.push_back(parse_case(l, source, line));
    pos = end + 1;
    ++line;
  }
  return out;
}

std::vector<Case> read_cases_jsonl(const std::filesystem::path& file) {
  return parse_cases_jsonl(read_case_text(file, kMaxCaseFileBytes, "a JSON Lines case file"), file.string());
}

std::vector<Case> read_cases(const std::filesystem::path& file) {
  if (file.extension() == ".jsonl") return read_cases_jsonl(file);
  std::vector<Case> out;
  out.push_back(read_case_file(file));
  return out;
}

// ---------------------------------------------------------------------------------------------
// Writing

namespace {

std::string vec_text(const glm::vec3& v) {
  return "[" + format_float(v.x) + ", " + format_float(v.y) + ", " + format_float(v.z) + "]";
}

}  // namespace

std::string format_volume(const Volume& v) {
  struct V {
    std::string operator()(const Point& p) const { return "{\"point\": " + vec_text(p) + "}"; }
    std::string operator()(const Sphere& s) const {
      return "{\"sphere\": {\"center\": " + vec_text(s.center) + ", \"radius\": " + format_float(s.radius) + "}}";
    }
    std::string operator()(const Aabb& b) const {
      return "{\"aabb\": {\"min\": " + vec_text(b.min) + ", \"max\": " + vec_text(b.max) + "}}";
    }
    std::string operator()(const Obb& b) const {
      return "{\"obb\": {\"center\": " + vec_text(b.center) + ", \"axes\": [" + vec_text(b.axes[0]) + ", " +
             vec_text(b.axes[1]) + ", " + vec_text(b.axes[2]) + "], \"half\": " + vec_text(b.half) + "}}";
    }
  };
  return std::visit(V{}, v);
}

std::string format_frustum(const CaseFrustum& f) {
  std::string s;
  if (f.matrix) {
    s = "{\"matrix\": [";
    for (int i = 0; i < 16; ++i) s += (i ? ", " : "") + format_float((*f.matrix)[i / 4][i % 4]);
    s += std::string("], \"depth\": \"") +
         (f.depth.range == DepthRange::negative_one_to_one ? "negative_one_to_one" : "zero_to_one") +
         "\", \"reversed_z\": " + (f.depth.reversed_z ? "true" : "false") + "}";
    return s;
  }
  s = "{\"planes\": [";
  for (int i = 0; i < 6; ++i) {
    const Plane& p = f.planes[i];
    s += (i ? ", [" : "[") + format_float(p.n.x) + ", " + format_float(p.n.y) + ", " +
         format_float(p.n.z) + ", " + format_float(p.d) + "]";
  }
  return s + "]}";
}

std::string format_case(const Case& c, bool pretty) {
  const char* sep = pretty ? ",\n  " : ", ";
  std::string s = pretty ? "{\n  " : "{";
  s += "\"id\": " + json(c.id).dump();
  s += sep + std::string("\"frustum\": ") + format_frustum(c.frustum);
  s += sep + std::string("\"volume\": ") + format_volume(c.volume);
  if (c.truth) s += sep + std::string("\"truth\": \"") + std::string(to_string(*c.truth)) + "\"";
  if (!c.note.empty()) s += sep + std::string("\"note\": ") + json(c.note).dump();
  if (c.extra.is_object())
    for (auto it = c.extra.begin(); it != c.extra.end(); ++it)
      s += sep + json(it.key()).dump() + ": " + it.value().dump();
  s += pretty ? "\n}\n" : "}";
  return s;
}

void write_case_file(const std::filesystem::path& file, const Case& c, bool overwrite) {
  write_file_atomic(file, format_case(c, true), overwrite);
}

}  // namespace cullproof

// Arithmetic a device may use, emulated on the device at hand: the shader's SPIR-V rewritten so
// that it computes as such a device would (gpu.hpp: Arithmetic; docs/gpu.md).
//
// Every instruction the rewriting adds is decorated NoContraction, so that the driver's compiler
// may not rearrange it (an emulation of a fused multiply-add by an error-free sum would not
// survive "(a + b) - a is b").
#define SPV_ENABLE_UTILITY_CODE
#include "vulkan.hpp"

#include <fmt/format.h>
#include <glslang/SPIRV/GLSL.std.450.h>
#include <glslang/SPIRV/spirv.hpp>
#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace cullproof::gpu {

double round_to_half(double x, int direction) {
  if (!std::isfinite(x) || x == 0.0) return x;
  int e = 0;
  std::frexp(x, &e);                          // |x| = m 2^e, m in [0.5, 1)
  const int quantum = std::max(e - 11, -24);  // a half's spacing in x's binade (subnormal halves: 2^-24)
  const double q = std::ldexp(x, -quantum);   // exact: a power of two
  const double r = std::ldexp(direction == 0 ? std::nearbyint(q) : direction < 0 ? std::floor(q) : std::ceil(q), quantum);
  if (r > 65504.0) return direction < 0 ? 65504.0 : INFINITY;  // to nearest: x >= 65520, halfway to 2^16 or past it
  if (r < -65504.0) return direction > 0 ? -65504.0 : -INFINITY;
  return r;
}

float round_to_half(float x) { return float(round_to_half(double(x), 0)); }

Volume stored_volume(const Volume& v, HalfStorage how) {
  if (how == HalfStorage::none) return v;
  const auto nearest3 = [](const glm::vec3& p) { return glm::vec3(round_to_half(p.x), round_to_half(p.y), round_to_half(p.z)); };
  if (how == HalfStorage::nearest) {
    if (const auto* p = std::get_if<Point>(&v)) return Volume(nearest3(*p));
    if (const auto* s = std::get_if<Sphere>(&v)) return Volume(Sphere{nearest3(s->center), round_to_half(s->radius)});
    if (const auto* b = std::get_if<Aabb>(&v)) return Volume(Aabb{nearest3(b->min), nearest3(b->max)});
    const Obb& o = std::get<Obb>(v);
    return Volume(Obb{nearest3(o.center), glm::mat3(nearest3(o.axes[0]), nearest3(o.axes[1]), nearest3(o.axes[2])),
                      nearest3(o.half)});
  }
  if (std::holds_alternative<Point>(v))
    throw std::invalid_argument("a point stored half-outward: a point cannot grow to contain its rounding");
  // The centre and axes to the nearest finite half; what grows, rounded up after growing by what
  // they moved, computed in double and enlarged by 2^-40 relatively, which covers the double
  // arithmetic's own rounding (a few 2^-53) many times over.
  const auto finite = [](float x) {
    const double r = round_to_half(double(x), 0);
    return float(std::isinf(r) && std::isfinite(x) ? std::copysign(65504.0, r) : r);
  };
  const auto finite3 = [&](const glm::vec3& p) { return glm::vec3(finite(p.x), finite(p.y), finite(p.z)); };
  const auto moved = [](const glm::vec3& a, const glm::vec3& b) { return glm::length(glm::dvec3(a) - glm::dvec3(b)); };
  // A radius or half extent grown by `growth` (NaN: an infinite coordinate moved), rounded up;
  // exact when nothing moved.
  const auto up = [](float x, double growth) {
    if (growth == 0.0) return float(round_to_half(double(x), +1));
    const double grown = (double(x) + growth) * (1.0 + 0x1p-40);
    return float(grown >= 0.0 ? round_to_half(grown, +1) : INFINITY);
  };
  if (const auto* s = std::get_if<Sphere>(&v)) {
    const glm::vec3 c = finite3(s->center);
    return Volume(Sphere{c, up(s->radius, moved(s->center, c))});
  }
  if (const auto* b = std::get_if<Aabb>(&v)) {
    glm::vec3 lo, hi;
    for (int i = 0; i < 3; ++i) {
      lo[i] = float(round_to_half(double(b->min[i]), -1));
      hi[i] = float(round_to_half(double(b->max[i]), +1));
    }
    return Volume(Aabb{lo, hi});
  }
  // An OBB: its points c + U t (|t_k| <= h_k) are c' + U' (t + s) with U' s = (c - c') + (U - U') t,
  // so |s_k| <= |s| <= ||U'^-1|| d, d = |c - c'| + sum_k h_k |u_k - u'_k|; ||U'^-1|| bounded by its
  // Frobenius norm, the adjugate's over the determinant (U' exact in double).
  const Obb& o = std::get<Obb>(v);
  Obb s{finite3(o.center), glm::mat3(finite3(o.axes[0]), finite3(o.axes[1]), finite3(o.axes[2])), glm::vec3(0.0f)};
  double d = moved(o.center, s.center);
  for (int k = 0; k < 3; ++k) d += double(o.half[k]) * moved(o.axes[k], s.axes[k]);
  double grow = 0.0;
  if (d != 0.0) {
    const glm::dvec3 u0(s.axes[0]), u1(s.axes[1]), u2(s.axes[2]);
    const double det = glm::dot(u0, glm::cross(u1, u2));
    const double adjugate = std::sqrt(glm::dot(glm::cross(u1, u2), glm::cross(u1, u2)) +
                                      glm::dot(glm::cross(u2, u0), glm::cross(u2, u0)) +
                                      glm::dot(glm::cross(u0, u1), glm::cross(u0, u1)));
    grow = det != 0.0 ? adjugate / std::fabs(det) * d : INFINITY;
  }
  for (int k = 0; k < 3; ++k) s.half[k] = up(o.half[k], grow);
  return Volume(s);
}

std::string to_string(const Arithmetic& a) {
  std::string s;
  const auto add = [&](const char* w) { s += (s.empty() ? "" : "+") + std::string(w); };
  if (a.contract) add("contract");
  if (a.flush) add("flush");
  if (a.bounds < 0) add("bounds-low");
  if (a.bounds > 0) add("bounds-high");
  if (a.relaxed) add("relaxed");
  if (a.half_storage == HalfStorage::nearest) add("half");
  if (a.half_storage == HalfStorage::outward) add("half-outward");
  return s.empty() ? "device" : s;
}

Arithmetic parse_arithmetic(const std::string& text) {
  Arithmetic a;
  if (text == "device") return a;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t end = std::min(text.find('+', at), text.size());
    const std::string w = text.substr(at, end - at);
    if (w == "contract") a.contract = true;
    else if (w == "flush") a.flush = true;
    else if (w == "bounds-low" && a.bounds <= 0) a.bounds = -1;
    else if (w == "bounds-high" && a.bounds >= 0) a.bounds = +1;
    else if (w == "relaxed") a.relaxed = true;
    else if (w == "half" && a.half_storage != HalfStorage::outward) a.half_storage = HalfStorage::nearest;
    else if (w == "half-outward" && a.half_storage != HalfStorage::nearest) a.half_storage = HalfStorage::outward;
    else
      throw std::invalid_argument(fmt::format(
          "arithmetic '{}': '{}' is not a variant, or contradicts one before it (device, or any of contract, flush, "
          "bounds-low or bounds-high, relaxed, half or half-outward joined by '+')",
          text, w));
    at = end + 1;
  }
  return a;
}

std::vector<Arithmetic> all_arithmetic() {
  std::vector<Arithmetic> v(9);
  v[1].contract = true;
  v[2].flush = true;
  v[3].bounds = -1;
  v[4].bounds = +1;
  v[5].relaxed = true;
  v[6].half_storage = HalfStorage::nearest;
  v[7].half_storage = HalfStorage::outward;
  v[8].contract = v[8].flush = true;
  v[8].bounds = -1;
  return v;
}

namespace {

struct Inst {
  spv::Op op;
  std::vector<std::uint32_t> w;  // the words after the first
};

// The instructions whose 32-bit float operands a flushing device flushes: arithmetic, comparisons,
// conversions and the GLSL extended instructions.
bool is_float_instruction(spv::Op op) {
  switch (op) {
    case spv::OpFNegate: case spv::OpFAdd: case spv::OpFSub: case spv::OpFMul: case spv::OpFDiv: case spv::OpFRem:
    case spv::OpFMod: case spv::OpVectorTimesScalar: case spv::OpDot: case spv::OpMatrixTimesVector:
    case spv::OpVectorTimesMatrix: case spv::OpFOrdEqual: case spv::OpFUnordEqual: case spv::OpFOrdNotEqual:
    case spv::OpFUnordNotEqual: case spv::OpFOrdLessThan: case spv::OpFUnordLessThan: case spv::OpFOrdGreaterThan:
    case spv::OpFUnordGreaterThan: case spv::OpFOrdLessThanEqual: case spv::OpFUnordLessThanEqual:
    case spv::OpFOrdGreaterThanEqual: case spv::OpFUnordGreaterThanEqual: case spv::OpConvertFToU:
    case spv::OpConvertFToS: case spv::OpFConvert: case spv::OpExtInst:
      return true;
    default:
      return false;
  }
}

// A SPIR-V module being rewritten: the instructions before the first function (`head`), the
// functions (`body`), and what the rewriting adds to the head.
class Module {
 public:
  explicit Module(const std::vector<std::uint32_t>& words) {
    if (words.size() < 5 || words[0] != spv::MagicNumber) throw std::logic_error("emulated arithmetic: not SPIR-V");
    header_.assign(words.begin(), words.begin() + 5);
    bound_ = words[3];
    bool in_body = false;
    for (std::size_t at = 5; at < words.size();) {
      const std::uint32_t count = words[at] >> 16;
      if (count == 0 || at + count > words.size()) throw std::logic_error("emulated arithmetic: a truncated instruction");
      Inst i{spv::Op(words[at] & 0xffff), std::vector<std::uint32_t>(words.begin() + long(at) + 1, words.begin() + long(at + count))};
      at += count;
      if (i.op == spv::OpFunction) in_body = true;
      note(i);
      (in_body ? body : head_).push_back(std::move(i));
    }
    for (const Inst& i : head_) {
      if (i.op == spv::OpExtInstImport && literal(i.w, 1) == "GLSL.std.450") glsl_ = i.w[0];
      if (i.op == spv::OpDecorate && i.w[1] == spv::DecorationNoContraction) no_contraction.insert(i.w[0]);
      if (i.op == spv::OpDecorate && i.w[1] == spv::DecorationRelaxedPrecision) relaxed.insert(i.w[0]);
      if (i.op == spv::OpCapability) capabilities_.insert(i.w[0]);
      if (i.op == spv::OpTypeFloat) types_[key('f', int(i.w[1]), 1)] = i.w[0];
      if (i.op == spv::OpTypeInt && i.w[2] == 0) types_[key('u', int(i.w[1]), 1)] = i.w[0];
      if (i.op == spv::OpTypeBool) types_[key('b', 1, 1)] = i.w[0];
    }
    for (const Inst& i : head_)
      if (i.op == spv::OpTypeVector)
        for (const auto& [k, id] : std::map<std::string, std::uint32_t>(types_))
          if (id == i.w[1] && k.back() == '1') types_[k.substr(0, k.size() - 1) + char('0' + i.w[2])] = i.w[0];
  }

  std::vector<std::uint32_t> words() const {
    std::vector<Inst> head;
    for (std::uint32_t c : new_capabilities_) head.push_back({spv::OpCapability, {c}});
    bool decorated = false, imported = glsl_imported_;
    for (const Inst& i : head_) {
      if (!imported && i.op == spv::OpMemoryModel) {
        std::vector<std::uint32_t> w{glsl_};
        const char name[] = "GLSL.std.450";  // 12 characters, a terminating zero: 4 words
        for (std::size_t k = 0; k < sizeof name; k += 4) {
          std::uint32_t word = 0;
          std::memcpy(&word, name + k, std::min<std::size_t>(4, sizeof name - k));
          w.push_back(word);
        }
        head.push_back({spv::OpExtInstImport, w});
        imported = true;
      }
      if (!decorated && (spv::Op(i.op) == spv::OpTypeVoid || is_declaration(i.op))) {
        for (std::uint32_t id : decorate_) head.push_back({spv::OpDecorate, {id, std::uint32_t(spv::DecorationNoContraction)}});
        decorated = true;
      }
      Inst copy = i;
      if (copy.op == spv::OpDecorate || copy.op == spv::OpDecorateId || copy.op == spv::OpDecorateString)
        if (const auto r = renamed_.find(copy.w[0]); r != renamed_.end()) copy.w[0] = r->second;
      head.push_back(std::move(copy));
    }
    std::vector<std::uint32_t> out = header_;
    out[3] = bound_;
    const auto put = [&out](const Inst& i) {
      out.push_back(std::uint32_t(i.w.size() + 1) << 16 | std::uint32_t(i.op));
      out.insert(out.end(), i.w.begin(), i.w.end());
    };
    for (const Inst& i : head) put(i);
    for (const Inst& i : added_) put(i);
    for (const Inst& i : body) put(i);
    return out;
  }

  std::uint32_t fresh() { return bound_++; }
  void need_capability(spv::Capability c) {
    if (capabilities_.insert(c).second) new_capabilities_.push_back(c);
  }
  std::uint32_t glsl() {
    if (!glsl_) {
      glsl_ = fresh();
      glsl_imported_ = false;
    }
    return glsl_;
  }

  // Types: 'f' float, 'u' unsigned integer, 'b' bool; n components (1: a scalar).
  std::uint32_t type(char kind, int width, int n) {
    const std::string k = key(kind, width, n);
    if (const auto t = types_.find(k); t != types_.end()) return t->second;
    const std::uint32_t id = fresh();
    if (n > 1) {
      added_.push_back({spv::OpTypeVector, {id, type(kind, width, 1), std::uint32_t(n)}});
    } else if (kind == 'f') {
      if (width == 64) need_capability(spv::CapabilityFloat64);
      added_.push_back({spv::OpTypeFloat, {id, std::uint32_t(width)}});
    } else if (kind == 'u') {
      if (width == 64) need_capability(spv::CapabilityInt64);
      added_.push_back({spv::OpTypeInt, {id, std::uint32_t(width), 0}});
    } else {
      added_.push_back({spv::OpTypeBool, {id}});
    }
    types_[k] = id;
    type_of[id] = 0;
    return id;
  }
  // A constant of n equal components: `value`'s bits for 'u', its value for 'f'.
  std::uint32_t constant(char kind, int width, int n, double value, std::uint64_t bits = 0) {
    const std::string k = fmt::format("{}{}:{}", key(kind, width, n), value, bits);
    if (const auto c = constants_.find(k); c != constants_.end()) return c->second;
    const std::uint32_t t = type(kind, width, n);
    std::uint32_t id;
    if (n > 1) {
      const std::uint32_t s = constant(kind, width, 1, value, bits);
      id = fresh();
      std::vector<std::uint32_t> w{t, id};
      for (int i = 0; i < n; ++i) w.push_back(s);
      added_.push_back({spv::OpConstantComposite, w});
    } else {
      id = fresh();
      std::vector<std::uint32_t> w{t, id};
      if (kind == 'f' && width == 32) {
        const float f = float(value);
        std::uint32_t b;
        std::memcpy(&b, &f, 4);
        w.push_back(b);
      } else if (kind == 'f') {
        std::uint64_t b;
        std::memcpy(&b, &value, 8);
        w.push_back(std::uint32_t(b));
        w.push_back(std::uint32_t(b >> 32));
      } else if (width == 64) {
        w.push_back(std::uint32_t(bits));
        w.push_back(std::uint32_t(bits >> 32));
      } else {
        w.push_back(std::uint32_t(bits));
      }
      added_.push_back({spv::OpConstant, w});
    }
    type_of[id] = t;
    constants_[k] = id;
    return id;
  }

  // The number of components of a 32-bit float scalar or vector type; 0 for any other type.
  int f32_size(std::uint32_t t) const {
    for (int n = 1; n <= 4; ++n)
      if (const auto f = types_.find(key('f', 32, n)); f != types_.end() && f->second == t) return n;
    return 0;
  }
  int f32_size_of(std::uint32_t id) const {
    const auto t = type_of.find(id);
    return t == type_of.end() ? 0 : f32_size(t->second);
  }

  // Appends an instruction of result type `t` (0: none) to `out`, decorated NoContraction when
  // it computes; returns its result.
  std::uint32_t emit(std::vector<Inst>& out, spv::Op op, std::uint32_t t, std::vector<std::uint32_t> args,
                     std::uint32_t id = 0) {
    if (!id) id = fresh();
    Inst i{op, {t, id}};
    i.w.insert(i.w.end(), args.begin(), args.end());
    note(i);
    out.push_back(std::move(i));
    if (op == spv::OpFAdd || op == spv::OpFSub || op == spv::OpFMul || op == spv::OpFDiv || op == spv::OpFNegate ||
        op == spv::OpDot || op == spv::OpVectorTimesScalar || op == spv::OpExtInst || op == spv::OpFConvert)
      decorate_.push_back(id);
    return id;
  }
  std::uint32_t ext(std::vector<Inst>& out, GLSLstd450 e, std::uint32_t t, std::vector<std::uint32_t> args,
                    std::uint32_t id = 0) {
    args.insert(args.begin(), {glsl(), std::uint32_t(e)});
    return emit(out, spv::OpExtInst, t, std::move(args), id);
  }

  // `id`'s instruction is given the new result `to`; decorations follow it.
  void rename(std::uint32_t id, std::uint32_t to) {
    renamed_[id] = to;
    if (no_contraction.erase(id)) no_contraction.insert(to);
  }

  std::vector<Inst> body;
  std::unordered_map<std::uint32_t, std::uint32_t> type_of;  // result -> its type
  std::unordered_map<std::uint32_t, Inst> defs;              // result -> its instruction (in functions)
  std::set<std::uint32_t> no_contraction;
  std::set<std::uint32_t> relaxed;  // decorated RelaxedPrecision (mediump): results, variables, parameters

 private:
  static std::string key(char kind, int width, int n) { return fmt::format("{}{}x{}", kind, width, n); }
  static bool is_declaration(spv::Op op) {
    return (op >= spv::OpTypeVoid && op <= spv::OpTypeForwardPointer) || op == spv::OpConstant ||
           op == spv::OpConstantComposite || op == spv::OpConstantTrue || op == spv::OpConstantFalse ||
           op == spv::OpConstantNull || op == spv::OpVariable || op == spv::OpUndef ||
           (op >= spv::OpSpecConstantTrue && op <= spv::OpSpecConstantOp);
  }
  static std::string literal(const std::vector<std::uint32_t>& w, std::size_t from) {
    std::string s;
    for (std::size_t k = from; k < w.size(); ++k)
      for (int b = 0; b < 4; ++b) {
        const char c = char((w[k] >> (8 * b)) & 0xff);
        if (c == 0) return s;
        s += c;
      }
    return s;
  }
  void note(const Inst& i) {
    bool r = false, t = false;
    spv::HasResultAndType(i.op, &r, &t);
    if (r && t) {
      type_of[i.w[1]] = i.w[0];
      defs[i.w[1]] = i;
    }
  }

  std::vector<std::uint32_t> header_;
  std::uint32_t bound_ = 0;
  std::vector<Inst> head_, added_;
  std::uint32_t glsl_ = 0;
  bool glsl_imported_ = true;
  std::set<std::uint32_t> capabilities_;
  std::vector<std::uint32_t> new_capabilities_, decorate_;
  std::map<std::string, std::uint32_t> types_, constants_;
  std::unordered_map<std::uint32_t, std::uint32_t> renamed_;
};

// The rewriting of one module: relaxed precision on the module as compiled (relax), then, inlined
// and in SSA form, flush first (it wraps the original instructions), then contraction (which looks
// through a flushed product: a fused operation rounds, and flushes, once), then the error bounds.
class Rewriter {
 public:
  Rewriter(Module& m, const Arithmetic& a) : m_(m), a_(a) {}

  // Relaxed precision is rewritten alone, on the module as compiled, before anything removes the
  // variables whose decoration says that what is stored in them and loaded from them is relaxed.
  void relax() { pass(&Rewriter::relax_instruction); }

  void run() {
    if (a_.flush) pass(&Rewriter::flush_instruction);
    if (a_.contract) pass(&Rewriter::contract_instruction);
    if (a_.bounds != 0) pass(&Rewriter::bound_instruction);
  }

 private:
  using Out = std::vector<Inst>;

  void pass(bool (Rewriter::*rewrite)(const Inst&, Out&)) {
    Out out;
    out.reserve(m_.body.size());
    bool in_function = false;
    for (const Inst& i : m_.body) {
      if (i.op == spv::OpFunction) in_function = true;
      if (!in_function || !(this->*rewrite)(i, out)) out.push_back(i);
      if (i.op == spv::OpFunctionEnd) in_function = false;
    }
    m_.body = std::move(out);
  }

  std::uint32_t f32(int n) { return m_.type('f', 32, n); }
  std::uint32_t f64(int n) { return m_.type('f', 64, n); }
  std::uint32_t u64(int n) { return m_.type('u', 64, n); }
  std::uint32_t u32(int n) { return m_.type('u', 32, n); }
  std::uint32_t boolean(int n) { return m_.type('b', 1, n); }
  std::uint32_t cf(int width, int n, double v) { return m_.constant('f', width, n, v); }
  std::uint32_t cu(int width, int n, std::uint64_t v) { return m_.constant('u', width, n, 0.0, v); }

  // ---- relaxed precision: a value decorated RelaxedPrecision computed at 16 bits
  // x rounded to half precision, to nearest even, as round_to_half: the float's last 13 bits
  // rounded off in its bits; below 2^-14 (subnormal halves) to a multiple of 2^-24 by adding and
  // taking away 0.75 (NoContraction: computed as written), its sign kept; 2^16 and beyond (65520
  // rounds there) infinite; infinities and NaN as they are. Not OpQuantizeToF16, which may flush
  // subnormal halves to either zero (lavapipe's gives +0 for -2^-22).
  std::uint32_t quantized(Out& out, std::uint32_t x, int n, std::uint32_t id = 0) {
    const std::uint32_t F = f32(n), U = u32(n), B = boolean(n);
    const std::uint32_t bits = m_.emit(out, spv::OpBitcast, U, {x});
    const std::uint32_t odd = m_.emit(out, spv::OpBitwiseAnd, U, {m_.emit(out, spv::OpShiftRightLogical, U, {bits, cu(32, n, 13)}), cu(32, n, 1)});
    const std::uint32_t up = m_.emit(out, spv::OpIAdd, U, {bits, m_.emit(out, spv::OpIAdd, U, {cu(32, n, 0x0fff), odd})});
    const std::uint32_t normal = m_.emit(out, spv::OpBitcast, F, {m_.emit(out, spv::OpBitwiseAnd, U, {up, cu(32, n, 0xffffe000u)})});
    const std::uint32_t a = m_.ext(out, GLSLstd450FAbs, F, {x});
    const std::uint32_t tiny = m_.emit(out, spv::OpFSub, F, {m_.emit(out, spv::OpFAdd, F, {a, cf(32, n, 0.75)}), cf(32, n, 0.75)});
    const std::uint32_t sign = m_.emit(out, spv::OpBitwiseAnd, U, {bits, cu(32, n, 0x80000000u)});
    const std::uint32_t subnormal = m_.emit(out, spv::OpBitcast, F, {m_.emit(out, spv::OpBitwiseOr, U, {m_.emit(out, spv::OpBitcast, U, {tiny}), sign})});
    const std::uint32_t infinite = m_.emit(out, spv::OpBitcast, F, {m_.emit(out, spv::OpBitwiseOr, U, {cu(32, n, 0x7f800000u), sign})});
    std::uint32_t r = m_.emit(out, spv::OpSelect, F, {m_.emit(out, spv::OpFOrdLessThan, B, {a, cf(32, n, std::ldexp(1.0, -14))}), subnormal, normal});
    r = m_.emit(out, spv::OpSelect, F, {m_.emit(out, spv::OpFOrdGreaterThanEqual, B, {m_.ext(out, GLSLstd450FAbs, F, {r}), cf(32, n, 65536.0)}), infinite, r});
    const std::uint32_t special = m_.emit(out, spv::OpLogicalOr, B, {m_.emit(out, spv::OpIsNan, B, {x}), m_.emit(out, spv::OpIsInf, B, {x})});
    return m_.emit(out, spv::OpSelect, F, {special, x, r}, id);
  }

  // A relaxed float instruction takes its 32-bit float operands and gives its result quantized to
  // half precision (a basic operation on halves rounded through a float is rounded once, 24 >=
  // 2 11 + 2: Figueroa 1995); so does a relaxed load or one from a relaxed variable, and a value
  // stored in a relaxed variable is quantized first.
  bool relax_instruction(const Inst& i, Out& out) {
    if (i.op == spv::OpStore) {
      const int n = m_.f32_size_of(i.w[1]);
      if (!m_.relaxed.count(i.w[0]) || n == 0) return false;
      Inst copy = i;
      copy.w[1] = quantized(out, i.w[1], n);
      out.push_back(std::move(copy));
      return true;
    }
    bool has_result = false, has_type = false;
    spv::HasResultAndType(i.op, &has_result, &has_type);
    if (!has_result || !has_type || i.op == spv::OpVariable || i.op == spv::OpFunction ||
        i.op == spv::OpFunctionParameter || i.op == spv::OpPhi)
      return false;
    const bool relaxed_load = i.op == spv::OpLoad && m_.relaxed.count(i.w[2]);
    if (!m_.relaxed.count(i.w[1]) && !relaxed_load) return false;
    wrapped(i, out, computes_float(i), true, [&](std::uint32_t x, int n, std::uint32_t id) { return quantized(out, x, n, id); });
    return true;
  }

  // A floating-point instruction whose float operands a device computes with (is_float_instruction;
  // of the extended instructions, GLSL's only).
  bool computes_float(const Inst& i) { return is_float_instruction(i.op) && !(i.op == spv::OpExtInst && i.w[2] != m_.glsl()); }

  // `i` with each 32-bit float operand x replaced by through(x, n, 0) when `operands`, and its
  // 32-bit float result, when `result`, computed under a fresh id and given as through(it, n, id).
  template <class Through>
  void wrapped(const Inst& i, Out& out, bool operands, bool result, Through through) {
    Inst copy = i;
    if (operands) {
      const std::size_t first = i.op == spv::OpExtInst ? 4 : 2;
      for (std::size_t k = first; k < copy.w.size(); ++k)
        if (const int n = m_.f32_size_of(copy.w[k])) copy.w[k] = through(copy.w[k], n, 0u);
    }
    const int n = m_.f32_size(copy.w[0]);
    if (n == 0 || !result) {
      out.push_back(std::move(copy));
      return;
    }
    const std::uint32_t id = copy.w[1], computed = m_.fresh();
    m_.rename(id, computed);
    copy.w[1] = computed;
    m_.type_of[computed] = copy.w[0];
    m_.defs[computed] = copy;
    out.push_back(std::move(copy));
    through(computed, n, id);
  }

  // ---- flushing: |x| < 2^-126 becomes x * 0 (a zero of x's sign)
  std::uint32_t flushed(Out& out, std::uint32_t x, int n, std::uint32_t id = 0) {
    const std::uint32_t a = m_.ext(out, GLSLstd450FAbs, f32(n), {x});
    const std::uint32_t small = m_.emit(out, spv::OpFOrdLessThan, boolean(n), {a, cf(32, n, std::ldexp(1.0, -126))});
    const std::uint32_t zero = m_.emit(out, spv::OpFMul, f32(n), {x, cf(32, n, 0.0)});
    const std::uint32_t r = m_.emit(out, spv::OpSelect, f32(n), {small, zero, x}, id);
    flush_of_[r] = x;
    return r;
  }

  bool flush_instruction(const Inst& i, Out& out) {
    if (!computes_float(i)) return false;
    wrapped(i, out, true, i.op != spv::OpFNegate, [&](std::uint32_t x, int n, std::uint32_t id) { return flushed(out, x, n, id); });
    return true;
  }

  // ---- contraction: a * b + c rounded once
  // a * b + c (n components, 32-bit) rounded once, as `id`: the product exact in 64-bit floats, the
  // sum rounded to odd there (its error by Knuth's two-sum), then rounded to float: a correctly
  // rounded fused multiply-add, 53 >= 24 + 2 bits (Boldo and Melquiond 2008).
  std::uint32_t fused(Out& out, int n, std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t id = 0) {
    const std::uint32_t D = f64(n), U = u64(n), B = boolean(n);
    const std::uint32_t da = m_.emit(out, spv::OpFConvert, D, {a});
    const std::uint32_t db = m_.emit(out, spv::OpFConvert, D, {b});
    const std::uint32_t dc = m_.emit(out, spv::OpFConvert, D, {c});
    const std::uint32_t p = m_.emit(out, spv::OpFMul, D, {da, db});
    const std::uint32_t s = m_.emit(out, spv::OpFAdd, D, {p, dc});
    const std::uint32_t bb = m_.emit(out, spv::OpFSub, D, {s, p});
    const std::uint32_t ap = m_.emit(out, spv::OpFSub, D, {s, bb});
    const std::uint32_t e = m_.emit(out, spv::OpFAdd, D,
                                    {m_.emit(out, spv::OpFSub, D, {p, ap}), m_.emit(out, spv::OpFSub, D, {dc, bb})});
    const std::uint32_t bits = m_.emit(out, spv::OpBitcast, U, {s});
    const std::uint32_t even = m_.emit(out, spv::OpIEqual, B, {m_.emit(out, spv::OpBitwiseAnd, U, {bits, cu(64, n, 1)}), cu(64, n, 0)});
    const std::uint32_t inexact = m_.emit(out, spv::OpFOrdNotEqual, B, {e, cf(64, n, 0.0)});
    const std::uint32_t same_sign = m_.emit(out, spv::OpLogicalEqual, B,
                                            {m_.emit(out, spv::OpFOrdLessThan, B, {e, cf(64, n, 0.0)}),
                                             m_.emit(out, spv::OpFOrdLessThan, B, {s, cf(64, n, 0.0)})});
    // An inexact sum with an even last bit moves one step toward the exact value: rounded to odd.
    const std::uint32_t step = m_.emit(out, spv::OpSelect, U,
                                       {same_sign, m_.emit(out, spv::OpIAdd, U, {bits, cu(64, n, 1)}),
                                        m_.emit(out, spv::OpISub, U, {bits, cu(64, n, 1)})});
    const std::uint32_t odd = m_.emit(out, spv::OpSelect, U,
                                      {m_.emit(out, spv::OpLogicalAnd, B, {even, inexact}), step, bits});
    const std::uint32_t r = m_.emit(out, spv::OpFConvert, f32(n), {m_.emit(out, spv::OpBitcast, D, {odd})}, id);
    return r;
  }

  // The factors of `id` when it is a product that may be contracted: the id itself or the flush
  // of one.
  bool product(Out& out, std::uint32_t id, int n, std::uint32_t* a, std::uint32_t* b) {
    for (auto f = flush_of_.find(id); f != flush_of_.end(); f = flush_of_.find(id)) id = f->second;
    const auto d = m_.defs.find(id);
    if (d == m_.defs.end() || m_.no_contraction.count(id)) return false;
    if (d->second.op == spv::OpFMul) {
      *a = d->second.w[2];
      *b = d->second.w[3];
      return true;
    }
    if (d->second.op == spv::OpVectorTimesScalar) {
      *a = d->second.w[2];
      std::vector<std::uint32_t> splat(std::size_t(n), d->second.w[3]);
      *b = m_.emit(out, spv::OpCompositeConstruct, f32(n), splat);
      return true;
    }
    return false;
  }

  bool contract_instruction(const Inst& i, Out& out) {
    const bool computes = i.op == spv::OpFAdd || i.op == spv::OpFSub || i.op == spv::OpDot ||
                          (i.op == spv::OpExtInst && i.w[2] == m_.glsl() && i.w[3] == GLSLstd450Fma);
    if (!computes || m_.f32_size(i.w[0]) == 0 || m_.no_contraction.count(i.w[1])) return false;
    const int n = m_.f32_size(i.w[0]);
    const std::uint32_t id = i.w[1];
    if (i.op == spv::OpExtInst) {
      fused(out, n, i.w[4], i.w[5], i.w[6], id);
      return true;
    }
    if (i.op == spv::OpDot) {
      const int k = m_.f32_size_of(i.w[2]);
      const auto part = [&](std::uint32_t v, int c) {
        return m_.emit(out, spv::OpCompositeExtract, f32(1), {v, std::uint32_t(c)});
      };
      std::uint32_t sum = m_.emit(out, spv::OpFMul, f32(1), {part(i.w[2], 0), part(i.w[3], 0)});
      if (a_.flush) sum = flushed(out, sum, 1);
      for (int c = 1; c < k; ++c) {
        const bool last = c == k - 1;
        sum = fused(out, 1, part(i.w[2], c), part(i.w[3], c), sum, last && !a_.flush ? id : 0);
        if (a_.flush && !last) sum = flushed(out, sum, 1);
      }
      if (a_.flush) m_.emit(out, spv::OpCopyObject, f32(1), {sum}, id);  // the flush after the dot flushes the result
      return true;
    }
    std::uint32_t a = 0, b = 0;
    const std::uint32_t x = i.w[2], y = i.w[3];
    if (product(out, x, n, &a, &b)) {  // a * b + y, a * b - y
      const std::uint32_t c = i.op == spv::OpFAdd ? y : m_.emit(out, spv::OpFNegate, f32(n), {y});
      fused(out, n, a, b, c, id);
      return true;
    }
    if (product(out, y, n, &a, &b)) {  // x + a * b, x - a * b
      if (i.op == spv::OpFSub) a = m_.emit(out, spv::OpFNegate, f32(n), {a});
      fused(out, n, a, b, x, id);
      return true;
    }
    return false;
  }

  // ---- error bounds: the float farthest from the exact value v (a 64-bit float) that is within
  // `ulps` of it (the Vulkan specification's ulp), toward zero (bounds < 0) or away from it.
  std::uint32_t at_bound(Out& out, std::uint32_t v, int n, double ulps, int direction, std::uint32_t id = 0) {
    const std::uint32_t D = f64(n), U = u64(n), B = boolean(n), F = f32(n), W = u32(n);
    const std::uint32_t av = m_.ext(out, GLSLstd450FAbs, D, {v});
    const std::uint32_t bits = m_.emit(out, spv::OpBitcast, U, {av});
    const std::uint32_t e = m_.emit(out, spv::OpBitwiseAnd, U, {m_.emit(out, spv::OpShiftRightLogical, U, {bits, cu(64, n, 52)}), cu(64, n, 0x7ff)});
    // ulp(x): 2^(floor(log2 |x|) - 23), the spacing of floats in x's binade; the spacing below it
    // when x is a power of two (the least distance between floats around x); 2^-149 below 2^-126.
    const std::uint32_t low_binade = m_.emit(out, spv::OpULessThan, B, {e, cu(64, n, 897)});  // 1023 - 126
    const std::uint32_t ec = m_.emit(out, spv::OpSelect, U, {low_binade, cu(64, n, 897), e});
    const std::uint32_t power = m_.emit(out, spv::OpLogicalAnd, B,
                                        {m_.emit(out, spv::OpIEqual, B, {m_.emit(out, spv::OpBitwiseAnd, U, {bits, cu(64, n, (std::uint64_t(1) << 52) - 1)}), cu(64, n, 0)}),
                                         m_.emit(out, spv::OpULessThan, B, {cu(64, n, 897), e})});
    const std::uint32_t k = m_.emit(out, spv::OpISub, U, {ec, m_.emit(out, spv::OpSelect, U, {power, cu(64, n, 24), cu(64, n, 23)})});
    const std::uint32_t ulp = m_.emit(out, spv::OpBitcast, D, {m_.emit(out, spv::OpShiftLeftLogical, U, {k, cu(64, n, 52)})});
    const std::uint32_t reach = m_.emit(out, spv::OpFMul, D, {ulp, cf(64, n, ulps)});  // exact: a power of two times 2 or 2.5
    std::uint32_t t = m_.emit(out, direction > 0 ? spv::OpFAdd : spv::OpFSub, D, {av, reach});
    if (direction < 0) t = m_.ext(out, GLSLstd450FMax, D, {t, cf(64, n, 0.0)});
    // The float nearest t, moved one step back toward |v| when it lies beyond t.
    const std::uint32_t f = m_.emit(out, spv::OpFConvert, F, {t});
    const std::uint32_t beyond = m_.emit(out, direction > 0 ? spv::OpFOrdGreaterThan : spv::OpFOrdLessThan, B,
                                         {m_.emit(out, spv::OpFConvert, D, {f}), t});
    const std::uint32_t fb = m_.emit(out, spv::OpBitcast, W, {f});
    const std::uint32_t back = m_.emit(out, direction > 0 ? spv::OpISub : spv::OpIAdd, W, {fb, cu(32, n, 1)});
    const std::uint32_t mag = m_.emit(out, spv::OpBitcast, F, {m_.emit(out, spv::OpSelect, W, {beyond, back, fb})});
    const std::uint32_t negative = m_.emit(out, spv::OpFOrdLessThan, B, {v, cf(64, n, 0.0)});
    return m_.emit(out, spv::OpSelect, F, {negative, m_.emit(out, spv::OpFNegate, F, {mag}), mag}, id);
  }

  std::uint32_t widen(Out& out, std::uint32_t x, int n) { return m_.emit(out, spv::OpFConvert, f64(n), {x}); }
  // inversesqrt: 2 ULP.
  std::uint32_t inversesqrt(Out& out, std::uint32_t x, int n, int dir, std::uint32_t id = 0) {
    const std::uint32_t v = m_.emit(out, spv::OpFDiv, f64(n), {cf(64, n, 1.0), m_.ext(out, GLSLstd450Sqrt, f64(n), {widen(out, x, n)})});
    return at_bound(out, v, n, 2.0, dir, id);
  }
  // x / y: 2.5 ULP (for |y| in [2^-126, 2^126]; beyond, the specification bounds nothing, and
  // the same bound is used).
  std::uint32_t divide(Out& out, std::uint32_t x, std::uint32_t y, int n, int dir, std::uint32_t id = 0) {
    const std::uint32_t v = m_.emit(out, spv::OpFDiv, f64(n), {widen(out, x, n), widen(out, y, n)});
    return at_bound(out, v, n, 2.5, dir, id);
  }
  // sqrt: inherited from 1.0 / inversesqrt().
  std::uint32_t square_root(Out& out, std::uint32_t x, int n, int dir, std::uint32_t id = 0) {
    return divide(out, cf(32, n, 1.0), maybe_flushed(out, inversesqrt(out, x, n, -dir), n), n, dir, id);
  }
  // x . x as the device computes a dot product (a scalar: x * x), flushed with the variant.
  std::uint32_t self_dot(Out& out, std::uint32_t x, int n) {
    return maybe_flushed(out, m_.emit(out, n == 1 ? spv::OpFMul : spv::OpDot, f32(1), {x, x}), 1);
  }
  // An intermediate result of an inherited bound, flushed when the device flushes.
  std::uint32_t maybe_flushed(Out& out, std::uint32_t x, int n) { return a_.flush ? flushed(out, x, n) : x; }

  bool bound_instruction(const Inst& i, Out& out) {
    if (i.op != spv::OpFDiv && i.op != spv::OpExtInst) return false;
    const int n = m_.f32_size(i.w[0]);
    if (n == 0) return false;
    const int dir = a_.bounds;
    const std::uint32_t id = i.w[1];
    if (i.op == spv::OpFDiv) {
      divide(out, i.w[2], i.w[3], n, dir, id);
      return true;
    }
    if (i.op != spv::OpExtInst || i.w[2] != m_.glsl()) return false;
    const std::uint32_t x = i.w[4];
    const int k = m_.f32_size_of(x);
    switch (i.w[3]) {
      case GLSLstd450InverseSqrt: inversesqrt(out, x, n, dir, id); return true;
      case GLSLstd450Sqrt: square_root(out, x, n, dir, id); return true;
      // length: inherited from sqrt(dot(x, x)); distance: from length(x - y).
      case GLSLstd450Length: square_root(out, self_dot(out, x, k), 1, dir, id); return true;
      case GLSLstd450Distance:
        square_root(out, self_dot(out, m_.emit(out, spv::OpFSub, f32(k), {x, i.w[5]}), k), 1, dir, id);
        return true;
      case GLSLstd450Normalize: {  // inherited from x * inversesqrt(dot(x, x))
        const std::uint32_t s = maybe_flushed(out, inversesqrt(out, self_dot(out, x, k), 1, dir), 1);
        m_.emit(out, k == 1 ? spv::OpFMul : spv::OpVectorTimesScalar, f32(k), {x, s}, id);
        return true;
      }
      default: return false;
    }
  }

  Module& m_;
  Arithmetic a_;
  std::unordered_map<std::uint32_t, std::uint32_t> flush_of_;  // a flush's result -> what it flushed
};

std::string joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const std::string& l : lines) s += "\n  " + l;
  return s;
}

}  // namespace

std::vector<std::uint32_t> emulate_arithmetic(const std::vector<std::uint32_t>& compiled, const Arithmetic& a) {
  if (!a.contract && !a.flush && a.bounds == 0 && !a.relaxed) return compiled;
  std::vector<std::string> messages;
  const auto collect = [&messages](spv_message_level_t, const char*, const spv_position_t& at, const char* m) {
    messages.push_back(fmt::format("word {}: {}", at.index, m));
  };
  std::vector<std::uint32_t> out = compiled;
  if (a.relaxed) {
    Module m(out);
    Rewriter(m, a).relax();
    out = m.words();
  }
  if (a.contract || a.flush || a.bounds != 0) {
    // Inlined and in SSA form, so that a product stored in a variable and added in another
    // statement is seen as a compiler sees it; these passes change no value.
    spvtools::Optimizer opt(SPV_ENV_VULKAN_1_0);
    opt.SetMessageConsumer(collect);
    opt.RegisterPass(spvtools::CreateInlineExhaustivePass())
        .RegisterPass(spvtools::CreateLocalSingleBlockLoadStoreElimPass())
        .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
        .RegisterPass(spvtools::CreateSSARewritePass())
        .RegisterPass(spvtools::CreateAggressiveDCEPass());
    std::vector<std::uint32_t> ssa;
    if (!opt.Run(out.data(), out.size(), &ssa))
      throw std::logic_error("emulated arithmetic " + to_string(a) + ": SPIRV-Tools cannot inline the shader:" + joined(messages));
    Module m(ssa);
    Rewriter(m, a).run();
    out = m.words();
  }
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_0);
  tools.SetMessageConsumer(collect);
  if (!tools.Validate(out))
    throw std::logic_error("emulated arithmetic " + to_string(a) + ": the rewritten shader does not validate:" + joined(messages));
  return out;
}

}  // namespace cullproof::gpu

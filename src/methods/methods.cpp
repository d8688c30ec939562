// Methods: the Method type and the built-in registry (the families register themselves; names
// are checked to be unique). The names of claims and origins are in claims.cpp.
#include "cullproof/methods/methods.hpp"

#include "builtin.hpp"

#include <set>
#include <stdexcept>

namespace cullproof {

Method::Method(MethodInfo info, Prepare prepare, bool batch)
    : MethodInfo(std::move(info)), prepare_(std::move(prepare)), batch_(batch) {
  if (!prepare_) throw std::invalid_argument("method '" + name + "' has no prepare function");
}

Answer Method::classify(const CaseFrustum& f, const Volume& v) const {
  if (stateful) reset();  // a camera path of one frame
  const std::unique_ptr<PreparedFrustum> p = prepare(f);
  if (!p) return std::nullopt;
  return p->classify(v);
}

void Method::classify_frames(const FrameRequest* frames, std::size_t n, Answer* answers) const {
  if (frames_) return frames_(frames, n, answers);
  for (std::size_t j = 0; j < n; ++j) {
    const std::unique_ptr<PreparedFrustum> p = prepare(*frames[j].frustum);
    for (std::size_t i = 0; i < frames[j].count; ++i) *answers++ = p ? p->classify(frames[j].volumes[i]) : Answer{};
  }
}

namespace {

std::vector<Method> build() {
  std::vector<Method> out;
  detail::register_cull_methods(out);
  detail::register_exact_methods(out);
  detail::register_certified_methods(out);
  std::set<std::string> seen;
  for (const Method& m : out)
    if (!seen.insert(m.name).second) throw std::logic_error("cullproof: method name registered twice: " + m.name);
  return out;
}

}  // namespace

const std::vector<Method>& builtin_methods() {
  static const std::vector<Method> all = build();
  return all;
}

const Method* find_builtin(std::string_view name) {
  for (const Method& m : builtin_methods())
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<Method> builtin_methods(const std::vector<std::string>& names) {
  if (names.empty()) return builtin_methods();
  std::vector<Method> out;
  for (const std::string& n : names) {
    const Method* m = find_builtin(n);
    if (!m) {
      std::string known;
      for (const Method& k : builtin_methods()) known += (known.empty() ? "" : ", ") + k.name;
      throw std::invalid_argument("unknown method '" + n + "' (built-in: " + known +
                                  "; a method behind a program is named with --external NAME -- PROGRAM: docs/protocol.md)");
    }
    out.push_back(*m);
  }
  return out;
}

}  // namespace cullproof

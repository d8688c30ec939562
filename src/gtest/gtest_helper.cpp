// The GoogleTest helper (see cullproof/gtest/gtest.hpp).
#include "cullproof/gtest/gtest.hpp"

#include "helper_text.hpp"

#include "cullproof/io/case_io.hpp"
#include "cullproof/corpus/corpus.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>

namespace cullproof::testing {

namespace detail {

std::optional<std::string> env(const char* name) {
  const char* v = std::getenv(name);
  if (!v || !*v) return std::nullopt;
  return std::string(v);
}

std::uint64_t env_number(const char* name, std::uint64_t fallback) {
  const auto v = env(name);
  if (!v) return fallback;
  std::size_t used = 0;
  unsigned long long x = 0;
  try {
    if (!v->empty() && (*v)[0] == '-') throw std::invalid_argument("negative");
    x = std::stoull(*v, &used, 10);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != v->size())
    throw std::invalid_argument(fmt::format("environment variable {}='{}' is not a non-negative integer", name, *v));
  return x;
}

namespace {

std::string hex3(const glm::vec3& x) {
  return fmt::format("[{}, {}, {}]", format_hex_float(x.x), format_hex_float(x.y), format_hex_float(x.z));
}

}  // namespace

std::string hex_numbers(const Case& c) {
  std::string s = "  frustum (hex):";
  if (c.frustum.matrix) {
    s += " matrix";
    for (int col = 0; col < 4; ++col) s += " " + hex3(glm::vec3((*c.frustum.matrix)[col])) + "," +
                                             format_hex_float((*c.frustum.matrix)[col][3]);
  }
  for (int k = 0; k < kPlaneCount; ++k) {
    const Plane& p = c.frustum.planes[k];
    s += fmt::format("\n    {:<6} n {} d {}", plane_name(k), hex3(p.n), format_hex_float(p.d));
  }
  s += "\n  volume (hex): ";
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, Point>) s += "point " + hex3(v);
        else if constexpr (std::is_same_v<T, Sphere>) s += "sphere centre " + hex3(v.center) + " radius " + format_hex_float(v.radius);
        else if constexpr (std::is_same_v<T, Aabb>) s += "aabb min " + hex3(v.min) + " max " + hex3(v.max);
        else
          s += "obb centre " + hex3(v.center) + " axes " + hex3(v.axes[0]) + " " + hex3(v.axes[1]) + " " +
               hex3(v.axes[2]) + " half " + hex3(v.half);
      },
      c.volume);
  return s;
}

}  // namespace detail

namespace {

using detail::env;
using detail::env_number;
using detail::hex_numbers;

VerifyOptions options_of(const ClaimOptions& o) {
  VerifyOptions v;
  v.cases = env_number("CULLPROOF_CASES", o.cases);
  v.seed = env_number("CULLPROOF_SEED", o.seed);
  v.distributions = o.distributions;
  if (const auto d = env("CULLPROOF_DISTRIBUTION")) v.distributions = gen::parse_distributions(*d);
  if (env("CULLPROOF_INDEX")) v.only_index = env_number("CULLPROOF_INDEX", 0);
  v.corpus = o.corpus ? *o.corpus : std::filesystem::path("cullproof-corpus");
  if (const auto c = env("CULLPROOF_CORPUS")) v.corpus = std::filesystem::path(*c);
  v.corpus_per_class = 0;  // only what breaks the claim
  v.threads = o.threads;
  v.shrink_budget = o.shrink_budget;
  v.progress = false;
  v.timing = false;
  return v;
}

std::string describe(const CorpusEntry& e) {
  const nlohmann::json& x = e.c.extra;
  auto field = [&](const char* k) { return x.contains(k) ? (x[k].is_string() ? x[k].get<std::string>() : x[k].dump()) : "-"; };
  std::string s = fmt::format("  {} says {} where the truth is {} ({}), found by the {} distribution\n", e.method,
                              to_string(e.verdict), e.c.truth ? to_string(*e.c.truth) : "?", to_string(e.error),
                              e.distribution);
  s += fmt::format("  distance to the verdict given: {} ({}); allowance {} (tolerance {} x scale {}{})\n",
                   field("verdict_distance"), field("verdict_distance_kind"), field("allowance"), field("tolerance"),
                   field("scale"), x.value("float_exact", false) ? ", float-exact: none" : "");
  s += fmt::format("  distance to the boundary (oracle): {} ({})\n", field("distance"), field("distance_kind"));
  Case bare = e.c;
  bare.extra = nlohmann::json::object();
  s += "  case: " + format_case(bare) + "\n" + hex_numbers(e.c) + "\n";
  if (e.path)
    s += fmt::format("  camera path: the error needs the {} frame(s) before it ({} motion, {} object(s)), recorded in "
                     "the corpus file's \"path\"\n",
                     e.path->frames.size() - 1, e.path->motion, e.path->objects.size());
  s += "  verdicts: " + field("verdicts") + "\n";
  s += "  witness: " + field("witness") + "\n";
  s += "  corpus file: " + e.file.string() + "\n";
  s += "  reproduce: " + field("reproduce") + "\n";
  return s;
}

}  // namespace

VerifyResult verify_methods(const std::vector<Method>& methods, const ClaimOptions& options) {
  return run_verify(options_of(options), methods);
}

::testing::AssertionResult claim_holds(const Method& method, const ClaimOptions& options) {
  std::vector<Method> ms = {method};
  for (const std::string& n : options.beside)
    if (const Method* b = find_builtin(n); b && n != method.name) ms.push_back(*b);
  const VerifyOptions vo = options_of(options);
  const VerifyResult r = run_verify(vo, ms);
  for (const DistributionResult& d : r.distributions)
    if (d.methods[0].fault) return ::testing::AssertionFailure() << "cullproof: FAULT: " << d.methods[0].fault->message(d.distribution, vo.seed);
  std::uint64_t cases = 0, violations = 0;
  std::set<std::string> ids;
  std::string counts;
  for (const DistributionResult& d : r.distributions) {
    const MethodStats& s = d.methods[0];
    cases += s.cases;
    violations += s.claim_violations;
    for (const std::string& id : s.corpus_written) ids.insert(id);
    if (s.claim_violations > 0)
      counts += fmt::format("  {}: {} of {} cases ({} false rejects, {} false insides, {} false intersects, {} under-insides)\n",
                            gen::to_string(d.distribution), s.claim_violations, s.cases, s.false_reject, s.false_inside,
                            s.false_intersect, s.under_inside);
  }
  if (violations == 0)
    return ::testing::AssertionSuccess() << method.name << " holds its claim '" << to_string(method.claim) << "' on "
                                         << cases << " cases";
  std::string msg = fmt::format("{} ({} method) breaks its claim '{}' on {} of {} cases (seed {}):\n{}", method.name,
                                to_string(method.origin), to_string(method.claim), violations, cases, vo.seed, counts);
  // The shrunk cases this run wrote; an earlier run may have written the same geometry already,
  // so the folder's records of this method that break its claim are the fallback.
  std::vector<CorpusEntry> shown;
  for (CorpusEntry& e : load_corpus(*vo.corpus)) {
    if (e.method != method.name) continue;
    const auto v = e.c.extra.find("violates_claim");
    if (v == e.c.extra.end() || !v->is_boolean() || !v->get<bool>()) continue;
    if (ids.count(e.c.id) || ids.empty()) shown.push_back(std::move(e));
  }
  // The first of the run's distributions that broke the claim is shown first.
  auto rank = [&](const CorpusEntry& e) {
    for (std::size_t k = 0; k < vo.distributions.size(); ++k)
      if (gen::to_string(vo.distributions[k]) == e.distribution) return k;
    return vo.distributions.size();
  };
  std::stable_sort(shown.begin(), shown.end(), [&](const CorpusEntry& a, const CorpusEntry& b) { return rank(a) < rank(b); });
  if (shown.empty()) {
    msg += fmt::format("  (no shrunk case could be written under {})\n", vo.corpus->string());
  } else {
    msg += fmt::format("first of {} shrunk case(s) written under {}:\n", shown.size(), vo.corpus->string());
    msg += describe(shown.front());
  }
  return ::testing::AssertionFailure() << msg;
}

}  // namespace cullproof::testing

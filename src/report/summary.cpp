// The summary of a verification run (see cullproof/report/summary.hpp).
#include "cullproof/report/summary.hpp"

#include "cullproof/campaign/campaign.hpp"

#include "show.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>

namespace cullproof::report {

const nlohmann::json& field(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object()) throw ResultError(where + ": expected an object");
  const auto it = j.find(key);
  if (it == j.end()) throw ResultError(where + "." + key + ": missing");
  return *it;
}

std::uint64_t count_field(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_number_unsigned() && !(v.is_number_integer() && v.get<std::int64_t>() >= 0))
    throw ResultError(where + "." + key + ": expected a count (a non-negative integer)");
  return v.get<std::uint64_t>();
}

std::string text_field(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_string()) throw ResultError(where + "." + key + ": expected a string");
  return v.get<std::string>();
}

std::optional<double> measure_field(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (v.is_null()) return std::nullopt;
  if (!v.is_number()) throw ResultError(where + "." + key + ": expected a number or null");
  return v.get<double>();
}

namespace {

bool flag(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_boolean()) throw ResultError(where + "." + key + ": expected true or false");
  return v.get<bool>();
}

std::vector<std::string> strings(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = field(j, key, where);
  if (!v.is_array()) throw ResultError(where + "." + key + ": expected an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!v[i].is_string()) throw ResultError(fmt::format("{}.{}[{}]: expected a string", where, key, i));
    out.push_back(v[i].get<std::string>());
  }
  return out;
}

// Volume kinds in the order the groups are listed: points first, the most general boxes last.
int kind_rank(const std::string& k) {
  static const char* order[] = {"point", "sphere", "aabb", "obb"};
  for (int i = 0; i < 4; ++i)
    if (k == order[i]) return i;
  return 4;
}

}  // namespace

bool on_front(const MethodOverall& m) {
  return m.claim != "none" && !m.refuted && !m.faulted && m.ns_per_test && m.truth_outside > 0;
}

bool Summary::own_claim_broken() const noexcept {
  return std::any_of(broken.begin(), broken.end(), [](const BrokenClaim& b) { return b.origin != "published"; });
}

std::optional<double> median(std::vector<double> values) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double x) { return !std::isfinite(x); }), values.end());
  if (values.empty()) return std::nullopt;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

std::vector<std::size_t> pareto_front(const std::vector<CostPoint>& points) {
  std::vector<std::size_t> order(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (points[a].ns_per_test != points[b].ns_per_test) return points[a].ns_per_test < points[b].ns_per_test;
    return points[a].fi_rate < points[b].fi_rate;
  });
  std::vector<std::size_t> front;
  for (const std::size_t i : order)
    if (front.empty() || points[i].fi_rate < points[front.back()].fi_rate) front.push_back(i);
  return front;
}

Summary summarize(const nlohmann::json& verify) {
  Summary s;
  s.seed = count_field(verify, "seed", "result");
  s.cases_per_distribution = count_field(verify, "cases_per_distribution", "result");
  s.failed = flag(verify, "failed", "result");
  s.interrupted = flag(verify, "interrupted", "result");
  const nlohmann::json& dists = field(verify, "distributions", "result");
  if (!dists.is_array()) throw ResultError("result.distributions: expected an array");

  struct Acc {
    MethodOverall m;
    std::vector<double> ns, ns_own;
    BrokenClaim broken;
  };
  std::vector<Acc> acc;
  std::map<std::string, std::size_t> index;
  for (std::size_t di = 0; di < dists.size(); ++di) {
    const std::string dw = fmt::format("result.distributions[{}]", di);
    const nlohmann::json& d = dists[di];
    const std::string family = text_field(d, "distribution", dw);
    s.families.push_back(family);
    const auto mit = d.find("methods");
    if (mit == d.end()) continue;  // a distribution no method took
    if (!mit->is_array()) throw ResultError(dw + ".methods: expected an array");
    for (std::size_t mi = 0; mi < mit->size(); ++mi) {
      const std::string w = fmt::format("{}.methods[{}]", dw, mi);
      const nlohmann::json& j = (*mit)[mi];
      const std::string name = text_field(j, "method", w);
      auto [it, fresh] = index.emplace(name, acc.size());
      if (fresh) {
        Acc a;
        a.m.method = name;
        a.m.claim = text_field(j, "claim", w);
        a.m.origin = text_field(j, "origin", w);
        a.m.three_way = flag(j, "three_way", w);
        a.m.volumes = strings(j, "volumes", w);
        a.broken.method = name;
        a.broken.claim = a.m.claim;
        a.broken.origin = a.m.origin;
        acc.push_back(std::move(a));
      }
      Acc& a = acc[it->second];
      MethodOverall& m = a.m;
      m.cases += count_field(j, "cases", w);
      m.truth_outside += count_field(field(j, "truth", w), "outside", w + ".truth");
      m.false_reject += count_field(j, "false_reject", w);
      m.false_inside += count_field(j, "false_inside", w);
      m.false_intersect += count_field(j, "false_intersect", w);
      m.under_inside += count_field(j, "under_inside", w);
      const std::uint64_t violations = count_field(j, "claim_violations", w);
      m.claim_violations += violations;
      if (flag(j, "refuted", w)) m.refuted = true;
      if (const nlohmann::json& fault = field(j, "fault", w); !fault.is_null()) {
        const std::string fw = w + ".fault";
        if (!fault.is_object()) throw ResultError(fw + ": expected an object or null");
        m.faulted = true;
        FaultLine f;
        f.method = name;
        f.family = family;
        f.problem = text_field(fault, "problem", fw);
        if (!field(fault, "index", fw).is_null()) {
          f.index = count_field(fault, "index", fw);
          f.reproduce = text_field(fault, "reproduce", fw);
        }
        s.faults.push_back(std::move(f));
      }
      if (const auto x = measure_field(j, "ns_per_test", w)) a.ns.push_back(*x);
      if (const auto x = measure_field(j, "ns_per_test_own", w)) a.ns_own.push_back(*x);
      if (violations) {
        FamilyBreak f;
        f.family = family;
        f.violations = violations;
        f.float_exact_violations = count_field(j, "float_exact_violations", w);
        const nlohmann::json& first = field(j, "first_violation", w);
        if (!first.is_null()) {
          f.first_violation = count_field(j, "first_violation", w);
          f.reproduce = text_field(j, "first_violation_reproduce", w);
        }
        f.corpus_ids = strings(j, "violation_ids", w);
        a.broken.violations += violations;
        a.broken.families.push_back(std::move(f));
      }
    }
  }

  for (Acc& a : acc) {
    MethodOverall& m = a.m;
    m.fi_rate = m.truth_outside ? double(m.false_intersect) / double(m.truth_outside) : 0.0;
    std::tie(m.fi_low, m.fi_high) = wilson95(m.false_intersect, m.truth_outside);
    m.ns_per_test = median(a.ns);
    m.ns_per_test_own = median(a.ns_own);
    if (!a.broken.families.empty()) s.broken.push_back(a.broken);
    s.methods.push_back(m);
  }

  // Groups by the exact set of volume kinds taken.
  std::map<std::vector<std::string>, std::vector<const MethodOverall*>> groups;
  for (const MethodOverall& m : s.methods) {
    std::vector<std::string> key = m.volumes;
    std::sort(key.begin(), key.end(), [](const std::string& a, const std::string& b) { return kind_rank(a) < kind_rank(b); });
    if (on_front(m)) groups[key].push_back(&m);
    else groups.try_emplace(key);
  }
  for (const auto& [kinds, members] : groups) {
    VolumeGroup g;
    g.volumes = kinds;
    g.methods = members.size();
    std::vector<CostPoint> pts;
    for (const MethodOverall* m : members) pts.push_back({*m->ns_per_test, m->fi_rate});
    for (const std::size_t i : pareto_front(pts)) {
      const MethodOverall& m = *members[i];
      g.front.push_back({m.method, m.claim, *m.ns_per_test, m.fi_rate, m.fi_low, m.fi_high});
    }
    s.cheapest.push_back(std::move(g));
  }
  std::stable_sort(s.cheapest.begin(), s.cheapest.end(), [](const VolumeGroup& a, const VolumeGroup& b) {
    std::vector<int> ra, rb;
    for (const auto& k : a.volumes) ra.push_back(kind_rank(k));
    for (const auto& k : b.volumes) rb.push_back(kind_rank(k));
    return ra < rb;
  });
  return s;
}

void print_summary(const Summary& s, std::ostream& out) {
  out << fmt::format("\n== summary: seed {}, {} famil{} ({}), {} method{}\n", s.seed, s.families.size(),
                     s.families.size() == 1 ? "y" : "ies", show::join(s.families, ", "), s.methods.size(),
                     s.methods.size() == 1 ? "" : "s");
  if (s.broken.empty()) {
    out << (s.faults.empty() ? "every claim held\n" : "no claim was refuted (the faulted methods' only up to their faults)\n");
  } else {
    out << fmt::format("claims refuted: {} of {} method{}\n", s.broken.size(), s.methods.size(), s.methods.size() == 1 ? "" : "s");
    for (const BrokenClaim& b : s.broken) {
      std::vector<std::string> where;
      for (const FamilyBreak& f : b.families) where.push_back(f.family);
      out << fmt::format("  {} ({}, claims {}): {} case{} on {}\n", b.method, b.origin, b.claim, b.violations,
                         b.violations == 1 ? "" : "s", show::join(where, ", "));
      for (const FamilyBreak& f : b.families) {
        out << fmt::format("    {}: {} case{}{}", f.family, f.violations, f.violations == 1 ? "" : "s",
                           f.float_exact_violations ? fmt::format(" ({} float-exact)", f.float_exact_violations) : "");
        if (!f.corpus_ids.empty()) out << "; corpus " << show::join(f.corpus_ids, ", ");
        else out << "; no corpus case recorded (--no-corpus)";
        out << "\n";
        if (!f.reproduce.empty()) out << "      first: " << f.reproduce << "\n";
      }
    }
  }
  if (!s.faults.empty()) {
    out << fmt::format("faults: {} (a faulted method's counts stop at its fault; it is not on the fronts below)\n", s.faults.size());
    for (const FaultLine& f : s.faults) {
      out << fmt::format("  {} on {}{}: {}\n", f.method, f.family,
                         f.index ? fmt::format(", case {}", *f.index) : std::string(", while timed"), f.problem);
      if (!f.reproduce.empty()) out << "      reproduce: " << f.reproduce << "\n";
    }
  }
  if (s.interrupted) out << "interrupted: the counts are over the cases judged before the run was stopped\n";
  out << "cheapest method for each level of accuracy (a claim made and held; false intersects / truly outside volumes over every "
         "family; cost: median ns/test over families, set-up hoisted):\n";
  for (const VolumeGroup& g : s.cheapest) {
    const std::string kinds = show::join(g.volumes, " + ");
    if (g.front.empty()) {
      out << fmt::format("  {}: no method whose claim held was timed on truly outside volumes\n", kinds);
      continue;
    }
    out << fmt::format("  {} ({} method{} compared):\n", kinds, g.methods, g.methods == 1 ? "" : "s");
    for (const FrontStep& f : g.front)
      out << fmt::format("    {:>7} ns/test  false intersects {} (95% {}-{})  {} ({})\n", show::nanoseconds(f.ns_per_test),
                         show::percent(f.fi_rate), show::percent(f.fi_low), show::percent(f.fi_high), f.method, f.claim);
  }
}

}  // namespace cullproof::report

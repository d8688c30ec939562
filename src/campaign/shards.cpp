// A run split over machines: a shard's result read back from its JSON, and the shards of one run
// merged into the result one process would have given (campaign.hpp: merge_shards).
#include "cullproof/campaign/campaign.hpp"

#include "campaign_internal.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/io/files.hpp"
#include "cullproof/io/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

namespace cullproof {

namespace {

using json = nlohmann::json;

// A field of `o`, checked: std::invalid_argument naming where it is and what it should be.
const json& field(const json& o, const char* key, const std::string& where) {
  if (!o.is_object()) throw std::invalid_argument(where + ": not a JSON object");
  const auto f = o.find(key);
  if (f == o.end()) throw std::invalid_argument(fmt::format("{}: no \"{}\"", where, key));
  return *f;
}
std::uint64_t count_of(const json& o, const char* key, const std::string& where) {
  const json& f = field(o, key, where);
  if (!f.is_number_unsigned() && !(f.is_number_integer() && f.get<std::int64_t>() >= 0))
    throw std::invalid_argument(fmt::format("{}: \"{}\" is {}, not a count", where, key, f.dump()));
  return f.get<std::uint64_t>();
}
std::string text_of(const json& o, const char* key, const std::string& where) {
  const json& f = field(o, key, where);
  if (!f.is_string()) throw std::invalid_argument(fmt::format("{}: \"{}\" is {}, not a string", where, key, f.dump()));
  return f.get<std::string>();
}
bool flag_of(const json& o, const char* key, const std::string& where) {
  const json& f = field(o, key, where);
  if (!f.is_boolean()) throw std::invalid_argument(fmt::format("{}: \"{}\" is {}, not true or false", where, key, f.dump()));
  return f.get<bool>();
}
// A number, or one that is not finite by its name ("inf", and "nan" where `nan` allows it: JSON has
// neither), as to_json writes a shard's distances and ranks; else std::invalid_argument saying it
// is not `what`.
double number_or_name(const json& x, const std::string& where, const char* key, const char* what, bool nan) {
  if (x.is_number()) return x.get<double>();
  if (x == "inf") return std::numeric_limits<double>::infinity();
  if (nan && x == "nan") return std::numeric_limits<double>::quiet_NaN();
  throw std::invalid_argument(fmt::format("{}: \"{}\" holds {}, not {}", where, key, x.dump(), what));
}
// A number or null (NaN).
double number_or_nan(const json& o, const char* key, const std::string& where) {
  const json& f = field(o, key, where);
  if (f.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!f.is_number()) throw std::invalid_argument(fmt::format("{}: \"{}\" is {}, not a number", where, key, f.dump()));
  return f.get<double>();
}
std::vector<std::string> texts_of(const json& o, const char* key, const std::string& where) {
  const json& f = field(o, key, where);
  std::vector<std::string> out;
  if (!f.is_array()) throw std::invalid_argument(fmt::format("{}: \"{}\" is not an array", where, key));
  for (const json& x : f) {
    if (!x.is_string()) throw std::invalid_argument(fmt::format("{}: \"{}\" holds {}, not a string", where, key, x.dump()));
    out.push_back(x.get<std::string>());
  }
  return out;
}

unsigned kinds_of(const json& o, const char* key, const std::string& where) {
  unsigned bits = 0;
  for (const std::string& name : texts_of(o, key, where)) {
    bool known = false;
    for (unsigned k : {kPointKind, kSphereKind, kAabbKind, kObbKind})
      if (name == volume_kind_name(k)) {
        bits |= k;
        known = true;
      }
    if (!known) throw std::invalid_argument(fmt::format("{}: \"{}\" names '{}', not a volume kind", where, key, name));
  }
  return bits;
}

Origin origin_of(const std::string& s, const std::string& where) {
  for (Origin o : {Origin::published, Origin::own, Origin::user})
    if (s == to_string(o)) return o;
  throw std::invalid_argument(fmt::format("{}: \"origin\" is '{}', not published, own or user", where, s));
}

ErrorClass error_class_of(const std::string& s, const std::string& where) {
  for (ErrorClass e : {ErrorClass::false_reject, ErrorClass::false_inside, ErrorClass::false_intersect, ErrorClass::under_inside})
    if (s == to_string(e)) return e;
  throw std::invalid_argument(fmt::format("{}: \"class\" is '{}', not an error class", where, s));
}

gen::Distribution distribution_of(const std::string& name, const std::string& where) {
  std::vector<gen::Distribution> d;
  try {
    d = gen::parse_distributions(name);
  } catch (const std::exception&) {
  }
  if (d.size() != 1) throw std::invalid_argument(fmt::format("{}: '{}' is not a distribution", where, name));
  return d[0];
}

// A method's counts and a distribution's, by their JSON names: read and summed alike.
template <class Of>
struct Count {
  const char* name;
  std::uint64_t Of::*member;
};
using MethodCount = Count<MethodStats>;
const MethodCount kMethodCounts[] = {
    {"cases", &MethodStats::cases},
    {"false_reject", &MethodStats::false_reject},
    {"false_inside", &MethodStats::false_inside},
    {"false_intersect", &MethodStats::false_intersect},
    {"under_inside", &MethodStats::under_inside},
    {"claim_violations", &MethodStats::claim_violations},
    {"float_exact_violations", &MethodStats::float_exact_violations},
    {"truth_inside_three_way", &MethodStats::truth_inside_three_way},
};
const MethodCount kTruthCounts[] = {  // under "truth"
    {"outside", &MethodStats::truth_outside},
    {"intersecting", &MethodStats::truth_intersecting},
    {"inside", &MethodStats::truth_inside},
};
using DistributionCount = Count<DistributionResult>;
const DistributionCount kDistributionCounts[] = {
    {"cases", &DistributionResult::cases},
    {"cases_asked", &DistributionResult::cases_asked},
    {"oracle_calls", &DistributionResult::oracle_calls},
    {"oracle_fallbacks", &DistributionResult::oracle_fallbacks},
    {"float_exact_cases", &DistributionResult::float_exact_cases},
};

MethodStats method_of(const json& m, const std::string& where) {
  MethodStats s;
  s.method = text_of(m, "method", where);
  const std::string at = where + ", method " + s.method;
  const json& program = field(m, "program", at);
  s.program = program.is_string() ? program.get<std::string>() : std::string();
  try {
    s.claim = claim_from_string(text_of(m, "claim", at));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(at + ": " + e.what());
  }
  s.origin = origin_of(text_of(m, "origin", at), at);
  s.three_way = flag_of(m, "three_way", at);
  s.two_way_kinds = kinds_of(m, "two_way_volumes", at);
  s.volumes = kinds_of(m, "volumes", at);
  for (const MethodCount& c : kMethodCounts) s.*c.member = count_of(m, c.name, at);
  const json& truth = field(m, "truth", at);
  for (const MethodCount& c : kTruthCounts) s.*c.member = count_of(truth, c.name, at + ", truth");
  if (!field(m, "first_violation", at).is_null()) {
    s.first_violation = count_of(m, "first_violation", at);
    s.first_violation_reproduce = text_of(m, "first_violation_reproduce", at);
  }
  if (m.contains("fi_distances")) {
    const json& d = m["fi_distances"];
    if (!d.is_array()) throw std::invalid_argument(at + ": \"fi_distances\" is not an array");
    for (const json& x : d) s.fi_distance.push_back(number_or_name(x, at, "fi_distances", "a distance", /*nan=*/true));
    if (s.fi_distance.size() != s.false_intersect)
      throw std::invalid_argument(fmt::format("{}: {} false-intersect distances for {} false intersects", at,
                                              s.fi_distance.size(), s.false_intersect));
  }
  s.ns_per_test = number_or_nan(m, "ns_per_test", at);
  s.ns_setup_per_frame = number_or_nan(m, "ns_setup_per_frame", at);
  s.ns_per_test_own = number_or_nan(m, "ns_per_test_own", at);
  s.timed_batch = flag_of(m, "timed_batch", at);
  s.corpus_written = texts_of(m, "corpus_written", at);
  s.violation_ids = texts_of(m, "violation_ids", at);
  if (m.contains("corpus_candidates")) {
    const json& cs = m["corpus_candidates"];
    if (!cs.is_array()) throw std::invalid_argument(at + ": \"corpus_candidates\" is not an array");
    for (const json& c : cs) {
      const std::string here = at + ", corpus candidate";
      CorpusCandidate k;
      k.index = count_of(c, "index", here);
      k.error = error_class_of(text_of(c, "class", here), here);
      k.violation = flag_of(c, "violation", here);
      k.rank = number_or_name(field(c, "rank", here), here, "rank", "a number", /*nan=*/false);
      k.id = text_of(c, "id", here);
      k.file = text_of(c, "file", here);
      k.violates = flag_of(c, "violates_claim", here);
      k.text = text_of(c, "text", here);
      const std::filesystem::path f(k.file);
      if (!k.file.empty() && (f.is_absolute() || std::distance(f.begin(), f.end()) != 3 ||
                              std::any_of(f.begin(), f.end(), [](const std::filesystem::path& x) { return x == ".." || x == "."; })))
        throw std::invalid_argument(fmt::format("{}: \"file\" is '{}', not <method>/<distribution>/<name>", here, k.file));
      s.corpus_candidates.push_back(std::move(k));
    }
  }
  const json& fault = field(m, "fault", at);
  if (!fault.is_null()) {
    MethodFault f;
    f.method = s.method;
    f.problem = text_of(fault, "problem", at + ", fault");
    if (!field(fault, "index", at + ", fault").is_null()) {
      f.index = count_of(fault, "index", at + ", fault");
      f.reproduce = text_of(fault, "reproduce", at + ", fault");
    }
    if (const json& saved = field(fault, "saved", at + ", fault"); saved.is_string()) f.saved = saved.get<std::string>();
    if (fault.contains("where")) f.where = text_of(fault, "where", at + ", fault");
    f.failing_case = field(fault, "case", at + ", fault");
    s.fault = std::move(f);
  }
  return s;
}

double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2.0;
}

void add_unique(std::vector<std::string>& to, const std::vector<std::string>& from) {
  for (const std::string& x : from)
    if (std::find(to.begin(), to.end(), x) == to.end()) to.push_back(x);
}

// Of the shards' corpus candidates (in case order), those one run records, in the order it writes
// them (campaign.cpp: tally): the first `per_class` errors of each class the claim allows, by case
// index, then per class the violations keep_farthest keeps.
std::vector<CorpusCandidate> chosen_records(std::vector<CorpusCandidate> all, int per_class) {
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
  std::vector<CorpusCandidate> out;
  std::map<ErrorClass, int> kept;
  std::map<ErrorClass, std::vector<CorpusCandidate>> violating;
  for (CorpusCandidate& c : all) {
    if (c.violation)
      violating[c.error].push_back(std::move(c));
    else if (kept[c.error]++ < per_class)
      out.push_back(std::move(c));
  }
  for (auto& [cls, v] : violating) {
    detail::keep_farthest(v, [](const CorpusCandidate& x) { return x.rank; });
    for (CorpusCandidate& c : v) out.push_back(std::move(c));
  }
  return out;
}

// One method's statistics over the shards of a distribution (in shard order): what one run would
// have counted.
MethodStats merge_method(const std::vector<const MethodStats*>& parts, const std::vector<std::uint64_t>& first_case,
                         int corpus_per_class) {
  // The earliest fault on a case: past it, one run asks the method nothing more.
  std::optional<std::size_t> faulted;
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (parts[p]->fault && parts[p]->fault->index &&
        (!faulted || *parts[p]->fault->index < *parts[*faulted]->fault->index))
      faulted = p;
  MethodStats m = *parts.front();
  for (const MethodCount& c : kMethodCounts) m.*c.member = 0;
  for (const MethodCount& c : kTruthCounts) m.*c.member = 0;
  m.first_violation.reset();
  m.first_violation_reproduce.clear();
  m.fi_distance.clear();
  m.corpus_written.clear();
  m.violation_ids.clear();
  m.fault.reset();
  m.corpus_candidates.clear();
  std::vector<CorpusCandidate> candidates;
  std::vector<double> ns, setup, own;
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const MethodStats& s = *parts[p];
    if (faulted && first_case[p] > *parts[*faulted]->fault->index) continue;  // cases one run would not ask
    for (const MethodCount& c : kMethodCounts) m.*c.member += s.*c.member;
    for (const MethodCount& c : kTruthCounts) m.*c.member += s.*c.member;
    if (s.first_violation && (!m.first_violation || *s.first_violation < *m.first_violation)) {
      m.first_violation = s.first_violation;
      m.first_violation_reproduce = s.first_violation_reproduce;
    }
    m.fi_distance.insert(m.fi_distance.end(), s.fi_distance.begin(), s.fi_distance.end());
    add_unique(m.corpus_written, s.corpus_written);
    add_unique(m.violation_ids, s.violation_ids);
    candidates.insert(candidates.end(), s.corpus_candidates.begin(), s.corpus_candidates.end());
    if (!m.fault && s.fault && !s.fault->index) m.fault = s.fault;  // while timed: the counts stand
    ns.push_back(s.ns_per_test);
    setup.push_back(s.ns_setup_per_frame);
    own.push_back(s.ns_per_test_own);
    m.timed_batch = m.timed_batch || s.timed_batch;
  }
  if (faulted) m.fault = parts[*faulted]->fault;
  const bool timed = !m.fault;  // one run does not time a method that faulted
  m.ns_per_test = timed ? median(ns) : std::numeric_limits<double>::quiet_NaN();
  m.ns_setup_per_frame = timed ? median(setup) : std::numeric_limits<double>::quiet_NaN();
  m.ns_per_test_own = timed ? median(own) : std::numeric_limits<double>::quiet_NaN();
  std::sort(m.fi_distance.begin(), m.fi_distance.end());
  m.corpus_candidates = chosen_records(std::move(candidates), corpus_per_class);
  return m;
}

// The first key at which two identities differ, as "\"key\" is A there, B here".
std::string difference(const json& a, const json& b) {
  for (const auto& [key, value] : a.items())
    if (!b.contains(key) || b[key] != value)
      return fmt::format("\"{}\" is {} there, {} here", key, value.dump(), b.contains(key) ? b[key].dump() : "absent");
  for (const auto& [key, value] : b.items())
    if (!a.contains(key)) return fmt::format("\"{}\" is absent there, {} here", key, value.dump());
  return "they are equal";
}

}  // namespace

VerifyResult from_json(const json& j, const std::string& where) {
  VerifyResult r;
  r.options.seed = count_of(j, "seed", where);
  r.options.frame_size = count_of(j, "frame_size", where);
  r.options.timing_frames = int(count_of(j, "timing_frames", where));
  r.wall_seconds = number_or_nan(j, "wall_seconds", where);
  r.interrupted = flag_of(j, "interrupted", where);
  r.options.distributions.clear();
  if (j.contains("run")) {
    const json& run = j["run"];
    r.options.cases = count_of(run, "cases_per_distribution", where + ", run");
    r.options.timing = flag_of(run, "timing", where + ", run");
    r.options.corpus_per_class = int(count_of(run, "corpus_per_class", where + ", run"));
    r.options.shrink_budget = int(count_of(run, "shrink_budget", where + ", run"));
    for (const std::string& d : texts_of(run, "distributions", where + ", run"))
      r.options.distributions.push_back(distribution_of(d, where + ", run"));
  } else {
    r.options.cases = count_of(j, "cases_per_distribution", where);
  }
  if (j.contains("shard")) {
    const json& s = j["shard"];
    r.options.shard = Shard{count_of(s, "index", where + ", shard"), count_of(s, "count", where + ", shard")};
    if (r.options.shard->count == 0 || r.options.shard->index >= r.options.shard->count)
      throw std::invalid_argument(fmt::format("{}: shard {}/{} (the index must be below the count)", where,
                                              r.options.shard->index, r.options.shard->count));
  }
  const json& ds = field(j, "distributions", where);
  if (!ds.is_array()) throw std::invalid_argument(where + ": \"distributions\" is not an array");
  for (const json& jd : ds) {
    DistributionResult d;
    d.distribution = distribution_of(text_of(jd, "distribution", where), where);
    const std::string at = where + ", distribution " + std::string(gen::to_string(d.distribution));
    d.first_case = jd.contains("first_case") ? count_of(jd, "first_case", at) : 0;
    for (const DistributionCount& c : kDistributionCounts) d.*c.member = count_of(jd, c.name, at);
    d.interrupted = flag_of(jd, "interrupted", at);
    const json& ms = field(jd, "methods", at);
    if (!ms.is_array()) throw std::invalid_argument(at + ": \"methods\" is not an array");
    for (const json& m : ms) d.methods.push_back(method_of(m, at));
    if (!j.contains("run")) r.options.distributions.push_back(d.distribution);
    r.distributions.push_back(std::move(d));
  }
  return r;
}

MergedRun merge_shards(const std::vector<ShardFile>& files, bool partial) {
  if (files.empty()) throw std::invalid_argument("no shard to merge");
  const json* identity = nullptr;
  const std::string* identity_file = nullptr;
  std::map<std::uint64_t, std::pair<const ShardFile*, VerifyResult>> shards;
  std::uint64_t count = 0;
  std::vector<std::uint64_t> interrupted;
  for (const ShardFile& f : files) {
    if (!f.json.is_object() || !f.json.contains("shard") || !f.json.contains("run"))
      throw std::invalid_argument(f.file + ": not a shard's result (cullproof verify --shard K/N --json FILE writes one)");
    if (!identity) {
      identity = &f.json["run"];
      identity_file = &f.file;
      count = count_of(*identity, "shards", f.file + ", run");
    } else if (f.json["run"] != *identity) {
      throw std::invalid_argument(fmt::format("{}: a shard of another run than {} ({})", f.file, *identity_file,
                                              difference(*identity, f.json["run"])));
    }
    VerifyResult r = from_json(f.json, f.file);
    const Shard s = *r.options.shard;
    if (s.count != count)
      throw std::invalid_argument(fmt::format("{}: shard {}/{} of a run of {} shards", f.file, s.index, s.count, count));
    if (const auto twice = shards.find(s.index); twice != shards.end())
      throw std::invalid_argument(fmt::format("{}: shard {}/{} given twice (also {})", f.file, s.index, count, twice->second.first->file));
    if (r.interrupted || r.distributions.size() != r.options.distributions.size()) {
      if (!partial)
        throw std::invalid_argument(fmt::format(
            "{}: shard {}/{} was interrupted: its result is incomplete (run the shard again; --partial leaves it out)", f.file,
            s.index, count));
      interrupted.push_back(s.index);
      continue;
    }
    shards.emplace(s.index, std::make_pair(&f, std::move(r)));
  }
  MergedRun out;
  out.shards = count;
  for (std::uint64_t k = 0; k < count; ++k)
    if (!shards.count(k)) out.missing.push_back(k);
  if (!out.missing.empty() && !partial) {
    std::string list;
    for (std::uint64_t k : out.missing) list += (list.empty() ? "" : ", ") + std::to_string(k);
    throw std::invalid_argument(fmt::format("missing shards: {} of {} (--partial merges those given and marks the result partial)",
                                            list, count));
  }
  if (shards.empty()) throw std::invalid_argument("no complete shard to merge");

  VerifyResult& r = out.result;
  const VerifyResult& first = shards.begin()->second.second;
  r.options = first.options;
  r.options.shard.reset();
  r.wall_seconds = 0.0;
  for (const auto& [k, s] : shards) {
    r.wall_seconds += s.second.wall_seconds;
    out.longest_shard_seconds = std::max(out.longest_shard_seconds, s.second.wall_seconds);
  }
  for (std::size_t d = 0; d < first.distributions.size(); ++d) {
    DistributionResult m;
    m.distribution = first.distributions[d].distribution;
    std::vector<std::uint64_t> first_case;
    for (const auto& [k, s] : shards) {
      const DistributionResult& part = s.second.distributions[d];
      const std::string where = fmt::format("{}, distribution {}", s.first->file, gen::to_string(part.distribution));
      if (part.distribution != m.distribution || part.methods.size() != first.distributions[d].methods.size())
        throw std::invalid_argument(where + ": not the distribution or methods of the other shards");
      for (const DistributionCount& c : kDistributionCounts) m.*c.member += part.*c.member;
      first_case.push_back(part.first_case);
    }
    for (std::size_t k = 0; k < first.distributions[d].methods.size(); ++k) {
      std::vector<const MethodStats*> parts;
      for (const auto& [i, s] : shards) {
        const MethodStats& p = s.second.distributions[d].methods[k];
        if (p.method != first.distributions[d].methods[k].method)
          throw std::invalid_argument(fmt::format("{}: method {} is '{}' there, '{}' in the first shard", s.first->file, k,
                                                  p.method, first.distributions[d].methods[k].method));
        parts.push_back(&p);
      }
      m.methods.push_back(merge_method(parts, first_case, first.options.corpus_per_class));
    }
    r.distributions.push_back(std::move(m));
  }
  r.options.corpus.reset();
  for (std::uint64_t k : interrupted)
    if (std::find(out.missing.begin(), out.missing.end(), k) == out.missing.end()) out.missing.push_back(k);
  std::sort(out.missing.begin(), out.missing.end());
  return out;
}

void write_merged_corpus(VerifyResult& merged, const std::filesystem::path& dir) {
  // The geometry a record's text holds (its frustum and volume as the case format writes them).
  const auto geometry = [](std::string_view text, const std::filesystem::path& file) {
    const CorpusEntry e = parse_corpus_entry(text, file);
    return format_frustum(e.c.frustum) + format_volume(e.c.volume);
  };
  // First every name checked, so that a refusal leaves the folder as it was: a name taken (by an
  // earlier run, or by an earlier record of this one) must hold the same case, found twice.
  std::map<std::string, std::string> taken;  // file -> its geometry
  std::set<std::string> there_before;          // files the folder held already
  for (const DistributionResult& d : merged.distributions)
    for (const MethodStats& m : d.methods)
      for (const CorpusCandidate& c : m.corpus_candidates) {
        if (c.file.empty()) continue;
        const std::filesystem::path file = dir / c.file;
        std::string mine;
        try {
          mine = geometry(c.text, file);
        } catch (const std::exception& e) {
          throw std::invalid_argument(fmt::format("a shard's record of case {} ({}) is not a corpus record: {}", c.index, c.file, e.what()));
        }
        auto it = taken.find(c.file);
        if (it == taken.end() && std::filesystem::exists(file)) {
          std::string there;
          try {
            there = geometry(read_file_limited(file, kMaxCaseFileBytes, "a corpus record"), file);
          } catch (const std::exception& e) {
            throw std::runtime_error(fmt::format("{}: the merged run's record of case {} goes here, and the file there is "
                                                 "not a readable record ({})", file.string(), c.index, e.what()));
          }
          it = taken.emplace(c.file, std::move(there)).first;
          there_before.insert(c.file);
        }
        if (it == taken.end())
          taken.emplace(c.file, std::move(mine));
        else if (it->second != mine)
          throw std::runtime_error(fmt::format("{}: holds another case than the merged run's record of case {} under the "
                                               "same name (two different records under one name; nothing was written)",
                                               file.string(), c.index));
      }
  std::set<std::string> written_now;
  for (DistributionResult& d : merged.distributions)
    for (MethodStats& m : d.methods) {
      m.corpus_written.clear();
      m.violation_ids.clear();
      for (const CorpusCandidate& c : m.corpus_candidates) {
        if (c.file.empty()) continue;  // its shrunk case faulted: no record (the method's fault)
        if (!there_before.count(c.file) && !written_now.count(c.file)) {
          const std::filesystem::path file = dir / c.file;
          try {
            write_file_atomic(file, c.text, /*overwrite=*/false);
            written_now.insert(c.file);
            m.corpus_written.push_back(c.id);
          } catch (const std::runtime_error&) {
            // Written meanwhile by another writer: kept if it holds this case, as one run keeps it.
            if (!std::filesystem::exists(file)) throw;
            if (geometry(read_file_limited(file, kMaxCaseFileBytes, "a corpus record"), file) != taken.at(c.file))
              throw std::runtime_error(fmt::format("{}: written meanwhile with another case than the merged run's record of "
                                                   "case {}", file.string(), c.index));
            there_before.insert(c.file);
          }
        }
        if (c.violation && c.violates && std::find(m.violation_ids.begin(), m.violation_ids.end(), c.id) == m.violation_ids.end())
          m.violation_ids.push_back(c.id);
      }
    }
  merged.options.corpus = dir;
}

}  // namespace cullproof

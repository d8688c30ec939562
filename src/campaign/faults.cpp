// The case that made a method fault, saved, and the report of the fault (campaign_internal.hpp).
#include "campaign_internal.hpp"

#include "cullproof/io/case_io.hpp"

#include <fmt/format.h>

namespace cullproof {

std::string MethodFault::message(gen::Distribution d, std::uint64_t seed) const {
  if (!index)
    return fmt::format("method '{}' faulted while it was timed on distribution {} (seed {}); its counts stand\n  {}", method,
                       gen::to_string(d), seed, problem);
  return fmt::format("method '{}' faulted on case {} of distribution {} (seed {}); it was not asked again there, its "
                     "counts are over the cases before\n  {}\n  reproduce: {}\n  case {}\n  {}",
                     method, *index, gen::to_string(d), seed, problem, reproduce, where, failing_case.dump());
}

namespace detail {

MethodFault make_fault(const VerifyOptions& opt, const Method& m, gen::Distribution d, std::uint64_t index, const GenCase& g,
                       const std::string& problem, const PathCase* path) {
  MethodFault f;
  f.method = m.name;
  f.problem = problem;
  f.index = index;
  f.reproduce = reproduce_command(opt.seed, d, index, m);
  Case c;
  c.id = fmt::format("{}-fault-{}", m.name, geometry_hash(g.frustum, g.volume));
  c.frustum = g.frustum;
  c.volume = g.volume;
  c.note = problem;
  c.extra["method"] = m.name;
  c.extra["fault"] = problem;
  c.extra["distribution"] = std::string(gen::to_string(d));
  c.extra["seed"] = opt.seed;
  c.extra["index"] = index;
  c.extra["reproduce"] = f.reproduce;
  if (path) c.extra["path"] = to_json(*path);
  std::optional<std::filesystem::path> dir = opt.faults;
  if (!dir && opt.corpus) dir = *opt.corpus / "faults";
  f.where = "not saved (no corpus folder)";
  if (dir) {
    const auto file = *dir / m.name / fmt::format("{}.json", geometry_hash(g.frustum, g.volume));
    try {
      if (!std::filesystem::exists(file)) write_case_file(file, c, /*overwrite=*/false);
      f.saved = file;
      f.where = "saved to " + file.string();
    } catch (const std::exception& e) {
      f.where = std::string("could not be saved: ") + e.what();
    }
  }
  f.failing_case = nlohmann::json::parse(format_case(c));
  return f;
}

MethodFault timing_fault(const Method& m, const std::string& problem) {
  MethodFault f;
  f.method = m.name;
  f.problem = problem;
  f.where = "not saved (a timing frame, not a case judged)";
  return f;
}

}  // namespace detail
}  // namespace cullproof

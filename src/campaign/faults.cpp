// The case that made a method fault, saved and named in the MethodFault the run stops with
// (campaign_internal.hpp).
#include "campaign_internal.hpp"

#include "cullproof/io/case_io.hpp"

#include <fmt/format.h>

namespace cullproof::detail {

[[noreturn]] void fault(const VerifyOptions& opt, const Method& m, gen::Distribution d, std::uint64_t index,
                        const GenCase& g, const std::string& problem, const PathCase* path) {
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
  c.extra["reproduce"] = reproduce_command(opt.seed, d, index, m);
  if (path) c.extra["path"] = to_json(*path);
  std::optional<std::filesystem::path> dir = opt.faults;
  if (!dir && opt.corpus) dir = *opt.corpus / "faults";
  std::optional<std::filesystem::path> saved;
  std::string where = "not saved (no corpus folder)";
  if (dir) {
    const auto file = *dir / m.name / fmt::format("{}.json", geometry_hash(g.frustum, g.volume));
    try {
      if (!std::filesystem::exists(file)) write_case_file(file, c, /*overwrite=*/false);
      saved = file;
      where = "saved to " + file.string();
    } catch (const std::exception& e) {
      where = std::string("could not be saved: ") + e.what();
    }
  }
  const std::string line = format_case(c);
  const nlohmann::json j = nlohmann::json::parse(line);
  throw MethodFault(fmt::format("{}\n  on case {} of distribution {} (seed {}); the run is incomplete, no results are reported\n"
                                "  reproduce: {}\n  case {}\n  {}",
                                problem, index, gen::to_string(d), opt.seed, reproduce_command(opt.seed, d, index, m),
                                where, line),
                    m.name, j, saved);
}

}  // namespace cullproof::detail

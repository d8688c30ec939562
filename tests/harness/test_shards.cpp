// A run split into shards and merged equals the run in one process: the same counts, truths,
// refutations, first violations, faults and false-intersect distances, for several shard counts,
// on framed families, camera paths (stateful methods replaying each path) and a method that
// faults part way. The merge refuses what would make a total silently smaller or wrong.
#include "harness_files.hpp"
#include "cullproof/campaign/campaign.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>

namespace cullproof {
namespace {

using test::files_under;

using V = Visibility;

// A user's culler that faults on the first box of the run whose centre lies above y = 40, and
// answers intersecting otherwise (conservative, and refuted by nothing).
Method faulting() {
  MethodInfo info;
  info.name = "faults-high-up";
  info.claim = Claim::conservative;
  return make_method(info, [](const CaseFrustum& f) { return f.planes; },
                     [](const Frustum&, const Aabb& b) -> Visibility {
                       if (b.min.y + b.max.y > 80.0f) throw std::domain_error("a box above y = 40");
                       return V::intersecting;
                     });
}

// A user's culler that claims exact, rejects every box right of x = 0 and calls the others
// intersecting: claim violations of two classes at every distance from their allowance, so that the
// corpus's choice of the farthest is put to the test.
Method rejects_right() {
  MethodInfo info;
  info.name = "rejects-right";
  info.claim = Claim::exact;
  info.tolerance = 1e-6;  // an allowance to be beyond, by different amounts
  return make_method(info, [](const CaseFrustum& f) { return f.planes; },
                     [](const Frustum&, const Aabb& b) -> Visibility {
                       return b.min.x + b.max.x > 0.0f ? V::outside : V::intersecting;
                     });
}

std::vector<Method> methods() {
  std::vector<Method> ms = builtin_methods();
  ms.push_back(faulting());
  return ms;
}

VerifyOptions run_options() {
  VerifyOptions o;
  o.cases = 700;
  o.seed = 3;
  o.distributions = {gen::Distribution::uniform, gen::Distribution::camera_path, gen::Distribution::contact,
                     gen::Distribution::ulp, gen::Distribution::far_offset};
  o.threads = 2;
  o.progress = false;
  o.timing = false;
  return o;
}

// What must be equal between one run and its merged shards, method by method.
// (A result read back from JSON other than a shard's has no distances in full: `distances` false.)
void expect_same(const VerifyResult& one, const VerifyResult& merged, const std::string& what, bool distances = true) {
  ASSERT_EQ(one.distributions.size(), merged.distributions.size()) << what;
  for (std::size_t d = 0; d < one.distributions.size(); ++d) {
    const DistributionResult &a = one.distributions[d], &b = merged.distributions[d];
    const std::string at = what + ", " + std::string(gen::to_string(a.distribution));
    EXPECT_EQ(a.cases, b.cases) << at;
    EXPECT_EQ(a.cases_asked, b.cases_asked) << at;
    EXPECT_EQ(a.float_exact_cases, b.float_exact_cases) << at;
    ASSERT_EQ(a.methods.size(), b.methods.size()) << at;
    for (std::size_t k = 0; k < a.methods.size(); ++k) {
      const MethodStats &x = a.methods[k], &y = b.methods[k];
      const std::string m = at + ", " + x.method;
      EXPECT_EQ(x.method, y.method) << m;
      EXPECT_EQ(x.cases, y.cases) << m;
      EXPECT_EQ(x.truth_outside, y.truth_outside) << m;
      EXPECT_EQ(x.truth_intersecting, y.truth_intersecting) << m;
      EXPECT_EQ(x.truth_inside, y.truth_inside) << m;
      EXPECT_EQ(x.truth_inside_three_way, y.truth_inside_three_way) << m;
      EXPECT_EQ(x.false_reject, y.false_reject) << m;
      EXPECT_EQ(x.false_inside, y.false_inside) << m;
      EXPECT_EQ(x.false_intersect, y.false_intersect) << m;
      EXPECT_EQ(x.under_inside, y.under_inside) << m;
      EXPECT_EQ(x.claim_violations, y.claim_violations) << m;
      EXPECT_EQ(x.float_exact_violations, y.float_exact_violations) << m;
      EXPECT_EQ(x.first_violation, y.first_violation) << m;
      EXPECT_EQ(x.first_violation_reproduce, y.first_violation_reproduce) << m;
      std::vector<double> fx = x.fi_distance;
      std::sort(fx.begin(), fx.end());
      if (distances) {
        EXPECT_EQ(fx, y.fi_distance) << m;
      }
      ASSERT_EQ(x.fault.has_value(), y.fault.has_value()) << m;
      if (x.fault) {
        EXPECT_EQ(x.fault->index, y.fault->index) << m;
        EXPECT_EQ(x.fault->problem, y.fault->problem) << m;
        EXPECT_EQ(x.fault->reproduce, y.fault->reproduce) << m;
      }
    }
  }
}

// Shards 0..n-1 of the run, each through its JSON (as files carry them); with a corpus, each shard
// writes its own (<corpus>-shard-K).
std::vector<ShardFile> shards_of(const VerifyOptions& o, std::uint64_t n, const std::vector<Method>& ms = methods()) {
  std::vector<ShardFile> files;
  for (std::uint64_t k = 0; k < n; ++k) {
    VerifyOptions s = o;
    s.shard = Shard{k, n};
    if (o.corpus) s.corpus = o.corpus->string() + "-shard-" + std::to_string(k);
    files.push_back({"shard-" + std::to_string(k) + ".json", nlohmann::json::parse(to_json(run_verify(s, ms)).dump())});
  }
  return files;
}

TEST(Shards, PartitionEveryCaseOnceInWholeFrames) {
  for (gen::Distribution d : {gen::Distribution::uniform, gen::Distribution::camera_path, gen::Distribution::ulp})
    for (std::uint64_t cases : {1u, 15u, 700u, 1000u})
      for (std::uint64_t n : {1u, 2u, 3u, 7u, 64u}) {
        std::uint64_t next = 0;
        const std::uint64_t unit =
            d == gen::Distribution::camera_path ? gen::kPathFrames * gen::kPathObjects : gen::cases_per_frame(d);
        for (std::uint64_t k = 0; k < n; ++k) {
          const auto [a, b] = shard_cases(d, cases, Shard{k, n});
          EXPECT_EQ(a, next) << gen::to_string(d) << " " << cases << " " << k << "/" << n;
          EXPECT_LE(a, b);
          EXPECT_TRUE(a % unit == 0 || a == cases);
          next = b;
        }
        EXPECT_EQ(next, cases);
      }
  EXPECT_THROW(shard_cases(gen::Distribution::uniform, 10, Shard{3, 3}), std::invalid_argument);
}

TEST(Shards, MergedEqualOneRunForSeveralShardCounts) {
  const VerifyOptions o = run_options();
  const VerifyResult one = run_verify(o, methods());
  // The run has something to compare: refutations, false intersects, a fault part way.
  std::uint64_t refuted = 0, faults = 0;
  for (const auto& d : one.distributions)
    for (const auto& m : d.methods) {
      refuted += m.refuted();
      faults += m.fault && m.fault->index && *m.fault->index > 0;
    }
  ASSERT_GT(refuted, 0u);
  ASSERT_GT(faults, 0u);
  for (std::uint64_t n : {2u, 3u, 7u}) {
    const MergedRun merged = merge_shards(shards_of(o, n), false);
    EXPECT_TRUE(merged.missing.empty());
    expect_same(one, merged.result, std::to_string(n) + " shards");
    // And through the merged JSON, as report --from reads it.
    expect_same(one, from_json(nlohmann::json::parse(to_json(merged.result).dump()), "merged"), "merged JSON", false);
  }
}

struct Scratch {
  std::filesystem::path path = std::filesystem::temp_directory_path() / ("cullproof-shards-" + std::to_string(::getpid()));
  Scratch() { std::filesystem::remove_all(path); }
  ~Scratch() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

TEST(Shards, TheMergedCorpusIsTheOneRunsFileForFile) {
  const Scratch scratch;
  VerifyOptions o = run_options();
  o.distributions = {gen::Distribution::uniform, gen::Distribution::camera_path, gen::Distribution::contact,
                     gen::Distribution::ulp};
  o.corpus_per_class = 2;  // the first two of a class may lie in different shards
  o.corpus = scratch.path / "one";
  o.faults = scratch.path / "faults";
  std::vector<Method> ms = methods();
  ms.push_back(rejects_right());
  const VerifyResult one = run_verify(o, ms);
  const auto reference = files_under(scratch.path / "one");
  // Records of both kinds: errors a claim allows (chosen by index), violations (by rank).
  std::size_t violations = 0, allowed = 0, with_fault = 0;
  for (const auto& [name, bytes] : reference) {
    const auto record = nlohmann::json::parse(bytes);
    (record.value("violates_claim", false) ? violations : allowed)++;
    // The faulting method faults on some recorded cases: named there, and the record written.
    with_fault += record.contains("verdict_faults") && record["verdict_faults"].contains("faults-high-up");
  }
  EXPECT_GT(with_fault, 0u);
  // More violations of a class than are kept, at different distances: the choice of the farthest
  // decides the corpus.
  for (const auto& d : one.distributions)
    for (const auto& m : d.methods)
      if (m.method == "rejects-right") {
        EXPECT_GT(m.claim_violations, 20u) << gen::to_string(d.distribution);
      }
  ASSERT_GT(violations, 0u);
  ASSERT_GT(allowed, 0u);
  ASSERT_GT(reference.size(), 20u);
  for (std::uint64_t n : {3u, 7u}) {
    const std::string what = std::to_string(n) + " shards";
    o.corpus = scratch.path / ("run-of-" + std::to_string(n));
    MergedRun merged = merge_shards(shards_of(o, n, ms), false);
    // The shards' corpora together hold more than the run's: each its own first and farthest.
    std::size_t shard_files = 0;
    for (std::uint64_t k = 0; k < n; ++k)
      shard_files += files_under(o.corpus->string() + "-shard-" + std::to_string(k)).size();
    EXPECT_GT(shard_files, reference.size()) << what;
    const auto merged_dir = scratch.path / ("merged-" + std::to_string(n));
    write_merged_corpus(merged.result, merged_dir);
    const auto files = files_under(merged_dir);
    EXPECT_EQ(files.size(), reference.size()) << what;
    for (const auto& [name, bytes] : reference) {
      const auto f = files.find(name);
      if (f == files.end())
        ADD_FAILURE() << what << ": " << name << " missing from the merged corpus";
      else
        EXPECT_EQ(f->second, bytes) << what << ": " << name << " differs";
    }
    for (const auto& [name, bytes] : files) EXPECT_TRUE(reference.count(name)) << what << ": " << name << " not the one run's";
    for (std::size_t d = 0; d < one.distributions.size(); ++d)
      for (std::size_t k = 0; k < one.distributions[d].methods.size(); ++k) {
        const MethodStats &a = one.distributions[d].methods[k], &b = merged.result.distributions[d].methods[k];
        EXPECT_EQ(a.corpus_written, b.corpus_written) << what << ", " << a.method;
        EXPECT_EQ(a.violation_ids, b.violation_ids) << what << ", " << a.method;
      }
    // Merged again into the same folder: every name is taken, nothing is written or changed.
    write_merged_corpus(merged.result, merged_dir);
    EXPECT_EQ(files_under(merged_dir), files) << what;
    for (const auto& d : merged.result.distributions)
      for (const auto& m : d.methods) EXPECT_TRUE(m.corpus_written.empty()) << what << ", " << m.method;
    // A name holding another case (another record's text under it) is refused before anything is
    // written.
    if (n != 3) continue;
    const auto clash = scratch.path / "clash";
    const auto first = reference.begin(), other = std::next(reference.begin());
    std::filesystem::create_directories((clash / first->first).parent_path());
    std::ofstream(clash / first->first, std::ios::binary) << other->second;
    try {
      write_merged_corpus(merged.result, clash);
      ADD_FAILURE() << "a name holding another case was not refused";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(first->first + ": holds another case than the merged run's record of case"),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(files_under(clash).size(), 1u) << "nothing written after a refusal";
  }
}

std::string refusal(const std::vector<ShardFile>& files, bool partial = false) {
  try {
    merge_shards(files, partial);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(Shards, TheMergeRefusesWhatWouldMakeTheTotalWrong) {
  VerifyOptions o = run_options();
  o.cases = 64;
  o.distributions = {gen::Distribution::uniform};
  const std::vector<ShardFile> all = shards_of(o, 3);
  // A shard twice.
  EXPECT_NE(refusal({all[0], all[1], all[2], {"again.json", all[1].json}}).find("again.json: shard 1/3 given twice"),
            std::string::npos);
  // A missing shard; --partial merges the others and says which is missing.
  EXPECT_NE(refusal({all[0], all[2]}).find("missing shards: 1 of 3"), std::string::npos);
  const MergedRun partial = merge_shards({all[0], all[2]}, true);
  EXPECT_EQ(partial.missing, std::vector<std::uint64_t>{1});
  EXPECT_LT(partial.result.distributions[0].cases, 64u);
  // A shard of another run.
  ShardFile other = all[2];
  other.json["run"]["seed"] = 4;
  other.file = "other.json";
  EXPECT_NE(refusal({all[0], all[1], other}).find("other.json: a shard of another run than shard-0.json (\"seed\" is 3 there, 4 here)"),
            std::string::npos)
      << refusal({all[0], all[1], other});
  // An interrupted shard; --partial counts it missing.
  ShardFile cut = all[1];
  cut.json["interrupted"] = true;
  cut.file = "cut.json";
  EXPECT_NE(refusal({all[0], cut, all[2]}).find("cut.json: shard 1/3 was interrupted"), std::string::npos);
  EXPECT_EQ(merge_shards({all[0], cut, all[2]}, true).missing, std::vector<std::uint64_t>{1});
  // Not a shard's result; a field missing.
  ShardFile whole{"whole.json", to_json(run_verify(o, methods()))};
  EXPECT_NE(refusal({whole}).find("whole.json: not a shard's result"), std::string::npos);
  ShardFile broken = all[0];
  broken.json["distributions"][0]["methods"][0].erase("false_reject");
  broken.file = "broken.json";
  EXPECT_NE(refusal({broken, all[1], all[2]}).find("broken.json, distribution uniform, method"), std::string::npos);
  EXPECT_NE(refusal({broken, all[1], all[2]}).find("no \"false_reject\""), std::string::npos);
}

}  // namespace
}  // namespace cullproof

// A run split into shards and merged equals the run in one process: the same counts, truths,
// refutations, first violations, faults and false-intersect distances, for several shard counts,
// on framed families, camera paths (stateful methods replaying each path) and a method that
// faults part way. The merge refuses what would make a total silently smaller or wrong.
#include "cullproof/campaign/campaign.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace cullproof {
namespace {

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

// Shards 0..n-1 of the run, each through its JSON (as files carry them).
std::vector<ShardFile> shards_of(const VerifyOptions& o, std::uint64_t n) {
  std::vector<ShardFile> files;
  for (std::uint64_t k = 0; k < n; ++k) {
    VerifyOptions s = o;
    s.shard = Shard{k, n};
    files.push_back({"shard-" + std::to_string(k) + ".json", nlohmann::json::parse(to_json(run_verify(s, methods())).dump())});
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

// Certified-exact culling against the oracle on every family: the verdict equals the truth,
// case by case (no error of any class; the claim's band is zero). Every volume of a case meets
// every method that can take it: AABBs also as OBBs (when the float centre and half-extents are
// exact), points as flat boxes, OBBs and balls of radius 0; AABBs and spheres through the batch
// forms as well. Built twice: as is, and (test_exact_certified_fma) with the float stages compiled
// with -mfma -ffp-contract=fast, so that the bounds are checked with contraction too.
#include "cullproof/exact_certified.hpp"
#include "cullproof/exact_certified_batch.hpp"
#include "cullproof/generators.hpp"
#include "cullproof/methods.hpp"
#include "cullproof/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>

#include "../harness/show.hpp"

#include <string>
#include <variant>

using namespace cullproof;

namespace {

#ifdef CULLPROOF_FMA_BUILD
bool cpu_has_fma() { return __builtin_cpu_supports("fma"); }
#else
bool cpu_has_fma() { return true; }
#endif

// The AABB as an OBB, when to_obb describes exactly the same points.
bool exact_obb(const Aabb& b, Obb& out) {
  out = to_obb(b);
  for (int i = 0; i < 3; ++i)
    if (double(out.center[i]) - double(out.half[i]) != double(b.min[i]) ||
        double(out.center[i]) + double(out.half[i]) != double(b.max[i]))
      return false;
  return true;
}

Visibility batch(const char* name, const CaseFrustum& f, const Aabb& b) {
  Answer a;
  find_builtin(name)->prepare(f)->classify_batch(&b, 1, &a);
  return *a;
}
Visibility batch(const char* name, const CaseFrustum& f, const Sphere& s) {
  Answer a;
  find_builtin(name)->prepare(f)->classify_batch(&s, 1, &a);
  return *a;
}

class ExactCertifiedOnEveryFamily : public ::testing::TestWithParam<gen::Distribution> {};

TEST_P(ExactCertifiedOnEveryFamily, EqualsTheOracle) {
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA";
  const gen::Distribution d = GetParam();
  const bool ok = rc::check(std::string("certified-exact equals the truth on ") + std::string(gen::to_string(d)), [d] {
    const gen::GenCase g = *gen::case_of(d);
    const Visibility truth = oracle::truth(g.frustum, g.volume);
    const ExactCertifiedFrustum f = prepare_exact_certified(g.frustum);
    auto expect = [&](const char* method, Visibility v) {
      if (v != truth)
        RC_FAIL(std::string(method) + " says " + std::string(to_string(v)) + ", the truth is " +
                std::string(to_string(truth)));
    };
    if (const Aabb* a = std::get_if<Aabb>(&g.volume)) {
      expect("aabb-exact-certified", exact_certified_aabb(f, *a));
      expect("aabb-batch-exact-certified", batch("aabb-batch-exact-certified", g.frustum, *a));
      Obb o;
      if (exact_obb(*a, o)) expect("obb-exact-certified (the box as an OBB)", exact_certified_obb(f, o));
    } else if (const Obb* o = std::get_if<Obb>(&g.volume)) {
      expect("obb-exact-certified", exact_certified_obb(f, *o));
    } else if (const Sphere* s = std::get_if<Sphere>(&g.volume)) {
      expect("sphere-exact-certified", exact_certified_sphere(f, *s));
      expect("sphere-batch-exact-certified", batch("sphere-batch-exact-certified", g.frustum, *s));
    } else {
      const Point& p = std::get<Point>(g.volume);
      expect("aabb-exact-certified (the point as a box)", exact_certified_aabb(f, Aabb{p, p}));
      expect("obb-exact-certified (the point as an OBB)", exact_certified_obb(f, Obb{p, glm::mat3(1.0f), glm::vec3(0.0f)}));
      expect("sphere-exact-certified (the point as a ball)", exact_certified_sphere(f, Sphere{p, 0.0f}));
    }
  });
  EXPECT_TRUE(ok);
}

std::string distribution_name(const ::testing::TestParamInfo<gen::Distribution>& p) {
  std::string s(gen::to_string(p.param));
  for (char& ch : s)
    if (ch == '-') ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(AllDistributions, ExactCertifiedOnEveryFamily,
                         ::testing::ValuesIn(gen::parse_distributions("all")), distribution_name);

}  // namespace

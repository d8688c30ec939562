// The certified guarantee with FMA contraction: this file and src/core/certified/certified.cpp are
// compiled with -mfma -ffp-contract=fast, so the plane evaluations and margins may be fused. The
// derivation (certified.cpp) holds either way; here the oracle checks it on every family.
#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/core/certified.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>
#include <rapidcheck.h>

using namespace cullproof;

namespace {

bool cpu_has_fma() { return __builtin_cpu_supports("fma"); }

}  // namespace

TEST(CertifiedWithFma, NeverAFalseRejectOrFalseInside) {
  if (!cpu_has_fma()) GTEST_SKIP() << "this CPU has no FMA";
  for (gen::Distribution d : gen::parse_distributions("all")) {
    const bool ok = rc::check(std::string("certified with FMA on ") + std::string(gen::to_string(d)), [d] {
      const gen::GenCase g = *gen::case_of(d);
      const Visibility truth = oracle::truth(g.frustum, g.volume);
      const CertifiedFrustum f = certify(g.frustum);
      std::optional<Visibility> v;
      if (const Aabb* a = std::get_if<Aabb>(&g.volume)) v = certified_pn_vertex(f, *a);
      else if (const Obb* o = std::get_if<Obb>(&g.volume)) v = certified_obb_pn_vertex(f, *o);
      else if (const Sphere* s = std::get_if<Sphere>(&g.volume)) v = certified_sphere(f, *s);
      else v = certified_point(f, std::get<Point>(g.volume));
      RC_ASSERT(!(*v == Visibility::outside && truth != Visibility::outside));
      RC_ASSERT(!(*v == Visibility::inside && truth != Visibility::inside));
    });
    EXPECT_TRUE(ok) << gen::to_string(d);
  }
}

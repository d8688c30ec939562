// The oracle against its independent second method: zero disagreements over
// generated touching, containment, degenerate and matrix cases. Each case is also classified by
// the exact route alone (no filter), which must agree with the filtered answer, and the
// distance must be consistent with the truth.
//
// Cases per family: RapidCheck's max_success (RC_PARAMS), which CTest sets (see CMakeLists.txt);
// by hand: RC_PARAMS=max_success=25000 build/tests/oracle/test_oracle_property. A failure logs the
// case as one case-format JSON line and RapidCheck's reproduce string.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "oracle_generators.hpp"

#include "cullproof/oracle.hpp"

#include <cmath>

// The property run and the slow campaign compile this file twice; distinct suite names keep
// their CTest names (and labels) apart.
#ifndef CULLPROOF_ORACLE_SUITE
#define CULLPROOF_ORACLE_SUITE OracleCrossCheck
#endif

namespace cullproof::oracle::test {
namespace {

void check_case(const GenCase& c) {
  RC_LOG() << describe(c) << "\n";
  const Result r = classify(c.frustum, c.volume);
  const Visibility other = classify_independent(c.frustum, c.volume);
  RC_TAG(std::string(cullproof::to_string(r.truth)), r.filtered ? "filtered" : "exact");
  RC_ASSERT(r.truth == other);
  Options exact_only;
  exact_only.filter = false;
  exact_only.distance = false;
  exact_only.witness_json = false;
  RC_ASSERT(classify(c.frustum, c.volume, exact_only).truth == r.truth);
  // Distances: outside volumes are at a positive distance (closed, disjoint, B compact).
  if (r.truth == Visibility::outside) {
    RC_ASSERT(r.distance_kind == DistanceKind::euclidean);
    RC_ASSERT(r.distance > 0.0);
  } else {
    RC_ASSERT(r.distance >= 0.0);
    RC_ASSERT(r.witness.at("kind") == "point");
  }
}

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, TouchingByConstruction, ()) { check_case(gen_touching()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, ContainmentBothWays, ()) { check_case(gen_containment()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, DegenerateVolumesAndSpecialPlanes, ()) { check_case(gen_degenerate()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, MatrixFrustaAllDepthConventions, ()) { check_case(gen_matrix()); }

}  // namespace
}  // namespace cullproof::oracle::test

// The oracle against its independent second method: zero disagreements over
// generated touching, containment, degenerate and matrix cases. Each case is also classified by
// the exact route alone (no filter), which must agree with the filtered answer, and the
// distance must be consistent with the truth.
//
// Cases per family: RC_PARAMS max_success when set (CTest sets it, see CMakeLists.txt), else
// CULLPROOF_ORACLE_CASES_PER_FAMILY (compile definition). A failure logs the case as one case-format JSON line and RapidCheck's
// reproduce string.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "oracle_generators.hpp"

#include "cullproof/oracle.hpp"

#include <rapidcheck/detail/TestListenerAdapter.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>

#ifndef CULLPROOF_ORACLE_CASES_PER_FAMILY
#define CULLPROOF_ORACLE_CASES_PER_FAMILY 25000
#endif
// The property run and the slow campaign compile this file twice; distinct suite names keep
// their CTest names (and labels) apart.
#ifndef CULLPROOF_ORACLE_SUITE
#define CULLPROOF_ORACLE_SUITE OracleCrossCheck
#endif

namespace cullproof::oracle::test {
namespace {

std::atomic<long> g_cases{0};

// Runs `property` CULLPROOF_ORACLE_CASES_PER_FAMILY times (RC_PARAMS max_success wins).
template <class Property>
void check_family(Property property) {
  using namespace rc::detail;
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  TestMetadata metadata;
  metadata.id = std::string(info->test_suite_name()) + "/" + info->name();
  metadata.description = info->name();
  TestParams params = configuration().testParams;
  const char* env = std::getenv("RC_PARAMS");
  if (env == nullptr || std::strstr(env, "max_success") == nullptr) params.maxSuccess = CULLPROOF_ORACLE_CASES_PER_FAMILY;
  TestListenerAdapter quiet;
  const long before = g_cases.load();
  const auto result = checkProperty(toProperty(property), metadata, params, quiet, configuration().reproduce);
  std::ostringstream msg;
  printResultMessage(result, msg);
  std::cout << metadata.id << ": " << (g_cases.load() - before) << " cases; " << msg.str() << std::endl;
  if (!result.template is<SuccessResult>()) FAIL() << msg.str();
}

void check_case(const GenCase& c) {
  RC_LOG() << describe(c) << "\n";
  ++g_cases;
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

TEST(CULLPROOF_ORACLE_SUITE, TouchingByConstruction) {
  check_family([] { check_case(gen_touching()); });
}

TEST(CULLPROOF_ORACLE_SUITE, ContainmentBothWays) {
  check_family([] { check_case(gen_containment()); });
}

TEST(CULLPROOF_ORACLE_SUITE, DegenerateVolumesAndSpecialPlanes) {
  check_family([] { check_case(gen_degenerate()); });
}

TEST(CULLPROOF_ORACLE_SUITE, MatrixFrustaAllDepthConventions) {
  check_family([] { check_case(gen_matrix()); });
}

}  // namespace
}  // namespace cullproof::oracle::test

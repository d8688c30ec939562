// The oracle against its independent second method: zero disagreements over generated cases.
// Each case is also classified by the exact route alone (no filter), which must agree with the
// filtered answer, and the distance must be consistent with the truth (an outside volume's the
// same with its closest pair found in double as by the exact QP alone).
//
// The cases come from the generator library (cullproof/gen/generators.hpp, cullproof/gen/arbitrary.hpp):
// the exact families (touching by construction, containment both ways, degenerate volumes and
// special planes, on frusta with integer corners), every camera-built distribution (matrix
// frusta in every depth convention, and planes), any case at all, and a frustum and a volume
// drawn apart.
//
// Cases per property: RapidCheck's max_success (RC_PARAMS), which CTest sets (see CMakeLists.txt);
// by hand: RC_PARAMS=max_success=25000 build/tests/oracle/test_oracle_property. A failure prints
// every value drawn, a case in the case format (cullproof/gen/arbitrary.hpp), and RapidCheck's
// reproduce string.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "cullproof/gen/arbitrary.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <cmath>
#include <string>

// The property run and the slow campaign compile this file twice; distinct suite names keep
// their CTest names (and labels) apart.
#ifndef CULLPROOF_ORACLE_SUITE
#define CULLPROOF_ORACLE_SUITE OracleCrossCheck
#endif

namespace cullproof::oracle::test {
namespace {

void check_case(const CaseFrustum& frustum, const Volume& volume) {
  const Result r = classify(frustum, volume);
  const Visibility other = classify_independent(frustum, volume);
  RC_TAG(std::string(cullproof::to_string(r.truth)), r.filtered ? "filtered" : "exact");
  RC_ASSERT(r.truth == other);
  Options exact_only;
  exact_only.filter = false;
  exact_only.distance = false;
  exact_only.witness = false;
  RC_ASSERT(classify(frustum, volume, exact_only).truth == r.truth);
  // Distances: outside volumes are at a positive distance (closed, disjoint, B compact), the same
  // exact value whether the closest pair was found in double and proven or solved as a QP.
  if (r.truth == Visibility::outside) {
    RC_ASSERT(r.distance_kind == DistanceKind::euclidean);
    RC_ASSERT(r.distance > 0.0);
    Options qp_only;
    qp_only.closest_in_double = false;
    qp_only.witness = false;
    const Result qp = classify(frustum, volume, qp_only);
    RC_ASSERT(qp.truth == r.truth);
    RC_ASSERT(qp.distance == r.distance);
  } else {
    RC_ASSERT(r.distance >= 0.0);
    RC_ASSERT(r.witness.kind == Witness::Kind::point);
  }
}

void check_case(const gen::GenCase& c) { check_case(c.frustum, c.volume); }

// The distributions that build their frustum from a camera: as a float matrix (end-to-end truth)
// or as the planes extracted from it, perspective, off-axis, orthographic, reversed-Z and
// infinite far in both depth ranges, with volumes near faces, edges and corners, degenerate,
// tiny, huge and subnormal. (touch, ulp and contact build exact frusta instead: see AnyCase.)
const std::vector<gen::Distribution>& camera_distributions() {
  static const std::vector<gen::Distribution> out = [] {
    std::vector<gen::Distribution> v;
    for (gen::Distribution d : gen::parse_distributions("all"))
      if (d != gen::Distribution::touch && d != gen::Distribution::ulp && d != gen::Distribution::contact) v.push_back(d);
    return v;
  }();
  return out;
}

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, TouchingByConstruction, ()) { check_case(*gen::exact_touching()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, ContainmentBothWays, ()) { check_case(*gen::exact_containment()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, DegenerateVolumesAndSpecialPlanes, ()) { check_case(*gen::exact_degenerate()); }

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, MatrixFrustaAllDepthConventions, ()) {
  const gen::Distribution d = *rc::gen::elementOf(camera_distributions());
  const gen::GenCase c = *gen::case_of(d);
  RC_TAG(c.frustum.matrix ? "matrix" : "planes");
  check_case(c);
}

RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, AnyCase, (const gen::GenCase& c)) { check_case(c.frustum, c.volume); }

// Frustum and volume from different cases: mostly far apart or of unrelated scales.
RC_GTEST_PROP(CULLPROOF_ORACLE_SUITE, FrustumAndVolumeDrawnApart, (const CaseFrustum& f, const Volume& v)) {
  check_case(f, v);
}

}  // namespace
}  // namespace cullproof::oracle::test

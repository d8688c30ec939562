// RapidCheck's idiom for the core types: rc::Arbitrary specialisations, so that a property writes
// rc::gen::arbitrary<cullproof::Aabb>() or takes the types as arguments,
//   RC_GTEST_PROP(Suite, Name, (const cullproof::CaseFrustum& f, const cullproof::Volume& v)) {...}
// and printers (showValue, found by argument-dependent lookup), so that a counterexample prints
// exactly: frusta, volumes and cases in the case format (shortest decimals that read back
// bit-exactly), a case's volume also as hex floats.
//
// Every value comes from the case generators (cullproof/gen/generators.hpp), not from raw floats: a
// frustum or a volume is one of gen::any_case(), the cases of every distribution (`huge`
// included, whose float sums overflow) and of the exact families. A volume or frustum asked for
// alone is the part of such a case; the other part is dropped, so take the GenCase where the two
// must meet. Shrinking is the generators' own.
//
// Point is glm::vec3, a type this library does not own, so it has no specialisation here (one
// would change arbitrary<glm::vec3>() for every user of GLM): points come as
// arbitrary<cullproof::Volume>() alternatives.
#pragma once

#include "cullproof/gen/generators.hpp"

#include <rapidcheck.h>

#include <iosfwd>
#include <variant>

namespace cullproof {

void showValue(Visibility v, std::ostream& os);
void showValue(const DepthConvention& d, std::ostream& os);
void showValue(const Plane& p, std::ostream& os);
void showValue(const Frustum& f, std::ostream& os);
void showValue(const CaseFrustum& f, std::ostream& os);
void showValue(const Aabb& v, std::ostream& os);
void showValue(const Sphere& v, std::ostream& os);
void showValue(const Obb& v, std::ostream& os);
void showValue(const Volume& v, std::ostream& os);

namespace gen {
void showValue(Distribution d, std::ostream& os);
/// The case in the case format, then every volume number as a hex float.
void showValue(const GenCase& g, std::ostream& os);

/// The volume of an arbitrary case, when it is a T (one of Volume's alternatives).
template <typename T>
rc::Gen<T> volume_of() {
  return rc::gen::map(rc::gen::suchThat(rc::gen::map(any_case(), [](const GenCase& g) { return g.volume; }),
                                        [](const Volume& v) { return std::holds_alternative<T>(v); }),
                      [](const Volume& v) { return std::get<T>(v); });
}
}  // namespace gen

}  // namespace cullproof

namespace rc {

/// Every distribution, parse_distributions("all") order; shrinks towards uniform.
template <>
struct Arbitrary<cullproof::gen::Distribution> {
  static Gen<cullproof::gen::Distribution> arbitrary() {
    return gen::elementOf(cullproof::gen::parse_distributions("all"));
  }
};

/// gen::any_case(): a case of any distribution or exact family.
template <>
struct Arbitrary<cullproof::gen::GenCase> {
  static Gen<cullproof::gen::GenCase> arbitrary() { return cullproof::gen::any_case(); }
};

/// The frustum of an arbitrary case: planes or a matrix in any depth convention.
template <>
struct Arbitrary<cullproof::CaseFrustum> {
  static Gen<cullproof::CaseFrustum> arbitrary() {
    return gen::map(cullproof::gen::any_case(), [](const cullproof::gen::GenCase& g) { return g.frustum; });
  }
};

/// The planes of an arbitrary case's frustum (for a matrix case, those extracted in float).
template <>
struct Arbitrary<cullproof::Frustum> {
  static Gen<cullproof::Frustum> arbitrary() {
    return gen::map(cullproof::gen::any_case(), [](const cullproof::gen::GenCase& g) { return g.frustum.planes; });
  }
};

/// One plane of an arbitrary Frustum (a degenerate one, n == 0, included).
template <>
struct Arbitrary<cullproof::Plane> {
  static Gen<cullproof::Plane> arbitrary() {
    return gen::resize(100, gen::apply([](const cullproof::Frustum& f, int k) { return f[k]; },
                                       gen::arbitrary<cullproof::Frustum>(), gen::inRange(0, cullproof::kPlaneCount)));
  }
};

/// The volume of an arbitrary case: a point, sphere, AABB or OBB.
template <>
struct Arbitrary<cullproof::Volume> {
  static Gen<cullproof::Volume> arbitrary() {
    return gen::map(cullproof::gen::any_case(), [](const cullproof::gen::GenCase& g) { return g.volume; });
  }
};

template <>
struct Arbitrary<cullproof::Aabb> {
  static Gen<cullproof::Aabb> arbitrary() { return cullproof::gen::volume_of<cullproof::Aabb>(); }
};

template <>
struct Arbitrary<cullproof::Sphere> {
  static Gen<cullproof::Sphere> arbitrary() { return cullproof::gen::volume_of<cullproof::Sphere>(); }
};

template <>
struct Arbitrary<cullproof::Obb> {
  static Gen<cullproof::Obb> arbitrary() { return cullproof::gen::volume_of<cullproof::Obb>(); }
};

/// The four depth conventions (range, reversed-Z or not).
template <>
struct Arbitrary<cullproof::DepthConvention> {
  static Gen<cullproof::DepthConvention> arbitrary() {
    using cullproof::DepthConvention, cullproof::DepthRange;
    return gen::element(DepthConvention{DepthRange::negative_one_to_one, false},
                        DepthConvention{DepthRange::zero_to_one, false},
                        DepthConvention{DepthRange::zero_to_one, true},
                        DepthConvention{DepthRange::negative_one_to_one, true});
  }
};

}  // namespace rc

// Helpers shared by the oracle tests: hand-checkable frusta and a classify-everything checker.
#pragma once

#include "cullproof/io/case_io.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>

namespace cullproof {
/// GoogleTest printer: "intersecting" rather than "1-byte object <01>".
inline void PrintTo(Visibility v, std::ostream* os) { *os << to_string(v); }
}  // namespace cullproof

namespace cullproof::oracle::test {

/// The axis-aligned cube [-1,1]^3 as a frustum: left x >= -1, right x <= 1, bottom y >= -1,
/// top y <= 1, near z <= 1 (n = (0,0,-1), d = 1), far z >= -1.
inline Frustum cube_frustum() {
  Frustum f;
  f[kLeft] = Plane{{1, 0, 0}, 1};
  f[kRight] = Plane{{-1, 0, 0}, 1};
  f[kBottom] = Plane{{0, 1, 0}, 1};
  f[kTop] = Plane{{0, -1, 0}, 1};
  f[kNear] = Plane{{0, 0, -1}, 1};
  f[kFar] = Plane{{0, 0, 1}, 1};
  return f;
}

/// The cube as a case's frustum (given by its planes).
inline CaseFrustum cube() { return frustum_spec(cube_frustum()); }

inline Aabb box(glm::vec3 lo, glm::vec3 hi) { return Aabb{lo, hi}; }

/// Every route of the oracle must give `expected`: filtered, exact-only, the independent
/// method; the witness must be present and of the right kind.
inline Result expect_truth(const CaseFrustum& f, const Volume& v, Visibility expected) {
  SCOPED_TRACE("volume " + format_volume(v) + " frustum " + format_frustum(f));
  const Result r = classify(f, v);
  EXPECT_EQ(r.truth, expected) << "filtered classify";
  Options exact_only;
  exact_only.filter = false;
  const Result e = classify(f, v, exact_only);
  EXPECT_EQ(e.truth, expected) << "exact route";
  EXPECT_FALSE(e.filtered);
  EXPECT_EQ(classify_independent(f, v), expected) << "independent method";
  EXPECT_EQ(r.witness.kind, expected == Visibility::outside ? Witness::Kind::separating_plane : Witness::Kind::point);
  // Both routes compute the same exact distance (same formulas after the decision).
  if (std::isfinite(r.distance) || std::isfinite(e.distance)) {
    EXPECT_DOUBLE_EQ(r.distance, e.distance);
  }
  EXPECT_GE(r.distance, 0.0);
  return r;
}

}  // namespace cullproof::oracle::test

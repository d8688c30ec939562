// Property: every finite float survives write -> read bit-exactly, as a decimal and as hex.
#include "cullproof/io/case_io.hpp"

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstring>

using namespace cullproof;

namespace {

// Any finite float, from its bit pattern (so subnormals, huge and tiny magnitudes all occur).
rc::Gen<float> finite_float() {
  return rc::gen::map(rc::gen::arbitrary<std::uint32_t>(), [](std::uint32_t u) {
    if (((u >> 23) & 0xffu) == 0xffu) u &= ~(1u << 30);  // turn Inf/NaN into a finite value
    float x;
    std::memcpy(&x, &u, 4);
    return x;
  });
}

std::uint32_t bits(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, 4);
  return u;
}

}  // namespace

RC_GTEST_PROP(CaseIoProperty, FloatRoundTripIsBitExact, ()) {
  const float x = *finite_float();
  RC_ASSERT(bits(parse_case_float(format_float(x), false)) == bits(x));
  RC_ASSERT(bits(parse_case_float(format_hex_float(x), true)) == bits(x));
}

RC_GTEST_PROP(CaseIoProperty, AabbCaseRoundTripIsBitExact, ()) {
  glm::vec3 a, b;
  for (int i = 0; i < 3; ++i) {
    a[i] = *finite_float();
    b[i] = *finite_float();
  }
  Case c;
  c.id = "p";
  Frustum f;
  for (int k = 0; k < 6; ++k) f[k] = Plane{{*finite_float(), *finite_float(), *finite_float()}, *finite_float()};
  c.frustum = frustum_spec(f);
  c.volume = Aabb{glm::min(a, b), glm::max(a, b)};
  const Case d = parse_case(format_case(c));
  const Aabb& x = std::get<Aabb>(c.volume);
  const Aabb& y = std::get<Aabb>(d.volume);
  for (int i = 0; i < 3; ++i) {
    RC_ASSERT(bits(x.min[i]) == bits(y.min[i]));
    RC_ASSERT(bits(x.max[i]) == bits(y.max[i]));
  }
  for (int k = 0; k < 6; ++k) RC_ASSERT(bits(f[k].d) == bits(d.frustum.planes[k].d));
}

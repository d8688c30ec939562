// Builds against an installed cullproof: extracts planes from a projection and writes a case; and
// checks that the headers' inline plane evaluation rounds as the library does in this translation
// unit too, whatever its flags (tests/consumer.sh builds it with FMA contraction asked for).
#include <cullproof/core/frustum_build.hpp>
#include <cullproof/io/case_io.hpp>

#include <cmath>
#include <iostream>

int main() {
  const cullproof::Frustum f = cullproof::frustum_from_matrix(cullproof::off_axis_projection(-1, 1, -1, 1, 1, 3));
  cullproof::Case c;
  c.id = "consumer";
  c.frustum = cullproof::frustum_spec(f);
  c.volume = cullproof::Point{0.0f, 0.0f, -2.0f};
  std::cout << cullproof::format_case(c) << "\n";
  if (!(f[cullproof::kNear].eval({0.0f, 0.0f, -2.0f}) > 0.0f)) return 1;
  // ((1 * b + 0 * 0) + a * -a) + 0 with a = 1 + 2^-12, b = 1 + 2^-11: a * a = b + 2^-24 rounds to b
  // (a tie, to even), so the sum is 0; fused into the addition it is -2^-24, outside the plane.
  volatile float a = 1.0f + std::ldexp(1.0f, -12), b = 1.0f + std::ldexp(1.0f, -11);
  const cullproof::Plane p{{1.0f, 0.0f, a}, 0.0f};
  const float v = p.eval({b, 0.0f, -a});
  if (v != 0.0f) {
    std::cerr << "Plane::eval rounds otherwise than the library: " << v << " instead of 0\n";
    return 1;
  }
  return 0;
}

// Builds against an installed cullproof: extracts planes from a projection and writes a case.
#include <cullproof/case_io.hpp>
#include <cullproof/frustum_build.hpp>

#include <iostream>

int main() {
  const cullproof::Frustum f = cullproof::frustum_from_matrix(cullproof::off_axis_projection(-1, 1, -1, 1, 1, 3));
  cullproof::Case c;
  c.id = "consumer";
  c.frustum = cullproof::frustum_spec(f);
  c.volume = cullproof::Point{0.0f, 0.0f, -2.0f};
  std::cout << cullproof::format_case(c) << "\n";
  return f[cullproof::kNear].eval({0.0f, 0.0f, -2.0f}) > 0.0f ? 0 : 1;
}

// Exact printing of generated cases for RapidCheck counterexamples: the case in the corpus
// format (shortest decimals read back bit-exactly) and every volume number as a hex float.
#pragma once

#include "cullproof/case_io.hpp"
#include "cullproof/generators.hpp"

#include <ostream>

namespace cullproof::gen {

inline void showValue(const GenCase& g, std::ostream& os) {
  Case c;
  c.id = "counterexample";
  c.frustum = g.frustum;
  c.volume = g.volume;
  os << format_case(c) << "\n  volume (hex):";
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        auto hex = [&](const glm::vec3& x) {
          os << " [" << format_hex_float(x.x) << ", " << format_hex_float(x.y) << ", " << format_hex_float(x.z) << "]";
        };
        if constexpr (std::is_same_v<T, Point>) hex(v);
        else if constexpr (std::is_same_v<T, Sphere>) { hex(v.center); os << " r=" << format_hex_float(v.radius); }
        else if constexpr (std::is_same_v<T, Aabb>) { hex(v.min); hex(v.max); }
        else { hex(v.center); hex(v.axes[0]); hex(v.axes[1]); hex(v.axes[2]); hex(v.half); }
      },
      g.volume);
}

}  // namespace cullproof::gen

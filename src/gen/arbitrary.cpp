// Printers for RapidCheck counterexamples (see cullproof/gen/arbitrary.hpp).
#include "cullproof/gen/arbitrary.hpp"

#include "cullproof/io/case_io.hpp"

#include <ostream>

namespace cullproof {

void showValue(Visibility v, std::ostream& os) { os << to_string(v); }

void showValue(const DepthConvention& d, std::ostream& os) {
  os << (d.range == DepthRange::zero_to_one ? "zero_to_one" : "negative_one_to_one")
     << (d.reversed_z ? " reversed_z" : "");
}

void showValue(const Plane& p, std::ostream& os) {
  os << "{\"n\": [" << format_float(p.n.x) << ", " << format_float(p.n.y) << ", " << format_float(p.n.z)
     << "], \"d\": " << format_float(p.d) << "}";
}

void showValue(const Frustum& f, std::ostream& os) { os << format_frustum(frustum_spec(f)); }
void showValue(const CaseFrustum& f, std::ostream& os) { os << format_frustum(f); }
void showValue(const Aabb& v, std::ostream& os) { os << format_volume(v); }
void showValue(const Sphere& v, std::ostream& os) { os << format_volume(v); }
void showValue(const Obb& v, std::ostream& os) { os << format_volume(v); }
void showValue(const Volume& v, std::ostream& os) { os << format_volume(v); }

namespace gen {

void showValue(Distribution d, std::ostream& os) { os << to_string(d); }

void showValue(const GenCase& g, std::ostream& os) {
  Case c;
  c.id = "counterexample";
  c.frustum = g.frustum;
  c.volume = g.volume;
  os << format_case(c) << "\n  volume (hex):";
  auto hex = [&](const glm::vec3& x) {
    os << " [" << format_hex_float(x.x) << ", " << format_hex_float(x.y) << ", " << format_hex_float(x.z) << "]";
  };
  std::visit(
      [&](const auto& v) {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, Point>) {
          hex(v);
        } else if constexpr (std::is_same_v<T, Sphere>) {
          hex(v.center);
          os << " r=" << format_hex_float(v.radius);
        } else if constexpr (std::is_same_v<T, Aabb>) {
          hex(v.min);
          hex(v.max);
        } else {
          hex(v.center);
          hex(v.axes[0]);
          hex(v.axes[1]);
          hex(v.axes[2]);
          hex(v.half);
        }
      },
      g.volume);
}

}  // namespace gen
}  // namespace cullproof

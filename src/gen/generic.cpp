// The generic distributions: a generic camera, a volume of the distribution about its frustum.
#include "blocks.hpp"

namespace cullproof::gen::detail {

// A volume of generic distribution d around placement p (its draws follow the camera's).
Volume generic_volume(Distribution d, const Placement& p) {
  const Shape shape = d == Distribution::degenerate ? Shape::aabb : any_shape();
  switch (d) {
    case Distribution::uniform: {
      const glm::dvec3 x = p.center + p.size * 0.75 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1));
      return volume_at(shape, x, p.size * rel_size(-3, -0.5));
    }
    case Distribution::near_boundary: return near_boundary(p, shape, p.size * rel_size(-3, -1));
    case Distribution::corner: return near_corner(p, shape, p.size * rel_size(-3, -1));
    case Distribution::enclosing: {
      const glm::dvec3 x = p.center + p.size * 0.2 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1));
      return volume_at(shape == Shape::point ? Shape::aabb : shape, x, p.size * in(0.5, 1.5));
    }
    case Distribution::tiny_huge: {
      const double s = p.size * rel_size(-7, 1);
      return coin(50) ? near_boundary(p, shape, s)
                      : volume_at(shape, p.center + p.size * 0.6 * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1)), s);
    }
    case Distribution::degenerate: {
      const double s = p.size * rel_size(-3, -1);
      Volume v = coin(50) ? near_boundary(p, Shape::aabb, s) : near_corner(p, Shape::aabb, s);
      const int kind = pick(6);
      if (kind == 0) return Point(std::get<Aabb>(v).center());
      if (kind == 1) return Sphere{std::get<Aabb>(v).center(), 0.0f};
      Aabb b = std::get<Aabb>(v);
      const int keep = kind == 2 ? 0 : kind == 3 ? 1 : 2;  // 2: point box, 3: segment, 4-5: flat
      for (int a = 0, kept = 0; a < 3; ++a) {
        const bool flat = kept >= keep;
        if (!flat) {
          ++kept;
          continue;
        }
        b.min[a] = b.max[a] = b.center()[a];
      }
      if (coin(50)) return to_obb(b);
      return b;
    }
    default: break;
  }
  return volume_at(shape, p.center, p.size * 0.1);
}

GenCase generic_case(Distribution d) {
  const Camera cam = generic_camera();
  const Placement p = placement_for(cam);
  return make(cam, p, generic_volume(d, p));
}


}  // namespace cullproof::gen::detail

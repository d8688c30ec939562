// The hard families on the generic camera: each takes a generic camera and pushes it to one end
// (far from the origin, a tiny near plane, reversed and infinite depth, an extreme field of view,
// ill-conditioned planes, long thin volumes).
#include "blocks.hpp"

#include <cmath>

namespace cullproof::gen::detail {

GenCase far_offset_case() {
  Camera cam = generic_camera();
  for (int i = 0; i < 3; ++i) cam.eye[i] = float((coin(50) ? 1 : -1) * log_in(5, 7));
  cam.n = float(log_in(-1, 0));
  cam.f = float(log_in(2, 3));
  if (cam.ortho) cam.ortho = false, cam.l = -cam.n, cam.r = cam.n, cam.b = -cam.n, cam.t = cam.n;
  const Placement p = placement_for(cam);
  return make(cam, p, coin(50) ? near_boundary(p, any_shape(), log_in(-2, 1)) : near_corner(p, any_shape(), log_in(-2, 1)));
}

GenCase tiny_near_case() {
  Camera cam = generic_camera();
  cam.ortho = false;
  cam.infinite = false;
  cam.n = float(log_in(-4, -2));
  cam.f = float(log_in(3, 7));
  const float t = cam.n * std::tan(glm::radians(float(in(20, 110))) / 2.0f), a = float(in(0.5, 2.2));
  cam.t = t, cam.b = -t, cam.r = t * a, cam.l = -t * a;
  cam.as_matrix = true;
  // Place near the planes close to the eye: a slice at depth between near and 1000 near.
  Camera slice = cam;
  slice.f = cam.n * float(log_in(0.3, 3));
  slice.depth = {};
  const Placement p = placement_for(slice);
  const Placement whole = placement_for(cam);
  GenCase g = make(cam, p, coin(60) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                                    : near_corner(p, any_shape(), p.size * rel_size(-3, -1)));
  g.scene_size = whole.size;
  return g;
}

GenCase reversed_infinite_case() {
  Camera cam = generic_camera();
  if (cam.ortho) cam.ortho = false, cam.l = -cam.n, cam.r = cam.n, cam.b = -cam.n, cam.t = cam.n;
  cam.infinite = true;
  cam.depth.reversed_z = coin(70);
  cam.as_matrix = coin(60);
  const Placement p = placement_for(cam);
  return make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                               : volume_at(any_shape(), p.center + p.size * glm::dvec3(in(-1, 1), in(-1, 1), in(-1, 1)),
                                           p.size * rel_size(-3, 0)));
}

GenCase extreme_fov_case() {
  Camera cam = generic_camera();
  cam.ortho = false;
  const float fovy = float(coin(50) ? log_in(-2, 1) : in(120, 179.9));
  const float aspect = float(log_in(-3, 3));
  const float t = cam.n * std::tan(glm::radians(fovy) / 2.0f);
  cam.t = t, cam.b = -t, cam.r = t * aspect, cam.l = -t * aspect;
  const Placement p = placement_for(cam);
  return make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-4, -1))
                               : near_corner(p, any_shape(), p.size * rel_size(-4, -1)));
}

GenCase ill_conditioned_case() {
  Camera cam = generic_camera();
  cam.as_matrix = false;
  cam.normalize = false;
  const Placement p = placement_for(cam);
  GenCase g = make(cam, p, coin(50) ? near_boundary(p, any_shape(), p.size * rel_size(-3, -1))
                                    : near_corner(p, any_shape(), p.size * rel_size(-3, -1)));
  for (Plane& pl : g.frustum.planes.planes) {
    // Powers of two keep the half-space exactly; other factors round every coefficient.
    const double k = coin(50) ? std::ldexp(1.0, int(integer(-60, 60))) : log_in(-18, 18);
    pl.n = glm::vec3(glm::dvec3(pl.n) * k);
    pl.d = float(double(pl.d) * k);
  }
  if (Obb* o = std::get_if<Obb>(&g.volume)) {
    for (int a = 0; a < 3; ++a)  // visibly non-orthonormal axes
      o->axes[a] = glm::vec3(glm::dvec3(o->axes[a]) + unit_vector() * log_in(-4, -2));
  }
  return g;
}

GenCase rod_case() {
  Camera cam = generic_camera();
  // A bounded frustum, so that both ends of a rod longer than the frustum lie outside it;
  // the rod passes through a point inside (slid along its own axis).
  cam.infinite = false;
  const Placement p = placement_for(cam);
  const glm::dvec3 through = glm::mix(p.center, p.corner[pick(8)], in(0, 0.6));
  const double len = p.size * in(1.5, 4), thick = p.size * log_in(-4, -2);
  Obb o;
  if (coin(30)) {
    const int a = pick(3);
    glm::dvec3 axis(0.0);
    axis[a] = 1.0;
    o.center = glm::vec3(through + axis * (len * in(-0.3, 0.3)));
    o.half = glm::vec3(float(thick));
    o.half[a] = float(len);
    return make(cam, p, Aabb{o.center - o.half, o.center + o.half});
  }
  o.axes = rotation();
  o.center = glm::vec3(through + glm::dvec3(o.axes[0]) * (len * in(-0.3, 0.3)));
  o.half = glm::vec3(float(len), float(thick), float(thick * in(0.2, 1)));
  return make(cam, p, o);
}

}  // namespace cullproof::gen::detail

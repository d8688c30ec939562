// The scene families: where their objects lie, how they move, and drawing a run by (seed, index).
#include "draw.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <stdexcept>

namespace cullproof::scenes {

namespace detail {

namespace {

float nearest(double x) noexcept { return static_cast<float>(x); }
glm::vec3 nearest(const glm::dvec3& x) noexcept { return glm::vec3(x); }

}  // namespace

bool same_volume(const Volume& a, const Volume& b) noexcept {
  if (a.index() != b.index()) return false;
  return std::visit(
      [&](const auto& x) {
        const auto& y = std::get<std::decay_t<decltype(x)>>(b);
        return std::memcmp(&x, &y, sizeof x) == 0;
      },
      a);
}

namespace {

// Whether the placement keeps a box a box: no rotation.
bool axis_aligned(const Placed& p) noexcept { return !p.rotated; }

}  // namespace

SceneObject realise(const Placed& p, std::uint32_t id) {
  SceneObject o;
  o.id = id;
  o.local = p.local;
  const glm::dmat3 linear(p.rotation[0] * p.scale.x, p.rotation[1] * p.scale.y, p.rotation[2] * p.scale.z);
  glm::mat4 m(1.0f);
  for (int c = 0; c < 3; ++c) m[c] = glm::vec4(glm::vec3(linear[c]), 0.0f);
  m[3] = glm::vec4(nearest(p.position), 1.0f);
  o.transform = m;
  auto place = [&](const glm::vec3& x) { return p.position + linear * glm::dvec3(x); };
  if (const auto* q = std::get_if<Point>(&p.local)) {
    o.world = Point(nearest(place(*q)));
  } else if (const auto* s = std::get_if<Sphere>(&p.local)) {
    o.world = Sphere{nearest(place(s->center)), nearest(double(s->radius) * std::abs(p.scale.x))};
  } else if (const auto* b = std::get_if<Aabb>(&p.local)) {
    const glm::dvec3 c = place(b->center()), h = glm::abs(p.scale) * glm::dvec3(b->half_extent());
    if (axis_aligned(p)) {
      o.world = Aabb{nearest(c - h), nearest(c + h)};
    } else {
      o.world = Obb{nearest(c), glm::mat3(p.rotation), nearest(h)};
    }
  } else {
    const Obb& ob = std::get<Obb>(p.local);  // uniform scale: the axes rotate, the half-extents scale
    o.world = Obb{nearest(place(ob.center)), glm::mat3(p.rotation * glm::dmat3(ob.axes)),
                  nearest(glm::dvec3(ob.half) * std::abs(p.scale.x))};
  }
  return o;
}

}  // namespace detail

using detail::same_volume;

namespace {

using detail::Camera;
using detail::kWorld;
using detail::Placed;
using detail::Rng;

// What a family needs to place its objects: the run's cameras (frame by frame) and origin.
struct Layout {
  const std::vector<Camera>& cameras;
  glm::dvec3 origin;
};

// A volume of a random kind about the origin with size `size` (box half-extents up to it, radius
// about it): boxes 40%, spheres 30%, OBBs 25%, points 5%.
Volume random_local(Rng& r, double size, bool any_axes) {
  const int k = r.pick(20);
  const glm::dvec3 h(size * r.uniform(0.1, 1.0), size * r.uniform(0.1, 1.0), size * r.uniform(0.1, 1.0));
  if (k < 8) return Aabb{glm::vec3(-h), glm::vec3(h)};
  if (k < 14) return Sphere{glm::vec3(0.0f), float(size)};
  if (k < 19) {
    const glm::dmat3 axes = any_axes ? r.rotation() : glm::dmat3(1.0);
    return Obb{glm::vec3(0.0f), glm::mat3(axes), glm::vec3(h)};
  }
  return Point(0.0f);
}

Placed at(const Volume& local, const glm::dvec3& position) {
  Placed p;
  p.local = local;
  p.position = position;
  return p;
}

// A point in the view of one of the run's cameras, up to a world's size deep.
glm::dvec3 in_view(Rng& r, const Layout& l) {
  const Camera& c = l.cameras[std::size_t(r.pick(int(l.cameras.size())))];
  const double far_d = std::min(c.far_d, c.near_d + kWorld);
  const double z = r.uniform(c.near_d, far_d);
  double h = c.kind == Camera::Kind::perspective ? z * std::tan(c.fovy * M_PI / 360.0) : 0.0;
  double x0 = -h * c.aspect, x1 = h * c.aspect, y0 = -h, y1 = h;
  if (c.kind != Camera::Kind::perspective) {
    const double s = c.kind == Camera::Kind::orthographic ? 1.0 : z / c.near_d;
    x0 = c.left * s, x1 = c.right * s, y0 = c.bottom * s, y1 = c.top * s;
  }
  return detail::to_world(c, {r.uniform(x0, x1), r.uniform(y0, y1), -z});
}

// Dense clusters and a sparse field: 70% of the objects in 3 to 12 clusters (most of them in
// some camera's view), the rest anywhere.
void clusters(Rng& r, const Layout& l, std::size_t n, std::vector<Placed>& out) {
  std::vector<std::pair<glm::dvec3, double>> centres(std::size_t(3 + r.pick(10)));
  for (auto& c : centres) c = {r.chance(0.7) ? in_view(r, l) : l.origin + r.in_box(kWorld), r.log_uniform(1.0, 15.0)};
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec3 pos = l.origin + r.in_box(kWorld);
    if (r.chance(0.7)) {
      const auto& [c, radius] = centres[std::size_t(r.pick(int(centres.size())))];
      pos = c + r.direction() * radius * std::cbrt(r.uniform(0.0, 1.0));
    }
    out.push_back(at(random_local(r, r.log_uniform(0.05, 3.0), true), pos));
  }
}

// Objects centred on the planes of a lattice of cell size 2^k (1 to 16): in every split a
// hierarchy makes along a lattice plane some objects straddle it, and many share coordinates
// (ties in a median split). Small dyadic values: no rounding in placing them.
void straddling(Rng& r, const Layout& l, std::size_t n, std::vector<Placed>& out) {
  const double cell = std::ldexp(1.0, r.pick(4));
  const int cells = int(kWorld / (4.0 * cell));
  // The lattice about a point in view, on a lattice point: coordinates stay small dyadics there.
  const glm::dvec3 centre = glm::round(in_view(r, l) / (cell * 16.0)) * (cell * 16.0);
  for (std::size_t i = 0; i < n; ++i) {
    glm::dvec3 pos;
    for (int k = 0; k < 3; ++k) pos[k] = cell * (r.pick(2 * cells + 1) - cells);
    if (r.chance(0.5)) pos[r.pick(3)] += cell * 0.5;  // on a face's centre line instead of a corner
    const double size = cell * std::ldexp(1.0, -r.pick(5));
    out.push_back(at(random_local(r, size, false), centre + pos));
  }
}

// A point of a camera's frustum boundary, in view space: on a side plane at a random depth, on a
// side edge, or at a corner of the near or far rectangle, within the part the world holds.
glm::dvec3 boundary_point(Rng& r, const Camera& c) {
  const double far_d = std::min(c.far_d, c.near_d + 2.0 * kWorld);
  double l = c.left, rt = c.right, b = c.bottom, t = c.top;  // the window at the near plane
  if (c.kind == Camera::Kind::perspective) {
    t = c.near_d * std::tan(c.fovy * M_PI / 360.0), b = -t, rt = t * c.aspect, l = -rt;
  }
  const int where = r.pick(6);  // 0-3: a side (left, right, bottom, top); 4: a side edge; 5: a corner
  const double z = where == 5 ? (r.chance(0.5) ? c.near_d : far_d) : r.log_uniform(c.near_d, far_d);
  const double s = c.kind == Camera::Kind::orthographic ? 1.0 : z / c.near_d;  // the window at depth z
  double x = r.uniform(l, rt), y = r.uniform(b, t);
  if (where == 0) x = l;
  if (where == 1) x = rt;
  if (where == 2) y = b;
  if (where == 3) y = t;
  if (where >= 4) x = r.chance(0.5) ? l : rt, y = r.chance(0.5) ? b : t;
  return {x * s, y * s, -z};
}

// Many tiny objects on the frusta's planes, edges and corners, frame by frame, each moved off the
// boundary by up to two of its sizes either way (or not at all).
void along_planes(Rng& r, const Layout& l, std::size_t n, std::vector<Placed>& out) {
  for (std::size_t i = 0; i < n; ++i) {
    const Camera& c = l.cameras[std::size_t(r.pick(int(l.cameras.size())))];
    const glm::dvec3 p = boundary_point(r, c);
    const double size = r.log_uniform(1e-6, 1e-2) * std::max(1.0, -p.z);
    const glm::dvec3 nudge = r.chance(0.3) ? glm::dvec3(0.0) : r.direction() * size * r.uniform(0.0, 2.0);
    out.push_back(at(random_local(r, size, true), detail::to_world(c, p) + nudge));
  }
}

// A few huge objects (half the world to ten times it; some holding the camera) among the small
// ones of `clusters`.
void few_huge(Rng& r, const Layout& l, std::size_t n, std::vector<Placed>& out) {
  const std::size_t huge = std::min<std::size_t>(n, std::size_t(1 + r.pick(5)));
  clusters(r, l, n - huge, out);
  for (std::size_t i = 0; i < huge; ++i) {
    const glm::dvec3 pos = r.chance(0.4) ? l.cameras.front().eye + r.in_box(5.0) : l.origin + r.in_box(kWorld);
    out.push_back(at(random_local(r, r.log_uniform(0.5, 10.0) * kWorld, true), pos));
  }
}

// Instances: a unit-sized local volume, rotated, scaled (boxes per axis, 0.01 to 100; spheres and
// OBBs uniformly) and placed, as a model matrix places a mesh's bounds.
void instances(Rng& r, const Layout& l, std::size_t n, std::vector<Placed>& out) {
  for (std::size_t i = 0; i < n; ++i) {
    Placed p = at(random_local(r, r.uniform(0.5, 1.0), true), r.chance(0.6) ? in_view(r, l) : l.origin + r.in_box(kWorld));
    if (std::holds_alternative<Aabb>(p.local) && r.chance(0.1)) p.local = Aabb{{0.25f, -1.0f, 0.0f}, {1.0f, 0.5f, 2.0f}};  // off-centre
    p.rotated = r.chance(0.8);
    if (p.rotated) p.rotation = r.rotation();
    const bool per_axis = std::holds_alternative<Aabb>(p.local);
    const double s = r.log_uniform(0.01, 100.0);
    p.scale = per_axis ? glm::dvec3(s, r.log_uniform(0.01, 100.0), r.log_uniform(0.01, 100.0)) : glm::dvec3(s);
    out.push_back(p);
  }
}

using Placer = void (*)(Rng&, const Layout&, std::size_t, std::vector<Placed>&);

struct Family {
  FamilyInfo info;
  Placer place;
  bool far;  ///< the run's origin 1e5 to 1e6 from the world's
};

const Family kFamilies[] = {
    {{"clusters", "dense clusters of boxes, spheres, OBBs and points in a sparse field"}, clusters, false},
    {{"straddling", "objects centred on the planes of a power-of-two lattice, straddling every split, many ties"},
     straddling, false},
    {{"along-planes", "tiny objects on the frusta's planes, edges and corners, nudged by up to two sizes"}, along_planes,
     false},
    {{"few-huge", "a few objects from half to ten times the world (some holding the camera) among small ones"},
     few_huge, false},
    {{"instances", "local bounds with rotation and non-uniform scale (0.01 to 100) given as model matrices"}, instances,
     false},
    {{"far-away", "clusters and camera 1e5 to 1e6 from the origin"}, clusters, true},
};

const Family& family(std::string_view name) {
  for (const Family& f : kFamilies)
    if (f.info.name == name) return f;
  std::string known;
  for (const Family& f : kFamilies) known += (known.empty() ? "" : ", ") + std::string(f.info.name);
  throw std::invalid_argument("unknown scene family '" + std::string(name) + "' (known: all, " + known + ")");
}

// ---- motion

enum class Motion { drift, teleport, oscillate, grow };
const char* const kMotionNames[] = {"drift", "teleport", "oscillate", "grow"};

struct Mover {
  std::size_t object;
  Motion motion;
  glm::dvec3 velocity{0.0};  ///< drift: per frame; oscillate: amplitude along the plane's normal
  std::size_t frame = 0;     ///< teleport: the frame it jumps at
  glm::dvec3 target{0.0};    ///< teleport: where to
  double rate = 1.0;         ///< grow: scale factor per frame; oscillate: radians per frame
};

// The pose of mover m's object at frame k from its pose at frame 0.
Placed moved(const Mover& m, const Placed& base, std::size_t k) {
  Placed p = base;
  const double t = double(k);
  switch (m.motion) {
    case Motion::drift: p.position += m.velocity * t; break;
    case Motion::teleport: if (k >= m.frame) p.position = m.target; break;
    case Motion::oscillate: p.position += m.velocity * std::sin(m.rate * t); break;
    case Motion::grow: p.scale *= std::pow(m.rate, t); break;
  }
  return p;
}

// Movers for a fifth of the objects, each with one of the motions (`used` lists the motions).
std::vector<Mover> movers(Rng& r, const Layout& l, const std::vector<Placed>& placed, std::size_t frames,
                          std::vector<bool>& used) {
  std::vector<Mover> out;
  used.assign(4, false);
  for (std::size_t i = 0; i < placed.size(); ++i) {
    if (!r.chance(0.2)) continue;
    Mover m{i, Motion(r.pick(4))};
    switch (m.motion) {
      case Motion::drift: m.velocity = r.direction() * r.log_uniform(0.01, 5.0); break;
      case Motion::teleport:
        m.frame = std::size_t(1 + r.pick(int(std::max<std::size_t>(frames, 2) - 1)));
        m.target = l.origin + r.in_box(kWorld);
        break;
      case Motion::oscillate: {
        // Across a plane of the first frame's frustum through the object: along that plane's normal.
        const Frustum& f = view_of(l.cameras.front()).frustum.planes;
        const Plane& pl = f[r.pick(6)];
        const double len = glm::length(glm::dvec3(pl.n));
        const glm::dvec3 n = len > 0.0 ? glm::dvec3(pl.n) / len : r.direction();
        m.velocity = n * r.log_uniform(0.1, 10.0);
        m.rate = r.uniform(0.3, 2.0);
        break;
      }
      case Motion::grow: m.rate = r.uniform(1.05, 1.6); break;
    }
    used[std::size_t(m.motion)] = true;
    out.push_back(m);
  }
  return out;
}

}  // namespace

const std::vector<FamilyInfo>& families() {
  static const std::vector<FamilyInfo> all = [] {
    std::vector<FamilyInfo> v;
    for (const Family& f : kFamilies) v.push_back(f.info);
    return v;
  }();
  return all;
}

std::vector<std::string> parse_families(std::string_view name) {
  std::vector<std::string> out;
  if (name == "all") {
    for (const Family& f : kFamilies) out.emplace_back(f.info.name);
    return out;
  }
  out.emplace_back(family(name).info.name);
  return out;
}

SceneRun draw_run(std::string_view family_name, std::uint64_t seed, std::uint64_t index, const RunSize& size) {
  const Family& fam = family(family_name);
  if (size.objects > kMaxObjects)
    throw std::invalid_argument("a scene of " + std::to_string(size.objects) + " objects: the limit is " +
                                std::to_string(kMaxObjects));
  if (size.frames == 0) throw std::invalid_argument("a run needs at least one frame");
  std::uint64_t key = splitmix64(seed);
  for (char ch : fam.info.name) key = splitmix64(key ^ std::uint64_t(static_cast<unsigned char>(ch)));
  Rng r{SplitMix64{splitmix64(key ^ index)}};

  SceneRun run;
  run.family = std::string(fam.info.name);
  run.seed = seed, run.index = index;
  run.scene.name = run.family + "-" + std::to_string(index);
  const glm::dvec3 origin = fam.far ? r.direction() * r.log_uniform(1e5, 1e6) : glm::dvec3(0.0);
  std::vector<Camera> cameras;
  run.frames = detail::camera_path(r, detail::random_camera(r, origin), size.frames, origin, cameras);

  std::vector<Placed> placed;
  placed.reserve(size.objects);
  fam.place(r, Layout{cameras, origin}, size.objects, placed);
  // Ids are stable and not dense: a system must not take them for positions.
  std::vector<std::uint32_t> ids(placed.size());
  for (std::size_t i = 0; i < placed.size(); ++i) ids[i] = std::uint32_t(3 * i + 7);
  run.scene.objects.reserve(placed.size());
  for (std::size_t i = 0; i < placed.size(); ++i) run.scene.objects.push_back(detail::realise(placed[i], ids[i]));

  run.motion = "static";
  if (r.chance(0.5) && size.frames > 1) {
    std::vector<bool> used;
    const std::vector<Mover> ms = movers(r, Layout{cameras, origin}, placed, size.frames, used);
    std::string names;
    for (std::size_t m = 0; m < used.size(); ++m)
      if (used[m]) names += (names.empty() ? "" : ", ") + std::string(kMotionNames[m]);
    if (!names.empty()) run.motion = names;
    std::vector<SceneObject> last;
    for (const Mover& m : ms) last.push_back(run.scene.objects[m.object]);
    for (std::size_t k = 1; k < size.frames; ++k)
      for (std::size_t j = 0; j < ms.size(); ++j) {
        const SceneObject now = detail::realise(moved(ms[j], placed[ms[j].object], k), ids[ms[j].object]);
        if (!same_volume(now.world, last[j].world)) {
          run.frames[k].moved.push_back(now);
          last[j] = now;
        }
      }
  }
  return run;
}

}  // namespace cullproof::scenes

// The world of a scene: instances of real meshes and a procedural floor turned into a
// bounding-volume hierarchy; moving objects; camera paths (the four path kinds of Assarsson &
// Möller 2000 §4, and keyframes) and the views of a frame.
//
// Hierarchy: two levels, as a scene graph. The top levels split the instances at the median of
// their centres (longest axis); each instance's subtree splits its triangles at the median on
// the longest axis of the centroid bounds, the left part rounded to a whole number of leaves
// (ceil(n/L)/2 leaves of L triangles), so an instance of T triangles has exactly ceil(T/L)
// leaves and the whole tree 2*sum ceil(T_i/L) - 1 nodes: a target node count (A&M's 3800 / 188 /
// 1274 graph nodes) is met by choosing L. Both levels split with the library's median_split
// (cullproof/core/cull_bvh.hpp). Node boxes are exact float min/max of their children (leaves: of
// their triangles' float world vertices), so a node encloses its subtree exactly.
#include "cullproof/sim/scene.hpp"

#include "cullproof/core/cull_bvh.hpp"
#include "cullproof/core/splitmix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

namespace cullproof::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The world's and the camera path's generator, from the scene's seed.
SplitMix64 world_rng(std::uint64_t seed) { return SplitMix64{seed * 0x9E3779B97F4A7C15ull + 0x1234567ull}; }

glm::dmat3 rot_y(double deg) {
  const double a = deg * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  // columns: x axis, y axis, z axis images
  return glm::dmat3(glm::dvec3(c, 0, -s), glm::dvec3(0, 1, 0), glm::dvec3(s, 0, c));
}
glm::dmat3 rot_x(double deg) {
  const double a = deg * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  return glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, c, s), glm::dvec3(0, -s, c));
}
glm::dmat3 orient(double yaw, double pitch) { return rot_y(yaw) * rot_x(pitch); }

Aabb empty_box() {
  const float inf = std::numeric_limits<float>::infinity();
  return Aabb{glm::vec3(inf), glm::vec3(-inf)};
}
void grow(Aabb& b, const Aabb& o) {
  b.min = glm::min(b.min, o.min);
  b.max = glm::max(b.max, o.max);
}
void grow(Aabb& b, const glm::vec3& p) {
  b.min = glm::min(b.min, p);
  b.max = glm::max(b.max, p);
}
// Model-space triangles of a normalised mesh (or the floor).
struct ModelGeom {
  std::vector<glm::vec3> vertices;  // model space: base centred at origin, scaled
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::size_t polygons = 0;
};

ModelGeom normalise(const Mesh& m, const ModelDesc& d) {
  std::vector<glm::dvec3> v(m.vertices.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 p(m.vertices[i]);
    v[i] = d.up_axis == 1 ? p : d.up_axis == 2 ? glm::dvec3(p.x, p.z, -p.y) : glm::dvec3(-p.y, p.x, p.z);
  }
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const auto& p : v) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 ext = hi - lo;
  const double big = std::max(ext.x, std::max(ext.y, ext.z));
  const double s = big > 0.0 ? d.size / big : 1.0;
  const glm::dvec3 off(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));
  ModelGeom g;
  g.vertices.reserve(v.size());
  for (const auto& p : v) g.vertices.emplace_back(glm::vec3((p - off) * s));
  g.triangles = m.triangles;
  g.polygons = m.polygons;
  return g;
}

ModelGeom floor_geom(const FloorDesc& f) {
  ModelGeom g;
  for (int j = 0; j <= f.tiles_z; ++j)
    for (int i = 0; i <= f.tiles_x; ++i)
      g.vertices.emplace_back(glm::vec3(glm::dvec3(-0.5 * f.size_x + f.size_x * i / f.tiles_x, 0.0,
                                                   -0.5 * f.size_z + f.size_z * j / f.tiles_z)));
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(j * (f.tiles_x + 1) + i); };
  for (int j = 0; j < f.tiles_z; ++j)
    for (int i = 0; i < f.tiles_x; ++i) {
      g.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      g.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      ++g.polygons;
    }
  return g;
}

struct Builder {
  World& w;
  std::uint32_t leaf_size;
  // per triangle of the instance being built
  std::vector<Aabb> tri_box, tri_local;
  std::vector<glm::vec3> tri_cent;

  std::uint32_t new_node(std::int32_t parent, std::int32_t inst) {
    w.bvh.nodes.emplace_back();
    w.parent.push_back(parent);
    w.node_instance.push_back(inst);
    w.local_box.push_back(Aabb{});
    w.bvh.subtree_prims.push_back({0, 0});
    return static_cast<std::uint32_t>(w.bvh.nodes.size() - 1);
  }

  std::uint32_t build_instance(std::vector<std::uint32_t>& idx, std::size_t b, std::size_t e, std::int32_t parent,
                               std::int32_t inst) {
    const std::uint32_t node = new_node(parent, inst);
    const std::size_t n = e - b;
    w.bvh.subtree_prims[node][0] = w.leaf_count();
    if (n <= leaf_size) {
      Aabb box = empty_box(), local = empty_box();
      for (std::size_t k = b; k < e; ++k) {
        grow(box, tri_box[idx[k]]);
        grow(local, tri_local[idx[k]]);
      }
      const std::uint32_t prim = w.leaf_count();
      w.bvh.nodes[node].box = box;
      w.bvh.nodes[node].right_or_first = prim;
      w.bvh.nodes[node].count = 1;
      w.local_box[node] = local;
      w.leaf_node.push_back(node);
      w.bvh.prim_order.push_back(prim);
      w.bvh.prim_boxes.push_back(box);
      w.bvh.subtree_prims[node][1] = w.leaf_count();
      return node;
    }
    // Split at a whole number of leaves (the median, rounded down to one).
    const std::size_t leaves = (n + leaf_size - 1) / leaf_size;
    const std::size_t left = (leaves / 2) * leaf_size;
    median_split(idx.data() + b, idx.data() + e, left, [&](std::uint32_t t) -> const glm::vec3& { return tri_cent[t]; });
    const std::uint32_t l = build_instance(idx, b, b + left, static_cast<std::int32_t>(node), inst);
    const std::uint32_t r = build_instance(idx, b + left, e, static_cast<std::int32_t>(node), inst);
    (void)l;
    Aabb box = w.bvh.nodes[node + 1].box, local = w.local_box[node + 1];
    grow(box, w.bvh.nodes[r].box);
    grow(local, w.local_box[r]);
    w.bvh.nodes[node].box = box;
    w.bvh.nodes[node].right_or_first = r;
    w.bvh.nodes[node].count = 0;
    w.local_box[node] = local;
    w.bvh.subtree_prims[node][1] = w.leaf_count();
    return node;
  }
};

}  // namespace

namespace {

// The models the scene's groups use, each mesh read once and normalised.
std::map<std::string, ModelGeom> read_models(const SceneDesc& scene, const std::filesystem::path& mesh_dir) {
  std::map<std::string, ModelGeom> models;
  for (const ModelDesc& m : scene.models) {
    bool used = false;
    for (const InstanceGroup& g : scene.groups) used = used || g.model == m.id;
    if (!used) continue;
    const std::filesystem::path file = mesh_dir / m.mesh;
    if (!std::filesystem::exists(file))
      throw MeshError(file.string(), 0,
                      "mesh not found (scene " + scene.file + ", field models." + m.id +
                          ".mesh); run scripts/fetch-meshes, which unpacks it from "
                          "/usr/share/doc/libcgal-dev/data.tar.gz (Debian package libcgal-demo, installed by "
                          "scripts/install-deps), or set CULLPROOF_MESH_DIR");
    models[m.id] = normalise(read_off(file), m);
  }
  return models;
}

// An instance and the model geometry it places.
struct Placed {
  Instance inst;
  const ModelGeom* geom;
};

// The floor (when the scene has one) and every group's instances, placed by the group's pattern
// and seed, with the scene's moving instances marked.
std::vector<Placed> place_instances(const SceneDesc& scene, const std::map<std::string, ModelGeom>& models,
                                    const ModelGeom& floor) {
  std::vector<Placed> placed;
  if (scene.floor) {
    Placed p;
    p.inst.group = -1;
    p.inst.model = "floor";
    p.inst.position = scene.floor->center;
    p.geom = &floor;
    placed.push_back(p);
  }
  for (std::size_t gi = 0; gi < scene.groups.size(); ++gi) {
    const InstanceGroup& g = scene.groups[gi];
    SplitMix64 rng = world_rng(g.seed);
    for (int i = 0; i < g.count; ++i) {
      Placed p;
      p.inst.group = static_cast<int>(gi);
      p.inst.index_in_group = i;
      p.inst.model = g.model;
      glm::dvec3 pos = g.origin;
      if (g.pattern == "row") pos.x += i * g.spacing;
      if (g.pattern == "grid") {
        pos.x += (i % g.columns) * g.spacing;
        pos.z += (i / g.columns) * g.spacing;
      }
      if (g.pattern == "scatter") {
        pos.x = g.area[0] + rng.uniform() * (g.area[2] - g.area[0]);
        pos.z = g.area[1] + rng.uniform() * (g.area[3] - g.area[1]);
      }
      double yaw = g.yaw_deg;
      if (g.random_yaw) yaw += 360.0 * rng.uniform();
      p.inst.position = pos;
      p.inst.rotation = rot_y(yaw);
      p.geom = &models.at(g.model);
      placed.push_back(p);
    }
  }
  for (const MovingDesc& m : scene.moving)
    for (Placed& p : placed)
      if (p.inst.group == m.group &&
          (m.instances.empty() || std::find(m.instances.begin(), m.instances.end(), p.inst.index_in_group) != m.instances.end()))
        p.inst.moving = true;
  return placed;
}

// Triangles per leaf: the scene's leaf_triangles, or the size whose hierarchy comes closest to
// its target_nodes (the smallest with no more nodes, or one less when that is closer).
std::size_t leaf_size(const std::vector<Placed>& placed, const HierarchyDesc& h) {
  std::vector<std::size_t> tri_counts;
  for (const Placed& p : placed) tri_counts.push_back(p.geom->triangles.size());
  const std::size_t max_t = *std::max_element(tri_counts.begin(), tri_counts.end());
  auto nodes_for = [&](std::size_t L) {
    std::size_t leaves = 0;
    for (std::size_t t : tri_counts) leaves += (t + L - 1) / L;
    return 2 * leaves - 1;
  };
  std::size_t L = h.leaf_triangles > 0 ? static_cast<std::size_t>(h.leaf_triangles) : 1;
  if (h.target_nodes > 0) {
    const std::size_t target = static_cast<std::size_t>(h.target_nodes);
    std::size_t lo = 1, hi = std::max<std::size_t>(1, max_t);  // smallest L with nodes <= target
    while (lo < hi) {
      const std::size_t mid = lo + (hi - lo) / 2;
      if (nodes_for(mid) <= target) hi = mid;
      else lo = mid + 1;
    }
    L = lo;
    if (L > 1) {
      const auto diff = [&](std::size_t x) {
        const std::size_t n = nodes_for(x);
        return n > target ? n - target : target - n;
      };
      if (diff(L - 1) < diff(L)) L = L - 1;
    }
  }
  return L;
}

// The top levels of the hierarchy: a median split of the instances' world-box centres; each
// instance's own subtree is built over its world triangles when the split reaches it.
struct TopBuilder {
  Builder& bld;
  World& w;
  std::vector<Placed>& placed;
  std::vector<Aabb> inst_box;

  TopBuilder(Builder& b, World& world, std::vector<Placed>& p) : bld(b), w(world), placed(p), inst_box(p.size(), empty_box()) {
    for (std::size_t i = 0; i < placed.size(); ++i) {
      const ModelGeom& g = *placed[i].geom;
      for (const glm::vec3& v : g.vertices)
        grow(inst_box[i], glm::vec3(placed[i].inst.position + placed[i].inst.rotation * glm::dvec3(v)));
    }
  }

  // The instance's triangles in world space (boxes, centres) and in model space, into bld.
  void triangle_geometry(const Placed& p) {
    const ModelGeom& g = *p.geom;
    bld.tri_box.resize(g.triangles.size());
    bld.tri_local.resize(g.triangles.size());
    bld.tri_cent.resize(g.triangles.size());
    std::vector<glm::vec3> wv(g.vertices.size());
    for (std::size_t i = 0; i < g.vertices.size(); ++i)
      wv[i] = glm::vec3(p.inst.position + p.inst.rotation * glm::dvec3(g.vertices[i]));
    for (std::size_t t = 0; t < g.triangles.size(); ++t) {
      const auto& tr = g.triangles[t];
      Aabb b{wv[tr[0]], wv[tr[0]]}, l{g.vertices[tr[0]], g.vertices[tr[0]]};
      for (int k = 1; k < 3; ++k) {
        grow(b, wv[tr[static_cast<std::size_t>(k)]]);
        grow(l, g.vertices[tr[static_cast<std::size_t>(k)]]);
      }
      bld.tri_box[t] = b;
      bld.tri_local[t] = l;
      bld.tri_cent[t] = b.center();
    }
  }

  std::uint32_t build_leaf_instance(Placed& p, std::int32_t parent) {
    triangle_geometry(p);
    std::vector<std::uint32_t> idx(p.geom->triangles.size());
    std::iota(idx.begin(), idx.end(), 0u);
    const std::int32_t inst = static_cast<std::int32_t>(w.instances.size());
    w.instances.push_back(p.inst);
    const std::uint32_t root = bld.build_instance(idx, 0, idx.size(), parent, inst);
    Instance& in = w.instances.back();
    in.root = root;
    in.node_end = w.node_count();
    in.triangles = p.geom->triangles.size();
    return root;
  }

  std::uint32_t build(std::vector<std::uint32_t>& ord, std::size_t b, std::size_t e, std::int32_t parent) {
    if (e - b == 1) return build_leaf_instance(placed[ord[b]], parent);
    const std::uint32_t node = bld.new_node(parent, -1);
    w.bvh.subtree_prims[node][0] = w.leaf_count();
    const std::size_t mid = b + (e - b) / 2;
    median_split(ord.data() + b, ord.data() + e, mid - b, [&](std::uint32_t i) { return inst_box[i].center(); });
    build(ord, b, mid, static_cast<std::int32_t>(node));
    const std::uint32_t r = build(ord, mid, e, static_cast<std::int32_t>(node));
    Aabb box = w.bvh.nodes[node + 1].box;
    grow(box, w.bvh.nodes[r].box);
    w.bvh.nodes[node].box = box;
    w.bvh.nodes[node].right_or_first = r;
    w.bvh.nodes[node].count = 0;
    w.bvh.subtree_prims[node][1] = w.leaf_count();
    return node;
  }
};

}  // namespace

World build_world(const SceneDesc& scene, const std::filesystem::path& mesh_dir) {
  World w;
  const std::map<std::string, ModelGeom> models = read_models(scene, mesh_dir);
  const ModelGeom floor = scene.floor ? floor_geom(*scene.floor) : ModelGeom{};
  std::vector<Placed> placed = place_instances(scene, models, floor);
  const std::size_t L = leaf_size(placed, scene.hierarchy);
  w.leaf_triangles = static_cast<std::uint32_t>(L);

  Builder bld{w, static_cast<std::uint32_t>(L), {}, {}, {}};
  TopBuilder top(bld, w, placed);
  std::vector<std::uint32_t> order(placed.size());
  std::iota(order.begin(), order.end(), 0u);
  top.build(order, 0, order.size(), -1);

  for (const Placed& p : placed) {
    w.triangles += p.geom->triangles.size();
    w.polygons += p.geom->polygons;
  }
  w.bounds = w.bvh.nodes.empty() ? Aabb{} : w.bvh.nodes[0].box;
  return w;
}

namespace {

// Pose of a moving instance at `frame`.
void moved_pose(const MovingDesc& m, const Instance& base, int frame, glm::dmat3& rot, glm::dvec3& pos) {
  rot = base.rotation;
  pos = base.position;
  if (m.motion == "spin") {
    rot = base.rotation * rot_y(m.rate * frame);
  } else if (m.motion == "translate") {
    pos = base.position + m.velocity * static_cast<double>(frame);
  } else {  // orbit
    const glm::dmat3 r = rot_y(m.rate * frame);
    pos = m.center + r * (base.position - m.center);
    rot = r * base.rotation;
  }
}

Aabb transform_box(const Aabb& b, const glm::dmat3& r, const glm::dvec3& t) {
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (int k = 0; k < 8; ++k) {
    const glm::dvec3 c((k & 1) ? b.max.x : b.min.x, (k & 2) ? b.max.y : b.min.y, (k & 4) ? b.max.z : b.min.z);
    const glm::dvec3 p = t + r * c;
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // Rounded outward: the float box contains the double-precision image of the model-space box.
  return Aabb{glm::vec3(float_at_most(lo.x), float_at_most(lo.y), float_at_most(lo.z)),
              glm::vec3(float_at_least(hi.x), float_at_least(hi.y), float_at_least(hi.z))};
}

bool same(const Aabb& a, const Aabb& b) {
  return a.min.x == b.min.x && a.min.y == b.min.y && a.min.z == b.min.z && a.max.x == b.max.x && a.max.y == b.max.y &&
         a.max.z == b.max.z;
}

}  // namespace

std::vector<std::uint32_t> move_objects(const SceneDesc& scene, World& w, int frame) {
  std::vector<std::uint32_t> changed;
  std::vector<char> dirty_parent(w.bvh.nodes.size(), 0);
  for (const MovingDesc& m : scene.moving) {
    for (const Instance& in : w.instances) {
      if (in.group != m.group) continue;
      if (!m.instances.empty() && std::find(m.instances.begin(), m.instances.end(), in.index_in_group) == m.instances.end())
        continue;
      glm::dmat3 rot;
      glm::dvec3 pos;
      moved_pose(m, in, frame, rot, pos);
      // Children have larger indices than their parent: backwards is bottom-up.
      for (std::uint32_t n = in.node_end; n-- > in.root;) {
        BvhNode& node = w.bvh.nodes[n];
        Aabb box;
        if (node.is_leaf()) {
          box = transform_box(w.local_box[n], rot, pos);
          w.bvh.prim_boxes[node.right_or_first] = box;
        } else {
          box = w.bvh.nodes[n + 1].box;
          grow(box, w.bvh.nodes[node.right_or_first].box);
        }
        if (!same(box, node.box)) changed.push_back(n);
        node.box = box;
      }
      if (w.parent[in.root] >= 0) dirty_parent[static_cast<std::size_t>(w.parent[in.root])] = 1;
    }
  }
  // Refit the top levels above moved instances (bottom-up: highest index first).
  for (std::size_t n = w.bvh.nodes.size(); n-- > 0;) {
    if (!dirty_parent[n]) continue;
    BvhNode& node = w.bvh.nodes[n];
    Aabb box = w.bvh.nodes[n + 1].box;
    grow(box, w.bvh.nodes[node.right_or_first].box);
    if (!same(box, node.box)) changed.push_back(static_cast<std::uint32_t>(n));
    node.box = box;
    if (w.parent[n] >= 0) dirty_parent[static_cast<std::size_t>(w.parent[n])] = 1;
  }
  std::sort(changed.begin(), changed.end());
  return changed;
}

// ---------------------------------------------------------------------------------------------
// Camera paths

namespace {

// The camera walking a path: its eye, yaw, pitch and axes, the frames so far, and the ground
// rectangle it stays inside. Each path kind is a member; the random steps draw from `rng` in the
// order they are taken, so a path is a function of the scene's seed.
class PathWalker {
 public:
  PathWalker(const CameraPathDesc& d, const World& world)
      : d_(d), n_(d.frames), rng_(world_rng(d.seed)), eye_(d.eye), yaw_(d.yaw_deg), pitch_(d.pitch_deg),
        R_(orient(yaw_, pitch_)) {
    if (d.bounds) {
      bounds_ = *d.bounds;
    } else {
      const double x0 = world.bounds.min.x, x1 = world.bounds.max.x, z0 = world.bounds.min.z, z1 = world.bounds.max.z;
      const double ix = 0.05 * (x1 - x0), iz = 0.05 * (z1 - z0);
      bounds_ = {x0 + ix, z0 + iz, x1 - ix, z1 - iz};
    }
    centre_ = glm::dvec2(0.5 * (bounds_[0] + bounds_[2]), 0.5 * (bounds_[1] + bounds_[3]));
    out_.reserve(static_cast<std::size_t>(n_));
  }

  std::vector<CameraFrame> walk() {
    switch (d_.kind) {
      case PathKind::navigation: navigation(); break;
      case PathKind::translation_rotation: translation_rotation(); break;
      case PathKind::rotation: rotation(); break;
      case PathKind::translation: translation(); break;
      case PathKind::keyframes: keyframes(); break;
    }
    out_.resize(static_cast<std::size_t>(n_));
    return std::move(out_);
  }

 private:
  bool inside(const glm::dvec3& e) const {
    return e.x >= bounds_[0] && e.x <= bounds_[2] && e.z >= bounds_[1] && e.z <= bounds_[3];
  }
  // Yaw (degrees) that looks from e towards the bounds' centre.
  double yaw_to_centre(const glm::dvec3& e) const {
    const glm::dvec2 v = centre_ - glm::dvec2(e.x, e.z);
    return std::atan2(-v.x, -v.y) * 180.0 / kPi;  // forward = (-sin yaw, 0, -cos yaw)
  }
  static double wrap(double a) {  // to (-180, 180]
    while (a > 180.0) a -= 360.0;
    while (a <= -180.0) a += 360.0;
    return a;
  }
  bool more() const { return static_cast<int>(out_.size()) < n_; }
  void push() {
    CameraFrame f;
    f.eye = eye_;
    f.axes = R_;
    out_.push_back(f);
  }
  glm::dvec3 fwd() const { return glm::dvec3(-std::sin(yaw_ * kPi / 180.0), 0.0, -std::cos(yaw_ * kPi / 180.0)); }
  glm::dvec3 right() const { return glm::dvec3(std::cos(yaw_ * kPi / 180.0), 0.0, -std::sin(yaw_ * kPi / 180.0)); }
  glm::dvec3 towards_centre() const {
    return glm::normalize(glm::dvec3(centre_.x - eye_.x, 0.0, centre_.y - eye_.z));
  }

  // A step that would leave the bounds becomes a turn towards the centre.
  void steer_or_move(const glm::dvec3& step, double dyaw) {
    const glm::dvec3 next = eye_ + step;
    if (!step.x && !step.z) {
      yaw_ += dyaw;
    } else if (inside(next)) {
      eye_ = next;
      yaw_ += dyaw;
    } else {
      const double want = wrap(yaw_to_centre(eye_) - yaw_);
      const double t = std::max(d_.turn_deg, 1.0);
      yaw_ += std::abs(want) < t ? want : (want > 0 ? t : -t);
    }
    R_ = orient(yaw_, pitch_);
  }
  // `len` frames (fewer at the end of the path), each one steer_or_move(step(), dyaw).
  template <class Step>
  void steps(int len, Step step, double dyaw) {
    for (int k = 0; k < len && more(); ++k) {
      steer_or_move(step(), dyaw);
      push();
    }
  }

  // A walk of random episodes: forward, turning on the spot, walking while turning, looking up
  // or down and back, strafing, standing still.
  void navigation() {
    push();
    while (more()) {
      const double u = rng_.uniform();
      const int sign = rng_.uniform() < 0.5 ? -1 : 1;
      if (u < 0.35) {
        steps(rng_.range(20, 80), [&] { return fwd() * d_.speed; }, 0.0);
      } else if (u < 0.55) {
        steps(rng_.range(10, 45), [] { return glm::dvec3(0.0); }, sign * d_.turn_deg);
      } else if (u < 0.75) {
        steps(rng_.range(15, 60), [&] { return fwd() * d_.speed; }, sign * 0.5 * d_.turn_deg);
      } else if (u < 0.82) {
        const int len = rng_.range(5, 20);
        for (int k = 0; k < 2 * len && more(); ++k) {
          pitch_ += (k < len ? sign : -sign) * 0.5 * d_.turn_deg;
          if (k == 2 * len - 1) pitch_ = d_.pitch_deg;
          R_ = orient(yaw_, pitch_);
          push();
        }
      } else if (u < 0.90) {
        steps(rng_.range(10, 40), [&] { return right() * (sign * 0.5 * d_.speed); }, 0.0);
      } else {
        const int len = rng_.range(5, 20);
        for (int k = 0; k < len && more(); ++k) push();
      }
    }
  }

  // Moving forward and turning every frame, the turn rate varying, its sign flipping every 97
  // frames; at the bounds, turning towards the centre while still moving a little.
  void translation_rotation() {
    push();
    int sign = 1;
    for (int f = 1; f < n_; ++f) {
      if (f % 97 == 0) sign = -sign;
      const double rate = d_.turn_deg * (0.3 + 0.7 * std::abs(std::sin(f * 0.05)));
      glm::dvec3 next = eye_ + fwd() * d_.speed;
      double dyaw = sign * rate;
      if (!inside(next)) {
        const double want = wrap(yaw_to_centre(eye_) - yaw_);
        dyaw = want > 0 ? std::max(d_.turn_deg, 1.0) : -std::max(d_.turn_deg, 1.0);
        next = eye_ + fwd() * (0.25 * d_.speed);
        if (!inside(next)) next = eye_ + towards_centre() * (0.25 * d_.speed);
      }
      eye_ = next;
      yaw_ += dyaw;
      R_ = orient(yaw_, pitch_);
      push();
    }
  }

  // Turning on the spot about the camera's own x or y axis, pitch kept within 40 degrees.
  void rotation() {
    push();
    double pitch_acc = pitch_;
    while (more()) {
      const bool about_x = rng_.uniform() < 0.3;
      int sign = rng_.uniform() < 0.5 ? -1 : 1;
      const int len = rng_.range(20, 90);
      for (int k = 0; k < len && more(); ++k) {
        if (about_x) {
          if (std::abs(pitch_acc + sign * d_.turn_deg) > 40.0) sign = -sign;
          pitch_acc += sign * d_.turn_deg;
          R_ = R_ * rot_x(sign * d_.turn_deg);
        } else {
          R_ = R_ * rot_y(sign * d_.turn_deg);
        }
        push();
      }
    }
  }

  // Moving in random directions; the orientation never changes, so the plane normals stay
  // bitwise equal from frame to frame.
  void translation() {
    push();
    while (more()) {
      const double a = 2.0 * kPi * rng_.uniform();
      glm::dvec3 dir(std::cos(a), 0.0, std::sin(a));
      const int len = rng_.range(20, 80);
      for (int k = 0; k < len && more(); ++k) {
        if (!inside(eye_ + dir * d_.speed)) dir = towards_centre();
        eye_ += dir * d_.speed;
        push();
      }
    }
  }

  // Linear interpolation of eye, yaw and pitch between the scene's keyframes.
  void keyframes() {
    const auto& ks = d_.keyframes;
    std::size_t seg = 0;
    for (int f = 0; f < n_; ++f) {
      while (seg + 2 < ks.size() && f > ks[seg + 1].frame) ++seg;
      const Keyframe& a = ks[seg];
      const Keyframe& b = ks[seg + 1];
      const double t = static_cast<double>(f - a.frame) / static_cast<double>(b.frame - a.frame);
      eye_ = a.eye + (b.eye - a.eye) * t;
      R_ = orient(a.yaw_deg + (b.yaw_deg - a.yaw_deg) * t, a.pitch_deg + (b.pitch_deg - a.pitch_deg) * t);
      push();
    }
  }

  const CameraPathDesc& d_;
  const int n_;
  SplitMix64 rng_;
  std::array<double, 4> bounds_{};
  glm::dvec2 centre_{};
  glm::dvec3 eye_;
  double yaw_, pitch_;
  glm::dmat3 R_;
  std::vector<CameraFrame> out_;
};

// Each frame's field of view (zooming when the scene says so) and how the camera moved since the
// previous frame, as the float view the cullers see it.
void label_frames(const ProjectionDesc& p, std::vector<CameraFrame>& out) {
  const int n = static_cast<int>(out.size());
  for (int f = 0; f < n; ++f) {
    CameraFrame& c = out[static_cast<std::size_t>(f)];
    c.fovy_deg = p.fovy_deg;
    if (p.zoom_fovy_end && n > 1) c.fovy_deg = p.fovy_deg + (*p.zoom_fovy_end - p.fovy_deg) * f / (n - 1);
    if (f == 0) {
      c.motion = FrameMotion::first;
      continue;
    }
    const CameraFrame& prev = out[static_cast<std::size_t>(f - 1)];
    const bool same_eye = glm::vec3(c.eye) == glm::vec3(prev.eye);
    const bool same_axes = glm::mat3(c.axes) == glm::mat3(prev.axes);
    c.motion = same_eye && same_axes ? FrameMotion::still
               : same_axes           ? FrameMotion::translation
               : same_eye            ? FrameMotion::rotation
                                     : FrameMotion::general;
  }
}

}  // namespace

std::vector<CameraFrame> camera_path(const SceneDesc& scene, const World& world) {
  std::vector<CameraFrame> out = PathWalker(scene.camera, world).walk();
  label_frames(scene.projection, out);
  return out;
}

std::vector<View> frame_views(const ProjectionDesc& p, const CameraFrame& c) {
  const glm::mat3 axes(c.axes);
  auto view_matrix = [&](const glm::vec3& eye) {
    glm::mat4 v(1.0f);
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) v[col][row] = axes[row][col];  // rotation part: R^T
    for (int row = 0; row < 3; ++row) v[3][row] = -glm::dot(axes[row], eye);
    return v;
  };
  auto make = [&](const glm::mat4& proj, const glm::vec3& eye, bool persp) {
    View v;
    v.look = view_matrix(eye);
    v.clip = proj * v.look;
    v.proj = proj;
    v.frustum = frustum_from_matrix(v.clip, v.depth);
    v.eye = eye;
    v.axes = axes;
    v.perspective = persp;
    return v;
  };
  const float n = static_cast<float>(p.near_dist), f = static_cast<float>(p.far_dist);
  const glm::vec3 eye(c.eye);
  std::vector<View> out;
  switch (p.kind) {
    case ProjectionKind::perspective: {
      const float t = static_cast<float>(p.near_dist * std::tan(c.fovy_deg * kPi / 360.0));
      const float hw = t * static_cast<float>(p.aspect);
      out.push_back(make(off_axis_projection(-hw, hw, -t, t, n, f), eye, true));
      break;
    }
    case ProjectionKind::off_axis:
      out.push_back(make(off_axis_projection(static_cast<float>(p.left), static_cast<float>(p.right),
                                             static_cast<float>(p.bottom), static_cast<float>(p.top), n, f),
                         eye, true));
      break;
    case ProjectionKind::stereo: {
      const float t = static_cast<float>(p.near_dist * std::tan(c.fovy_deg * kPi / 360.0));
      const float hw = t * static_cast<float>(p.aspect);
      for (int e = 0; e < 2; ++e) {
        const double offset = (e == 0 ? -0.5 : 0.5) * p.eye_separation;  // left eye at -right
        const float shift = static_cast<float>(offset * p.near_dist / p.convergence);
        const glm::vec3 ee(c.eye + offset * c.axes[0]);
        out.push_back(make(off_axis_projection(-hw - shift, hw - shift, -t, t, n, f), ee, true));
      }
      break;
    }
    case ProjectionKind::orthographic:
      out.push_back(make(orthographic_projection(static_cast<float>(p.left), static_cast<float>(p.right),
                                                 static_cast<float>(p.bottom), static_cast<float>(p.top), n, f),
                         eye, false));
      break;
  }
  return out;
}

CullView cull_view(const View& v) {
  CullView c;
  c.frustum.planes = v.frustum;
  c.frustum.matrix = v.clip;
  c.frustum.depth = v.depth;
  c.view = v.look;
  c.projection = v.proj;
  c.eye = v.eye;
  c.axes = v.axes;
  c.perspective = v.perspective;
  return c;
}

}  // namespace cullproof::sim

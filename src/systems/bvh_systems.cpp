// cullproof's own culling systems: the fast family's hierarchies over the objects' enclosing boxes,
// refitted when objects move, and the same per-box test in a flat loop beside them.
//
// Sources: Assarsson & Möller 2000, "Optimized View Frustum Culling Algorithms for Bounding
// Boxes", §3.1 (the n/p-vertex test), §3.2 (plane coherency), §3.3 (the octant test), §3.4 (plane
// masking), §3.5 (TR coherency, through the hierarchy culler of hierarchy.hpp); the Cesium
// text on hierarchical culling with plane masking. The BVH is build_bvh's median split (leaves of
// four objects); after objects move it is refitted (refit_bvh), not rebuilt, as engines do between
// rebuilds; the wide BVHs are collapsed again from the refitted binary one.
//
// An object is culled by its enclosing box (enclosing_box: rounded outward), so a sphere or an
// OBB is never rejected while its box is visible; a box that straddles a plane makes its object
// `intersecting` even where the object itself lies outside (a false intersect, which a
// conservative claim allows). Claim: conservative within the n/p-vertex test's float tolerance.
#include "builtin_systems.hpp"

#include "cullproof/core/cull.hpp"
#include "cullproof/simd/bvh_wide.hpp"
#include "cullproof/systems/hierarchy.hpp"

#include <stdexcept>
#include <memory>
#include <string>
#include <unordered_map>

namespace cullproof::detail {

namespace {

constexpr std::uint32_t kLeafSize = 4;

// The scene's objects as boxes, by position in the scene, with their ids.
struct Boxes {
  std::vector<std::uint32_t> ids;
  std::unordered_map<std::uint32_t, std::uint32_t> position;
  std::vector<Aabb> boxes;

  explicit Boxes(const Scene& scene) {
    ids.reserve(scene.objects.size());
    boxes.reserve(scene.objects.size());
    position.reserve(scene.objects.size());
    for (const SceneObject& o : scene.objects) {
      position.emplace(o.id, std::uint32_t(ids.size()));
      ids.push_back(o.id);
      boxes.push_back(enclosing_box(o.world));
    }
  }
  void move(const std::vector<SceneObject>& moved) {
    for (const SceneObject& o : moved) {
      const auto it = position.find(o.id);
      if (it == position.end()) throw std::invalid_argument("moved object " + std::to_string(o.id) + " is not in the scene");
      boxes[it->second] = enclosing_box(o.world);
    }
  }
  // The traversals list positions; the set a system answers lists ids.
  void to_ids(VisibleSet& out) const {
    for (std::uint32_t& i : out.indices) i = ids[i];
  }
};

enum class Traversal { flat, plain, masked, coherent, wide4, wide8 };

struct BoxSystem {
  Traversal kind;
  Boxes objects;
  Bvh bvh;
  Bvh4 bvh4;
  Bvh8 bvh8;
  BvhCoherency cache;

  BoxSystem(Traversal k, const Scene& scene) : kind(k), objects(scene) {
    if (kind != Traversal::flat) bvh = build_bvh(objects.boxes, kLeafSize);
    collapse();
  }
  void collapse() {
    if (kind == Traversal::wide4) bvh4 = build_bvh4(bvh);
    if (kind == Traversal::wide8) bvh8 = build_bvh8(bvh);
  }
  void update(const std::vector<SceneObject>& moved) {
    objects.move(moved);
    if (kind == Traversal::flat) return;
    refit_bvh(bvh, objects.boxes);
    collapse();
  }
  void cull(const CullView& view, VisibleSet& out) {
    const Frustum& f = view.frustum.planes;
    CullStats stats;
    switch (kind) {
      case Traversal::flat:
        out.clear();
        for (std::uint32_t i = 0; i < objects.boxes.size(); ++i) {
          const Visibility v = pn_vertex(f, objects.boxes[i]);
          if (v != Visibility::outside) out.indices.push_back(i), out.verdicts.push_back(v);
        }
        break;
      case Traversal::plain: cull_bvh_plain(f, bvh, out, stats); break;
      case Traversal::masked: cull_bvh_masked(f, bvh, out, stats); break;
      case Traversal::coherent: cull_bvh_coherent(f, bvh, cache, out, stats); break;
      case Traversal::wide4: cull_bvh4_masked(f, bvh4, out, stats); break;
      case Traversal::wide8: cull_bvh8_masked(f, bvh8, out, stats); break;
    }
    objects.to_ids(out);
  }
};

// A node test of the hierarchy culler (cullproof/systems/hierarchy.hpp) over a BVH of one object
// per leaf, so that every object's verdict comes from the node test and the caches it keeps.
// After objects move, the BVH is refitted and the nodes whose boxes changed lose their TR state.
struct NodeTestSystem {
  Boxes objects;
  std::unique_ptr<Bvh> bvh;  // the culler keeps its address
  HierarchyCuller culler;

  NodeTestSystem(HierarchyTest test, const Scene& scene)
      : objects(scene), bvh(std::make_unique<Bvh>(build_bvh(objects.boxes, 1))), culler(test, *bvh) {}
  void update(const std::vector<SceneObject>& moved) {
    objects.move(moved);
    std::vector<Aabb> before(bvh->nodes.size());
    for (std::size_t n = 0; n < before.size(); ++n) before[n] = bvh->nodes[n].box;
    refit_bvh(*bvh, objects.boxes);
    std::vector<std::uint32_t> changed;
    for (std::size_t n = 0; n < before.size(); ++n)
      if (before[n].min != bvh->nodes[n].box.min || before[n].max != bvh->nodes[n].box.max)
        changed.push_back(static_cast<std::uint32_t>(n));
    culler.moved(changed);
  }
  void cull(const CullView& view, VisibleSet& out) {
    culler.cull(view, out);
    objects.to_ids(out);
  }
};

SystemInfo own_info(const char* name, const char* description, const char* source, double tolerance) {
  SystemInfo info;
  info.name = name;
  info.description = description;
  info.source = source;
  info.claim = Claim::conservative;
  info.tolerance = tolerance;
  info.touching = "by the enclosing box: touching from outside is intersecting, from inside inside";
  info.origin = Origin::own;
  return info;
}

System node_test_system(const char* name, const char* description, const char* source, HierarchyTest test) {
  // The octant and TR tests derive planes and distances from the given ones: the tolerance of
  // the derived methods (octant-corrected, tr-coherency).
  return make_system(
      own_info(name, description, source, 1e-5), [test](const Scene& s) { return NodeTestSystem(test, s); },
      [](NodeTestSystem& s, const std::vector<SceneObject>& moved) { s.update(moved); },
      [](NodeTestSystem& s, const CullView& v, VisibleSet& out) { s.cull(v, out); });
}

System box_system(const char* name, const char* description, const char* source, Traversal kind) {
  // The n/p-vertex test's tolerance: its plane evaluations round.
  return make_system(
      own_info(name, description, source, 1e-6), [kind](const Scene& s) { return BoxSystem(kind, s); },
      [](BoxSystem& s, const std::vector<SceneObject>& moved) { s.update(moved); },
      [](BoxSystem& s, const CullView& v, VisibleSet& out) { s.cull(v, out); });
}

}  // namespace

std::vector<System> make_builtin_systems() {
  return {
      box_system("flat-pn-vertex", "every object's enclosing box, n/p-vertex test, in a flat loop",
                 "Assarsson & Möller 2000, §3.1", Traversal::flat),
      box_system("bvh-plain", "binary median-split BVH, six planes per node, refitted when objects move",
                 "Assarsson & Möller 2000, §3.1; Cesium, basic hierarchical culling", Traversal::plain),
      box_system("bvh-masked", "binary BVH with plane masks handed to children, refitted when objects move",
                 "Assarsson & Möller 2000, §3.4; Cesium, hierarchical culling with plane masking", Traversal::masked),
      box_system("bvh-coherent", "binary BVH, plane masks and the plane that rejected each node last frame first",
                 "Assarsson & Möller 2000, §3.2 and §3.4", Traversal::coherent),
      box_system("bvh4-masked", "4-wide BVH collapsed from the binary one, plane masks, SIMD lanes per node",
                 "Assarsson & Möller 2000, §3.4; Dammertz, Hanika & Keller 2008", Traversal::wide4),
      box_system("bvh8-masked", "8-wide BVH collapsed from the binary one, plane masks, SIMD lanes per node",
                 "Assarsson & Möller 2000, §3.4; Dammertz, Hanika & Keller 2008", Traversal::wide8),
      node_test_system("bvh-pc-octant",
                       "binary BVH of one object per leaf, plane coherency and the corrected octant test (plane "
                       "coherency alone when the frustum is not symmetric or not bounded)",
                       "Assarsson & Möller 2000, §3.2 and §3.3", HierarchyTest::pc_octant),
      node_test_system("bvh-pc-tr",
                       "binary BVH of one object per leaf, plane coherency and translation/rotation coherency "
                       "(TR only while the camera translates or turns about one axis, the projection unchanged)",
                       "Assarsson & Möller 2000, §3.2 and §3.5", HierarchyTest::pc_tr),
      node_test_system("bvh-pc-octant-tr", "binary BVH of one object per leaf, plane coherency, octant and TR coherency",
                       "Assarsson & Möller 2000, §3.2, §3.3 and §3.5", HierarchyTest::pc_octant_tr),
  };
}

}  // namespace cullproof::detail

// The culling-system interface, the scene families and a system judged on them: enclosing boxes
// hold their volumes (the oracle decides), a refitted BVH encloses its subtrees and culls as a
// rebuilt one, runs are drawn deterministically with every camera event and motion, visible sets
// that are not ones are faults, and cullproof's own systems hold their claims on every family.
#include "cullproof/core/cull.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/gtest/gtest.hpp"
#include "cullproof/oracle/oracle.hpp"
#include "cullproof/scenes/scenes.hpp"
#include "cullproof/systems/system.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <string>

using namespace cullproof;

namespace {

// The box as six half-spaces x >= min.x, -x >= -max.x, ...
CaseFrustum box_as_frustum(const Aabb& b) {
  Frustum f;
  for (int k = 0; k < 3; ++k) {
    glm::vec3 n(0.0f);
    n[k] = 1.0f;
    f[2 * k] = Plane{n, -b.min[k]};
    f[2 * k + 1] = Plane{-n, b.max[k]};
  }
  return frustum_spec(f);
}

bool finite_box(const Aabb& b) {
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(b.min[k]) || !std::isfinite(b.max[k])) return false;
  return true;
}

}  // namespace

// Every volume of every distribution (the whole float range, `huge` and `subnormal` included) lies
// inside its enclosing box, decided exactly; and the box is tight: a box is its own, and the box of
// a sphere or OBB is within a few ulps of its extreme points computed in double.
TEST(EnclosingBox, HoldsEveryVolumeExactly) {
  std::size_t checked = 0, infinite = 0;
  for (const gen::Distribution d : gen::parse_distributions("all"))
    for (std::uint64_t i = 0; i < 150; ++i) {
      const Volume v = gen::draw(d, 3, i).value().volume;
      const Aabb b = enclosing_box(v);
      if (const auto* box = std::get_if<Aabb>(&v)) {
        EXPECT_EQ(std::memcmp(box, &b, sizeof b), 0);
      }
      if (!finite_box(b)) {
        ++infinite;
        continue;
      }
      ++checked;
      EXPECT_EQ(oracle::truth(box_as_frustum(b), v), Visibility::inside)
          << gen::to_string(d) << " case " << i << ": the volume reaches outside its enclosing box";
    }
  EXPECT_GT(checked, 2000u);
  RecordProperty("infinite_boxes", int(infinite));
}

TEST(EnclosingBox, RoundsOutwardOnlyWhereTheSumRounds) {
  // Exact sums: the box is exact.
  const Aabb s = enclosing_box(Sphere{{1.0f, -2.0f, 0.5f}, 0.25f});
  EXPECT_EQ(s.min, glm::vec3(0.75f, -2.25f, 0.25f));
  EXPECT_EQ(s.max, glm::vec3(1.25f, -1.75f, 0.75f));
  // 1 + 2^-30 is not a float: the box reaches the next float beyond it, on both sides.
  const Aabb t = enclosing_box(Sphere{{1.0f, 0.0f, 0.0f}, 0x1p-30f});
  EXPECT_EQ(t.max.x, std::nextafter(1.0f, 2.0f));
  EXPECT_EQ(t.min.x, std::nextafter(1.0f, 0.0f));
  EXPECT_EQ(enclosing_box(Point{3.0f, 4.0f, 5.0f}).min, glm::vec3(3.0f, 4.0f, 5.0f));
}

TEST(RefitBvh, EnclosesEverySubtreeAndCullsAsARebuiltOne) {
  const scenes::SceneRun run = scenes::draw_run("clusters", 5, 0, {500, 2});
  std::vector<Aabb> boxes;
  for (const SceneObject& o : run.scene.objects) boxes.push_back(enclosing_box(o.world));
  Bvh bvh = build_bvh(boxes, 4);
  // Move every third box far away and grow every fifth.
  for (std::size_t i = 0; i < boxes.size(); i += 3) boxes[i].min += glm::vec3(60.0f), boxes[i].max += glm::vec3(60.0f);
  for (std::size_t i = 0; i < boxes.size(); i += 5) boxes[i].max += glm::vec3(7.0f);
  refit_bvh(bvh, boxes);
  for (std::size_t n = 0; n < bvh.nodes.size(); ++n) {
    const auto [first, last] = bvh.subtree_prims[n];
    for (std::uint32_t k = first; k < last; ++k) {
      const Aabb& b = boxes[bvh.prim_order[k]];
      EXPECT_TRUE(glm::all(glm::lessThanEqual(bvh.nodes[n].box.min, b.min)) &&
                  glm::all(glm::lessThanEqual(b.max, bvh.nodes[n].box.max)))
          << "node " << n << " does not enclose primitive " << bvh.prim_order[k];
    }
  }
  for (const scenes::RunFrame& f : run.frames) {
    VisibleSet refitted;
    CullStats stats;
    cull_bvh_masked(f.view.frustum.planes, bvh, refitted, stats);
    std::map<std::uint32_t, Visibility> got, want;
    for (std::size_t k = 0; k < refitted.indices.size(); ++k) got[refitted.indices[k]] = refitted.verdicts[k];
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (const Visibility v = pn_vertex(f.view.frustum.planes, boxes[i]); v != Visibility::outside) want[i] = v;
    EXPECT_EQ(got, want);
  }
  EXPECT_THROW(refit_bvh(bvh, std::vector<Aabb>(3)), std::invalid_argument);
}

// ---- the scene families

bool same_run(const scenes::SceneRun& a, const scenes::SceneRun& b) {
  if (a.scene.objects.size() != b.scene.objects.size() || a.frames.size() != b.frames.size()) return false;
  for (std::size_t i = 0; i < a.scene.objects.size(); ++i)
    if (a.scene.objects[i].id != b.scene.objects[i].id ||
        gen::case_scale(a.frames[0].view.frustum, a.scene.objects[i].world) !=
            gen::case_scale(b.frames[0].view.frustum, b.scene.objects[i].world))
      return false;
  for (std::size_t k = 0; k < a.frames.size(); ++k)
    if (std::memcmp(&a.frames[k].view.frustum.planes, &b.frames[k].view.frustum.planes, sizeof(Frustum)) != 0 ||
        a.frames[k].camera != b.frames[k].camera || a.frames[k].moved.size() != b.frames[k].moved.size())
      return false;
  return true;
}

TEST(SceneFamilies, RunsAreDrawnDeterministicallyWithEveryEventAndMotion) {
  std::set<std::string> events, motions, kinds;
  for (const std::string& family : scenes::parse_families("all")) {
    SCOPED_TRACE(family);
    for (std::uint64_t i = 0; i < 8; ++i) {
      const scenes::SceneRun a = scenes::draw_run(family, 9, i, {300, 12});
      EXPECT_TRUE(same_run(a, scenes::draw_run(family, 9, i, {300, 12}))) << "run " << i << " drawn twice differs";
      EXPECT_FALSE(same_run(a, scenes::draw_run(family, 10, i, {300, 12}))) << "another seed gives the same run";
      ASSERT_EQ(a.scene.objects.size(), 300u);
      ASSERT_EQ(a.frames.size(), 12u);
      std::set<std::uint32_t> ids;
      for (const SceneObject& o : a.scene.objects) {
        EXPECT_TRUE(ids.insert(o.id).second) << "id " << o.id << " twice";
        EXPECT_TRUE(is_valid(o.world));
        kinds.insert(std::string(volume_kind_name(volume_kind(o.world))));
      }
      for (const scenes::RunFrame& f : a.frames) {
        events.insert(f.camera);
        for (const SceneObject& m : f.moved) EXPECT_TRUE(ids.count(m.id)) << "moved object " << m.id << " not in the scene";
      }
      motions.insert(a.motion);
    }
  }
  for (const char* e : {"first", "still", "translate", "turn", "roll", "zoom", "cut", "projection", "eye"})
    EXPECT_TRUE(events.count(e)) << "no frame with camera event " << e;
  for (const char* k : {"point", "sphere", "aabb", "obb"}) EXPECT_TRUE(kinds.count(k)) << "no " << k;
  EXPECT_TRUE(motions.count("static"));
  std::string all;
  for (const std::string& m : motions) all += m + "; ";
  for (const char* m : {"drift", "teleport", "oscillate", "grow"}) EXPECT_NE(all.find(m), std::string::npos) << all;
  EXPECT_THROW(scenes::draw_run("no-such-family", 1, 0), std::invalid_argument);
  EXPECT_THROW(scenes::draw_run("clusters", 1, 0, {scenes::kMaxObjects + 1, 2}), std::invalid_argument);
}

// An instance's world volume is its local volume moved by its transform.
TEST(SceneFamilies, InstancesWorldIsTheTransformedLocalVolume) {
  const scenes::SceneRun run = scenes::draw_run("instances", 2, 0, {400, 1});
  std::size_t scaled = 0;
  for (const SceneObject& o : run.scene.objects) {
    const glm::mat4& m = o.transform;
    const double sx = glm::length(glm::dvec3(m[0])), sy = glm::length(glm::dvec3(m[1]));
    scaled += std::abs(sx / sy - 1.0) > 0.1;
    if (const auto* s = std::get_if<Sphere>(&o.local)) {
      const Sphere& w = std::get<Sphere>(o.world);
      EXPECT_NEAR(w.radius, s->radius * sx, 1e-5 * w.radius);
      const glm::dvec3 c = glm::dvec3(m * glm::vec4(s->center, 1.0f));
      EXPECT_NEAR(glm::length(c - glm::dvec3(w.center)), 0.0, 1e-5 * (1.0 + glm::length(c)));
    }
  }
  EXPECT_GT(scaled, 50u) << "too few non-uniformly scaled instances";
}

// ---- faults

namespace {

SystemInfo answering(const char* name, bool three_way = true) {
  SystemInfo info;
  info.name = name;
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  info.three_way = three_way;
  return info;
}

// A system that answers `set` every frame whatever the scene.
System fixed_answer(const char* name, VisibleSet set, bool three_way = true) {
  return make_system(
      answering(name, three_way), [](const Scene&) { return 0; }, [](int&, const std::vector<SceneObject>&) {},
      [set](int&, const CullView&, VisibleSet& out) { out = set; });
}

std::string fault_of(const System& s) {
  const scenes::SceneRun run = scenes::draw_run("clusters", 1, 0, {20, 3});
  try {
    scenes::judge_run(s, run);
  } catch (const scenes::SystemFault& f) {
    return f.what();
  }
  return "";
}

}  // namespace

TEST(SystemFaults, VisibleSetsThatAreNotOnesAreNamed) {
  EXPECT_NE(fault_of(fixed_answer("unknown-id", {{12345u}, {Visibility::inside}})).find("id 12345 is not in the scene"),
            std::string::npos);
  EXPECT_NE(fault_of(fixed_answer("twice", {{7u, 7u}, {Visibility::inside, Visibility::inside}})).find("id 7 again"),
            std::string::npos);
  EXPECT_NE(fault_of(fixed_answer("counts", {{7u, 10u}, {Visibility::inside}})).find("2 ids and 1 verdicts"),
            std::string::npos);
  EXPECT_NE(fault_of(fixed_answer("outside-listed", {{7u}, {Visibility::outside}})).find("listed with verdict outside"),
            std::string::npos);
  EXPECT_NE(fault_of(fixed_answer("two-way-inside", {{7u}, {Visibility::inside}}, false)).find("inside by a two-way"),
            std::string::npos);
  EXPECT_NE(fault_of(fixed_answer("no-verdicts", {{7u}, {}})).find("three-way system's visible set has no verdicts"),
            std::string::npos);
  // A two-way system may list ids alone.
  EXPECT_EQ(fault_of(fixed_answer("two-way-ids", {{7u, 10u}, {}}, false)), "");
  const System thrower = make_system(
      answering("throws-on-cull"), [](const Scene&) { return 0; }, [](int&, const std::vector<SceneObject>&) {},
      [](int&, const CullView&, VisibleSet&) { throw std::runtime_error("engine assertion"); });
  EXPECT_NE(fault_of(thrower).find("system 'throws-on-cull' threw in cull on frame 0: engine assertion"),
            std::string::npos);
}

// ---- cullproof's own systems

TEST(BuiltinSystems, HoldTheirClaimsOnEveryFamily) {
  for (const System& s : builtin_systems()) EXPECT_TRUE(cullproof::testing::system_holds(s)) << s.name;
}

// A system that returns nothing (every object outside) is refuted: the families show visible
// objects.
TEST(BuiltinSystems, AnEmptyVisibleSetIsRefuted) {
  const ::testing::AssertionResult r = cullproof::testing::system_holds(fixed_answer("nothing-visible", {}));
  EXPECT_FALSE(r);
  EXPECT_NE(std::string(r.message()).find("false rejects"), std::string::npos) << r.message();
  EXPECT_NE(std::string(r.message()).find("reproduce: CULLPROOF_SEED=1 CULLPROOF_SCENE_FAMILY="), std::string::npos)
      << r.message();
}

TEST(BuiltinSystems, RegistryNamesAndRefusesUnknown) {
  EXPECT_EQ(builtin_systems({"bvh-masked"}).front().name, "bvh-masked");
  try {
    builtin_systems({"bvh-nope"});
    FAIL() << "unknown system accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown system 'bvh-nope' (known: flat-pn-vertex, bvh-plain"), std::string::npos);
  }
}

// The culling-system interface, the scene families and a system judged on them: enclosing boxes
// hold their volumes (the oracle decides), a refitted BVH encloses its subtrees and culls as a
// rebuilt one, runs are drawn deterministically with every camera event and motion, visible sets
// that are not ones are faults, and cullproof's own systems hold their claims on every family.
#include "cullproof/core/cull.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/gtest/gtest.hpp"
#include "cullproof/oracle/oracle.hpp"
#include "cullproof/scenes/scenes.hpp"
#include "cullproof/systems/hierarchy.hpp"
#include "cullproof/systems/system.hpp"

#include "fault_of.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
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

std::string fault_of_run(const System& s) { return cullproof::test::fault_of(s, 20); }

}  // namespace

// Every volume of every distribution (the whole float range, `huge` and `subnormal` included) lies
// inside its enclosing box, decided exactly; and the box is tight: a box is its own, and the box of
// a sphere or OBB is within a few ulps of its extreme points computed in double.
TEST(EnclosingBox, HoldsEveryVolumeExactly) {
  std::size_t checked = 0, infinite = 0;
  for (const gen::Distribution d : gen::parse_distributions("all"))
    for (std::uint64_t i = 0; i < 150; ++i) {
      const Volume v = gen::draw_case(d, 3, i).volume;
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

// The truths decided down the hierarchy are the oracle's, object by object, on every family with
// its moves, in fewer oracle decisions.
TEST(SceneTruths, EqualTheOracleObjectByObject) {
  std::uint64_t calls = 0, exact = 0, object_frames = 0;
  for (const std::string& family : scenes::parse_families("all"))
    for (std::uint64_t i = 0; i < 3; ++i) {
      const scenes::SceneRun run = scenes::draw_run(family, 4, i, {400, 6});
      std::vector<Volume> world;
      std::map<std::uint32_t, std::size_t> at;
      for (const SceneObject& o : run.scene.objects) at[o.id] = world.size(), world.push_back(o.world);
      scenes::SceneTruths truths(world);
      std::vector<Visibility> got;
      for (const scenes::RunFrame& f : run.frames) {
        for (const SceneObject& m : f.moved) world[at[m.id]] = m.world, truths.move(at[m.id], m.world);
        truths.decide(f.view.frustum, got);
        ASSERT_EQ(got.size(), world.size());
        for (std::size_t k = 0; k < world.size(); ++k)
          ASSERT_EQ(got[k], oracle::truth(f.view.frustum, world[k])) << family << " run " << i << " object " << k;
        object_frames += world.size();
      }
      calls += truths.oracle_calls();
      exact += truths.exact_decisions();
    }
  EXPECT_LT(calls + exact, object_frames) << "the hierarchy decided nothing in bulk";
  EXPECT_GT(exact, 0u) << "the exact-certified cascade decided nothing";
  RecordProperty("oracle_calls", std::to_string(calls));
  RecordProperty("exact_decisions", std::to_string(exact));
  RecordProperty("object_frames", std::to_string(object_frames));
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

}  // namespace

TEST(SystemFaults, VisibleSetsThatAreNotOnesAreNamed) {
  EXPECT_NE(fault_of_run(fixed_answer("unknown-id", {{12345u}, {Visibility::inside}})).find("id 12345 is not in the scene"),
            std::string::npos);
  EXPECT_NE(fault_of_run(fixed_answer("twice", {{7u, 7u}, {Visibility::inside, Visibility::inside}})).find("id 7 again"),
            std::string::npos);
  EXPECT_NE(fault_of_run(fixed_answer("counts", {{7u, 10u}, {Visibility::inside}})).find("2 ids and 1 verdicts"),
            std::string::npos);
  EXPECT_NE(fault_of_run(fixed_answer("outside-listed", {{7u}, {Visibility::outside}})).find("listed with verdict outside"),
            std::string::npos);
  EXPECT_NE(fault_of_run(fixed_answer("two-way-inside", {{7u}, {Visibility::inside}}, false)).find("inside by a two-way"),
            std::string::npos);
  EXPECT_NE(fault_of_run(fixed_answer("no-verdicts", {{7u}, {}})).find("three-way system's visible set has no verdicts"),
            std::string::npos);
  // A two-way system may list ids alone.
  EXPECT_EQ(fault_of_run(fixed_answer("two-way-ids", {{7u, 10u}, {}}, false)), "");
  const System thrower = make_system(
      answering("throws-on-cull"), [](const Scene&) { return 0; }, [](int&, const std::vector<SceneObject>&) {},
      [](int&, const CullView&, VisibleSet&) { throw std::runtime_error("engine assertion"); });
  EXPECT_NE(fault_of_run(thrower).find("system 'throws-on-cull' threw in cull on frame 0: engine assertion"),
            std::string::npos);
}

// ---- shrinking and records

namespace {

// Shrunk runs are recorded here, not in the source tree.
cullproof::testing::SystemOptions in_temp() {
  cullproof::testing::SystemOptions o;
  o.corpus = std::filesystem::path(::testing::TempDir()) / "cullproof-systems-corpus";
  return o;
}

// A flat loop over the objects' boxes that forgets the near plane.
System without_near_plane() {
  return make_system(
      answering("flat-without-near"), [](const Scene& s) { return s; },
      [](Scene& s, const std::vector<SceneObject>& moved) {
        for (const SceneObject& m : moved)
          for (SceneObject& o : s.objects)
            if (o.id == m.id) o = m;
      },
      [](Scene& s, const CullView& v, VisibleSet& out) {
        Frustum f = v.frustum.planes;
        f[kNear] = Plane{{0, 0, 0}, 1};  // the bug: holds everywhere
        for (const SceneObject& o : s.objects)
          if (const Visibility r = pn_vertex(f, enclosing_box(o.world)); r != Visibility::outside)
            out.indices.push_back(o.id), out.verdicts.push_back(r);
      });
}

}  // namespace

TEST(SystemRecords, AFailingRunShrinksAndItsRecordReplays) {
  const System bug = without_near_plane();
  const auto tallies = cullproof::testing::verify_system(bug, in_temp());
  const cullproof::testing::FamilyTally* t = nullptr;
  for (const auto& x : tallies)
    if (x.broken && !t) t = &x;
  ASSERT_NE(t, nullptr) << "the missing near plane went unnoticed";
  scenes::ShrinkStats st;
  const scenes::SceneRun small = scenes::shrink_run(bug, *t->broken_run, *t->broken, 300, &st);
  EXPECT_LT(st.objects_after, st.objects_before);
  EXPECT_LE(st.frames_after, t->broken->frame + 1);
  EXPECT_LE(small.scene.objects.size(), 3u) << "one object behind the camera suffices";
  const scenes::RunJudgement j = scenes::judge_run(bug, small);
  ASSERT_TRUE(j.first_broken);
  RecordProperty("shrink_tries", st.tries);

  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "cullproof-system-records";
  std::filesystem::remove_all(dir);
  const std::filesystem::path file = scenes::write_system_record(dir, bug, small, *j.first_broken, "rerun");
  EXPECT_EQ(file.parent_path(), dir / "flat-without-near" / small.family);
  EXPECT_EQ(scenes::write_system_record(dir, bug, small, *j.first_broken, "rerun"), file) << "the same failure, the same file";
  const scenes::SystemRecord back = scenes::read_system_record(file);
  EXPECT_EQ(back.system, "flat-without-near");
  EXPECT_EQ(scenes::to_json(back.run), scenes::to_json(small)) << "the run reads back bit for bit";
  EXPECT_EQ(back.failure.frame, j.first_broken->frame);
  EXPECT_EQ(back.failure.id, j.first_broken->id);
  const scenes::RunJudgement again = scenes::judge_run(bug, back.run);
  EXPECT_EQ(again.claim_broken, j.claim_broken);
  // A field that is wrong is named.
  nlohmann::json rec = back.record;
  rec["run"]["objects"][0]["world"] = {{"sphere", {{"center", {0, 0}}, {"radius", 1}}}};
  std::ofstream(dir / "bad.json") << rec.dump();
  try {
    scenes::read_system_record(dir / "bad.json");
    FAIL() << "a malformed volume was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("field 'run.objects[0].world'"), std::string::npos) << e.what();
  }
}

// ---- cullproof's own systems

TEST(BuiltinSystems, HoldTheirClaimsOnEveryFamily) {
  for (const System& s : builtin_systems()) EXPECT_TRUE(cullproof::testing::system_holds(s, in_temp())) << s.name;
}

// The coherent node tests are exercised, not bypassed, by the scene runs: TR coherency decides
// frames where the camera translates or turns, and never one after a cut, a zoom or a change of
// projection; the octant test decides frames of symmetric bounded frusta and never an off-axis one.
TEST(BuiltinSystems, CoherentNodeTestsDecideOnlyWhereValid) {
  std::map<std::string, int> tr_by_event, frames_by_event;
  int octant_frames = 0;
  for (const scenes::FamilyInfo& fam : scenes::families())
    for (std::uint64_t index = 0; index < 6; ++index) {
      const scenes::SceneRun run = scenes::draw_run(fam.name, 1, index);
      std::vector<Aabb> boxes;
      for (const SceneObject& o : run.scene.objects) boxes.push_back(enclosing_box(o.world));
      Bvh bvh = build_bvh(boxes, 1);
      HierarchyCuller tr(HierarchyTest::pc_octant_tr, bvh);
      VisibleSet out;
      std::map<std::uint32_t, std::size_t> position;
      for (std::size_t k = 0; k < run.scene.objects.size(); ++k) position[run.scene.objects[k].id] = k;
      for (const scenes::RunFrame& f : run.frames) {
        for (const SceneObject& o : f.moved) boxes[position.at(o.id)] = enclosing_box(o.world);
        if (!f.moved.empty()) {
          refit_bvh(bvh, boxes);
          tr.reset();  // every cache dropped: the stricter case of moved()
        }
        tr.cull(f.view, out);
        ++frames_by_event[f.camera];
        tr_by_event[f.camera] += tr.frame().tr_used;
        octant_frames += tr.frame().octant_used;
        if (tr.frame().octant_used) {
          double d1 = 0.0;
          EXPECT_EQ(octant_decision(f.view.projection, f.view.frustum.depth, &d1), "");
        }
      }
    }
  for (const char* never : {"first", "cut", "zoom", "projection"}) EXPECT_EQ(tr_by_event[never], 0) << never;
  EXPECT_GT(tr_by_event["translate"], 0);
  EXPECT_GT(tr_by_event["turn"] + tr_by_event["roll"], 0);
  EXPECT_GT(octant_frames, 0);
}

// A system that returns nothing (every object outside) is refuted: the families show visible
// objects.
TEST(BuiltinSystems, AnEmptyVisibleSetIsRefuted) {
  const ::testing::AssertionResult r = cullproof::testing::system_holds(fixed_answer("nothing-visible", {}), in_temp());
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

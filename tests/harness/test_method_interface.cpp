// The method interface as a user meets it: make_method in its forms, what it deduces and refuses,
// a user's culler verified beside a built-in one (a correct one holds its claim, a planted bug is
// refuted and fails the run), two-way methods, stateful methods, and methods that fault.
#include <gtest/gtest.h>

#include "harness_files.hpp"
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/methods/methods.hpp"
#include "cullproof/oracle/oracle.hpp"


#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>

namespace cullproof {
namespace {

using test::files_under;
using test::temp_dir;

using V = Visibility;

// A user's n/p-vertex test written from scratch: planes in prepare, three-way classify.
struct UserPlanes {
  Frustum f;
};
Visibility user_pn(const UserPlanes& s, const Aabb& b, bool bug) {
  bool inside = true;
  for (const Plane& p : s.f.planes) {
    glm::vec3 pv, nv;
    for (int i = 0; i < 3; ++i) {
      pv[i] = p.n[i] >= 0 ? b.max[i] : b.min[i];
      nv[i] = p.n[i] >= 0 ? b.min[i] : b.max[i];
    }
    if (bug) pv.y = b.min.y;  // the p-vertex's y from the wrong corner
    if (p.eval(pv) < 0) return V::outside;
    if (p.eval(nv) < 0) inside = false;
  }
  return inside ? V::inside : V::intersecting;
}

Method user_method(bool bug) {
  MethodInfo info;
  info.name = bug ? "user-pn-bug" : "user-pn";
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  return make_method(
      info, [](const CaseFrustum& f) { return UserPlanes{f.planes}; },
      [bug](const UserPlanes& s, const Aabb& b) { return user_pn(s, b, bug); });
}

VerifyOptions small_run(std::uint64_t cases) {
  VerifyOptions o;
  o.cases = cases;
  o.seed = 5;
  o.distributions = {gen::Distribution::near_boundary, gen::Distribution::corner};
  o.threads = 2;
  o.progress = false;
  o.timing = false;
  return o;
}

TEST(MethodInterface, MakeMethodDeducesKindsAndDefaultsToAUserMethod) {
  const Method m = user_method(false);
  EXPECT_EQ(m.volumes, unsigned(kAabbKind));
  EXPECT_EQ(m.origin, Origin::user);
  EXPECT_TRUE(m.three_way);
  EXPECT_FALSE(m.has_batch());
  const CaseFrustum f = frustum_spec(frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 10)));
  // Boxes far from every plane: the user's test must give the oracle's truth.
  for (const Aabb& b : {Aabb{{-0.1f, -0.1f, -3}, {0.1f, 0.1f, -2}}, Aabb{{-0.1f, -0.1f, 1}, {0.1f, 0.1f, 2}},
                        Aabb{{-0.5f, -0.5f, -12}, {0.5f, 0.5f, -8}}})
    EXPECT_EQ(m.classify(f, b), oracle::truth(f, b)) << to_string(oracle::truth(f, b));
}

TEST(MethodInterface, RefusesADeclaredKindItsClassifyDoesNotTake) {
  MethodInfo info;
  info.name = "boxes-only";
  info.volumes = kAabbKind | kSphereKind;
  try {
    make_method(info, [](const CaseFrustum& f) { return f.planes; }, [](const Frustum&, const Aabb&) { return V::intersecting; });
    FAIL() << "accepted a sphere kind the classify does not take";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("boxes-only"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("sphere"), std::string::npos) << e.what();
  }
}

TEST(MethodInterface, OnePhaseVolumeAndBoolForms) {
  MethodInfo info;
  info.name = "one-phase-two-way";
  // One phase, taking any Volume, answering visible / not visible.
  const Method m = make_method(info, [](const CaseFrustum& f, const Volume& v) {
    return !std::holds_alternative<Point>(v) || f.planes[kNear].eval(std::get<Point>(v)) >= 0;
  });
  EXPECT_EQ(m.volumes, unsigned(kPointKind | kSphereKind | kAabbKind | kObbKind));
  EXPECT_FALSE(m.three_way) << "a bool answer is two-way";
  const CaseFrustum f = frustum_spec(frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 10)));
  EXPECT_EQ(m.classify(f, Point{0, 0, -5}), V::intersecting);
  EXPECT_EQ(m.classify(f, Point{0, 0, 5}), V::outside);
}

TEST(MethodInterface, TwoWayIsNotChargedWithUnderInsides) {
  EXPECT_EQ(error_class(V::intersecting, V::inside, /*three_way=*/false), ErrorClass::correct);
  EXPECT_EQ(error_class(V::intersecting, V::inside, /*three_way=*/true), ErrorClass::under_inside);
  EXPECT_EQ(error_class(V::outside, V::inside, false), ErrorClass::false_reject);
  EXPECT_EQ(error_class(V::intersecting, V::outside, false), ErrorClass::false_intersect);
}

TEST(MethodInterface, ABatchFormGivesTheSameAnswersAsItsClassify) {
  MethodInfo info;
  info.name = "user-batch";
  std::atomic<int> batch_calls{0};
  const Method m = make_method(
      info, [](const CaseFrustum& f) { return UserPlanes{f.planes}; },
      [](const UserPlanes& s, const Aabb& b) { return user_pn(s, b, false); },
      [&batch_calls](const UserPlanes& s, const Aabb* b, std::size_t n, Visibility* out) {
        ++batch_calls;
        for (std::size_t i = 0; i < n; ++i) out[i] = user_pn(s, b[i], false);
      });
  EXPECT_TRUE(m.has_batch());
  const gen::Frame fr = gen::draw_frame(gen::Distribution::near_boundary, 3, 0, 9000, kAabbKind);
  ASSERT_EQ(fr.volumes.size(), 9000u);
  std::vector<Aabb> boxes;
  for (const Volume& v : fr.volumes) boxes.push_back(std::get<Aabb>(v));
  const auto p = m.prepare(fr.frustum);
  std::vector<Answer> out(boxes.size());
  p->classify_batch(boxes.data(), boxes.size(), out.data());
  EXPECT_EQ(batch_calls.load(), 3) << "9,000 volumes in chunks of 4,096";
  for (std::size_t i = 0; i < boxes.size(); ++i) EXPECT_EQ(out[i], p->classify(fr.volumes[i])) << i;
}

TEST(MethodInterface, AUserCullerBesideABuiltInOne) {
  std::vector<Method> ms = {user_method(false), *find_builtin("pn-vertex")};
  const VerifyResult r = run_verify(small_run(1500), ms);
  ASSERT_EQ(r.distributions.size(), 2u);
  for (const auto& d : r.distributions) {
    ASSERT_EQ(d.methods.size(), 2u);
    const MethodStats& user = d.methods[0];
    const MethodStats& builtin = d.methods[1];
    EXPECT_EQ(user.method, "user-pn");
    EXPECT_EQ(user.origin, Origin::user);
    EXPECT_FALSE(user.refuted());
    // The same test written twice: the oracle counts the same errors.
    EXPECT_EQ(user.false_intersect, builtin.false_intersect);
    EXPECT_EQ(user.false_reject, builtin.false_reject);
  }
  EXPECT_FALSE(r.claim_broken());
}

TEST(MethodInterface, APlantedBugIsRefutedFailsTheRunAndIsWrittenToTheCorpus) {
  const auto dir = temp_dir("planted");
  VerifyOptions o = small_run(1500);
  o.corpus = dir;
  const VerifyResult r = run_verify(o, {user_method(true)});
  std::uint64_t violations = 0;
  for (const auto& d : r.distributions) violations += d.methods[0].claim_violations;
  EXPECT_GT(violations, 0u);
  EXPECT_TRUE(r.claim_broken()) << "a user's refuted claim fails the run";
  const auto entries = load_corpus(dir);
  ASSERT_FALSE(entries.empty());
  for (const CorpusEntry& e : entries) {
    EXPECT_EQ(e.method, "user-pn-bug");
    EXPECT_EQ(e.c.extra.at("origin"), "user");
    const ReplayResult rr = replay(e, {user_method(true)});
    EXPECT_TRUE(rr.reproduces) << e.file;
  }
  std::filesystem::remove_all(dir);
}

TEST(MethodInterface, AnErrorTheCorpusHoldsIsNotShrunkAgainAndThreadsWriteTheSameCorpus) {
  // The planted bug, counting the volumes the campaign asks it about.
  std::atomic<std::uint64_t> calls{0};
  MethodInfo info;
  info.name = "user-pn-bug";
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  const Method m = make_method(
      info, [](const CaseFrustum& f) { return UserPlanes{f.planes}; },
      [&calls](const UserPlanes& s, const Aabb& b) {
        calls.fetch_add(1, std::memory_order_relaxed);
        return user_pn(s, b, true);
      });
  VerifyOptions o = small_run(1500);
  o.threads = 1;
  run_verify(o, {m});
  const std::uint64_t judging = calls.exchange(0);  // without a corpus: judging only

  const auto one = temp_dir("held-1"), two = temp_dir("held-2");
  o.corpus = one;
  run_verify(o, {m});
  const std::uint64_t recording = calls.exchange(0) - judging;
  o.corpus = two;
  o.threads = 2;
  const VerifyResult first = run_verify(o, {m});
  calls.exchange(0);
  const auto written = files_under(two);
  ASSERT_FALSE(written.empty());
  EXPECT_EQ(files_under(one), written) << "one thread and two write the same records";

  // Again over the same corpus: each error's record is found by its source case and replayed
  // once; nothing is shrunk or written, and the same records are the run's evidence.
  const VerifyResult again = run_verify(o, {m});
  const std::uint64_t held = calls.exchange(0) - judging;
  std::size_t records = 0;
  for (std::size_t d = 0; d < again.distributions.size(); ++d) {
    const MethodStats& a = first.distributions[d].methods[0];
    const MethodStats& b = again.distributions[d].methods[0];
    EXPECT_TRUE(b.corpus_written.empty());
    EXPECT_EQ(b.violation_ids, a.violation_ids);
    records += a.corpus_written.size();
  }
  EXPECT_GT(records, 0u);
  EXPECT_LE(held, records) << "one replay per record held (recording the first time asked " << recording << ")";
  EXPECT_GT(recording, 20 * records) << "shrinking asks the method many times per record";
  EXPECT_EQ(files_under(two), written);

  // A record the method no longer gives (its verdict edited) is not held: that error is shrunk
  // again, to the same geometry, so the file is not written twice.
  const std::vector<CorpusEntry> entries = load_corpus(two);
  const CorpusEntry& e = entries.front();
  const gen::Distribution d = gen::parse_distributions(e.distribution).at(0);
  const std::uint64_t seed = e.c.extra.at("seed"), index = e.c.extra.at("index");
  const detail::CorpusSources sources(two, m.name, d);
  EXPECT_TRUE(sources.held(m, seed, index, e.error).has_value());
  EXPECT_FALSE(sources.held(m, seed + 1, index, e.error).has_value()) << "another seed's case";
  Case edited = e.c;
  edited.extra["verdict"] = e.verdict == V::outside ? "inside" : "outside";
  write_case_file(e.file, edited, true);
  EXPECT_FALSE(detail::CorpusSources(two, m.name, d).held(m, seed, index, e.error).has_value());
  std::filesystem::remove_all(one);
  std::filesystem::remove_all(two);
}

void expect_fault(const Method& m, const std::string& says, std::vector<gen::Distribution> families = {}) {
  const auto dir = temp_dir("fault");
  VerifyOptions o = small_run(200);
  if (!families.empty()) o.distributions = families;
  o.corpus = dir;
  const VerifyResult r = run_verify(o, {m});
  EXPECT_TRUE(r.failed());
  for (const DistributionResult& d : r.distributions) {
    ASSERT_TRUE(d.methods[0].fault) << m.name << ": no fault reported on " << gen::to_string(d.distribution);
    const MethodFault& f = *d.methods[0].fault;
    const std::string what = f.message(d.distribution, o.seed);
    EXPECT_EQ(f.method, m.name);
    EXPECT_NE(what.find(m.name), std::string::npos) << what;
    EXPECT_NE(what.find(says), std::string::npos) << what;
    EXPECT_NE(what.find("reproduce: CULLPROOF_SEED=5 CULLPROOF_DISTRIBUTION="), std::string::npos) << what;
    ASSERT_TRUE(f.saved.has_value()) << what;
    // Its counts stop before the fault's case; the saved case reproduces the fault.
    ASSERT_TRUE(f.index.has_value());
    EXPECT_LE(d.methods[0].cases, *f.index);
    const Case c = read_case_file(*f.saved);
    EXPECT_THROW(checked_classify(m, c.frustum, c.volume), std::runtime_error);
  }
  std::filesystem::remove_all(dir);
}

TEST(MethodInterface, AMethodThatThrowsIsStoppedWithTheCase) {
  MethodInfo info;
  info.name = "throws";
  expect_fault(make_method(info, [](const CaseFrustum& f) { return f.planes; },
                           [](const Frustum&, const Aabb& b) -> Visibility {
                             if (b.max.z >= b.min.z) throw std::domain_error("cannot handle this box");
                             return V::intersecting;
                           }),
               "threw: cannot handle this box");
}

TEST(MethodInterface, AnAnswerThatIsNotAVerdictIsAFault) {
  MethodInfo info;
  info.name = "answers-seven";
  expect_fault(make_method(info, [](const CaseFrustum& f) { return f.planes; },
                           [](const Frustum&, const Aabb&) { return Visibility(7); }),
               "answered 7, which is not a verdict");
}

TEST(MethodInterface, ATwoWayMethodAnsweringInsideIsAFault) {
  MethodInfo info;
  info.name = "two-way-says-inside";
  info.three_way = false;
  expect_fault(make_method(info, [](const CaseFrustum& f) { return f.planes; },
                           [](const Frustum&, const Aabb&) { return V::inside; }),
               "answered inside, but it is two-way");
}

TEST(MethodInterface, StatefulMethodsAreResetBeforeEachCaseOffCameraPaths) {
  struct Log {
    int resets = 0;
    int frames_since_reset = 0;
    int max_frames_since_reset = 0;
  };
  auto log = std::make_shared<Log>();
  MethodInfo info;
  info.name = "coherent";
  info.stateful = true;
  Method m = make_method(
      info,
      [log](const CaseFrustum& f) {
        log->max_frames_since_reset = std::max(log->max_frames_since_reset, ++log->frames_since_reset);
        return f.planes;
      },
      [](const Frustum& f, const Aabb& b) { return pn_vertex(f, b); });
  m.on_reset([log] {
    ++log->resets;
    log->frames_since_reset = 0;
  });
  VerifyOptions o = small_run(300);
  o.distributions = {gen::Distribution::corner};
  const VerifyResult r = run_verify(o, {m});
  // Off camera paths each case it takes is a path of one frame.
  EXPECT_EQ(std::uint64_t(log->resets), r.distributions[0].methods[0].cases);
  EXPECT_GT(log->resets, 50);
  EXPECT_EQ(log->max_frames_since_reset, 1);
}

TEST(MethodInterface, TwoMethodsWithOneNameAreRefused) {
  EXPECT_THROW(run_verify(small_run(10), {user_method(false), user_method(false)}), std::invalid_argument);
}

TEST(MethodInterface, TimingReportsSetUpAndPerTestCostSeparately) {
  VerifyOptions o = small_run(50);
  o.distributions = {gen::Distribution::uniform};
  o.timing = true;
  o.frame_size = 256;
  o.timing_frames = 2;
  const VerifyResult r = run_verify(o, {user_method(false), *find_builtin("pn-vertex-batch-simd")});
  for (const MethodStats& s : r.distributions[0].methods) {
    EXPECT_GT(s.ns_per_test, 0.0) << s.method;
    EXPECT_GT(s.ns_setup_per_frame, 0.0) << s.method;
  }
  EXPECT_FALSE(r.distributions[0].methods[0].timed_batch);
  EXPECT_TRUE(r.distributions[0].methods[1].timed_batch);
}

}  // namespace
}  // namespace cullproof

namespace cullproof {
namespace {

// A culler three-way on boxes (the n/p-vertex test) and two-way on spheres (the sphere test with
// `inside` reported as visible), declared so per kind, or declared three-way on both.
Method box_and_visible_sphere(unsigned two_way_kinds, bool answers_inside_for_spheres = false) {
  MethodInfo info;
  info.name = "box-and-visible-sphere";
  info.claim = Claim::conservative;
  info.tolerance = std::max(find_builtin("pn-vertex")->tolerance, find_builtin("sphere-plane")->tolerance);
  info.volumes = kAabbKind | kSphereKind;
  info.two_way_kinds = two_way_kinds;
  return make_method(info, [](const CaseFrustum& f) { return f; },
                     [answers_inside_for_spheres](const CaseFrustum& f, const Volume& v) -> Visibility {
                       if (std::holds_alternative<Aabb>(v)) return *find_builtin("pn-vertex")->classify(f, v);
                       const Visibility s = *find_builtin("sphere-plane")->classify(f, v);
                       return s == V::inside && !answers_inside_for_spheres ? V::intersecting : s;
                     });
}

TEST(MethodInterface, AMethodTwoWayOnOneKindIsChargedUnderInsidesOnTheOthersOnly) {
  VerifyOptions o = small_run(3000);
  o.distributions = {gen::Distribution::near_boundary, gen::Distribution::tiny_huge};  // truly inside spheres
  const VerifyResult r = run_verify(o, {box_and_visible_sphere(kSphereKind), *find_builtin("pn-vertex"),
                                        *find_builtin("sphere-plane")});
  const VerifyResult all_three_way = run_verify(o, {box_and_visible_sphere(0)});
  for (std::size_t k = 0; k < r.distributions.size(); ++k) {
    const auto& ms = r.distributions[k].methods;
    const MethodStats &mixed = ms[0], &box = ms[1], &sphere = ms[2];
    const std::string family(gen::to_string(r.distributions[k].distribution));
    EXPECT_FALSE(mixed.fault) << family;
    EXPECT_FALSE(mixed.refuted()) << family;
    EXPECT_EQ(mixed.two_way_kinds, unsigned(kSphereKind));
    EXPECT_EQ(mixed.cases, box.cases + sphere.cases) << family;
    // Under-insides are those of its box test, over the truly inside boxes.
    EXPECT_EQ(mixed.truth_inside, box.truth_inside + sphere.truth_inside) << family;
    EXPECT_EQ(mixed.truth_inside_three_way, box.truth_inside) << family;
    EXPECT_EQ(mixed.under_inside, box.under_inside) << family;
    EXPECT_EQ(mixed.false_intersect, box.false_intersect + sphere.false_intersect) << family;
    // Declared three-way on spheres too, every truly inside sphere is an under-inside.
    ASSERT_GT(sphere.truth_inside, 0u) << family;
    const MethodStats& charged = all_three_way.distributions[k].methods[0];
    EXPECT_EQ(charged.under_inside, box.under_inside + sphere.truth_inside) << family;
  }
  std::ostringstream table;
  print_table(r.distributions[0], o.seed, table);
  EXPECT_NE(table.str().find("| box-and-visible-sphere | user | conservative held, two-way on sphere |"), std::string::npos)
      << table.str();
  EXPECT_EQ(to_json(r)["distributions"][0]["methods"][0]["two_way_volumes"], nlohmann::json::array({"sphere"}));
}

TEST(MethodInterface, InsideForAKindItAnswersTwoWayIsAFault) {
  expect_fault(box_and_visible_sphere(kSphereKind, /*answers_inside_for_spheres=*/true),
               "answered inside for a sphere, but it is two-way on those",
               {gen::Distribution::near_boundary, gen::Distribution::tiny_huge});
}

}  // namespace
}  // namespace cullproof

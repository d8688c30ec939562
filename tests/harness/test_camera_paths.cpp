// Camera paths and stateful methods: the camera-path distribution is deterministic and moves; a
// stateful method sees each path's frames in order with the same objects in the same order (the
// contract of cullproof/methods/methods.hpp), through classify and through an array form; a coherency
// cache that trusts a stale answer is refuted with a shrunk path that replays from the corpus;
// a correct coherent culler holds; a fault on a path names the frame and saves the path.
#include <gtest/gtest.h>

#include "harness_files.hpp"
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/io/case_io.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/core/cull_coherence.hpp"
#include "cullproof/methods/methods.hpp"
#include "cullproof/oracle/oracle.hpp"
#include "mutants.hpp"


#include <filesystem>
#include <memory>
#include <set>
#include <stdexcept>

namespace cullproof {
namespace {

using test::temp_dir;

using V = Visibility;
using gen::Distribution;

VerifyOptions path_run(std::uint64_t cases) {
  VerifyOptions o;
  o.cases = cases;
  o.seed = 9;
  o.distributions = {Distribution::camera_path};
  o.threads = 2;
  o.progress = false;
  o.timing = false;
  return o;
}

TEST(CameraPaths, AreDeterministicAndTheirCasesArePathCases) {
  const gen::CameraPath a = gen::draw_path(4, 2), b = gen::draw_path(4, 2);
  ASSERT_EQ(a.frames.size(), gen::kPathFrames);
  ASSERT_EQ(a.objects.size(), gen::kPathObjects);
  ASSERT_EQ(a.scene_size.size(), gen::kPathFrames);
  EXPECT_EQ(a.motion, b.motion);
  for (std::size_t f = 0; f < gen::kPathFrames; ++f) EXPECT_EQ(format_frustum(a.frames[f]), format_frustum(b.frames[f]));
  for (std::size_t o = 0; o < gen::kPathObjects; ++o) EXPECT_EQ(format_volume(a.objects[o]), format_volume(b.objects[o]));
  for (const std::uint64_t index : {0ull, 1ull, 130ull, 2047ull, 2048ull, 5000ull}) {
    const gen::PathIndex at = gen::path_index(index);
    EXPECT_EQ(gen::path_case_index(at), index);
    const gen::CameraPath p = gen::draw_path(4, at.path);
    const gen::GenCase c = gen::draw_case(Distribution::camera_path, 4, index);
    EXPECT_EQ(format_frustum(c.frustum), format_frustum(p.frames[at.frame])) << index;
    EXPECT_EQ(format_volume(c.volume), format_volume(p.objects[at.object])) << index;
  }
}

TEST(CameraPaths, TheCameraMovesInEveryWayAndObjectsCrossTheBoundary) {
  std::set<std::string> motions;
  int crossings = 0;  // objects whose truth changes along their path
  for (std::uint64_t k = 0; k < 40; ++k) {
    const gen::CameraPath p = gen::draw_path(1, k);
    motions.insert(p.motion);
    const bool still = format_frustum(p.frames.front()) == format_frustum(p.frames.back());
    EXPECT_EQ(still, p.motion == "still") << p.motion;
    for (std::size_t o = 0; o < 8; ++o)
      crossings += oracle::truth(p.frames.front(), p.objects[o]) != oracle::truth(p.frames.back(), p.objects[o]);
  }
  EXPECT_EQ(motions, (std::set<std::string>{"still", "translation", "rotation-x", "rotation-y", "rotation-z", "general",
                                            "zoom"}));
  EXPECT_GT(crossings, 20) << "of 320 objects, too few change visibility along their path";
}

// A stateful method that checks the harness keeps its contract: after reset(), the first frame
// fixes the object sequence; every later frame must present the same objects in the same order,
// in full, before the next frame is prepared. It throws (a fault) if not.
struct Contract {
  std::vector<std::string> first;  // the objects of the path's first frame
  std::vector<std::string> now;    // this frame's so far
  int frames = 0, longest = 0, resets = 0;
  // The previous frame ends when the next is prepared (or the path is reset): it must have
  // presented the first frame's objects in full.
  void end_frame(const char* at) {
    if (frames == 1) first = now;
    else if (frames > 1 && now != first)
      throw std::logic_error(std::string(at) + ": frame " + std::to_string(frames - 1) + " presented " +
                             std::to_string(now.size()) + " objects, not the first frame's " +
                             std::to_string(first.size()) + " in order");
    now.clear();
  }
  void see(const Aabb& b) {
    now.push_back(format_volume(b));
    if (frames > 1 && (now.size() > first.size() || now.back() != first[now.size() - 1]))
      throw std::logic_error("object " + std::to_string(now.size() - 1) + " is not the one it was on the first frame");
  }
};

Method contract_method(const std::shared_ptr<Contract>& c, bool batch) {
  MethodInfo info;
  info.name = batch ? "contract-batch" : "contract";
  info.stateful = true;
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  auto prepare = [c](const CaseFrustum& f) {
    c->end_frame("prepare");
    c->longest = std::max(c->longest, ++c->frames);
    return f.planes;
  };
  auto classify = [c](const Frustum& f, const Aabb& b) {
    c->see(b);
    return pn_vertex(f, b);
  };
  Method m = batch ? make_method(info, prepare, classify,
                                 [c](const Frustum& f, const Aabb* b, std::size_t n, Visibility* out) {
                                   for (std::size_t i = 0; i < n; ++i) {
                                     c->see(b[i]);
                                     out[i] = pn_vertex(f, b[i]);
                                   }
                                 })
                   : make_method(info, prepare, classify);
  m.on_reset([c] {
    c->end_frame("reset");
    ++c->resets;
    c->first.clear();
    c->frames = 0;
  });
  return m;
}

TEST(CameraPaths, StatefulMethodsSeeEveryFrameInOrderWithTheSameObjects) {
  for (const bool batch : {false, true}) {
    auto c = std::make_shared<Contract>();
    const Method m = contract_method(c, batch);
    VerifyOptions o = path_run(3 * gen::kPathFrames * gen::kPathObjects);  // three whole paths
    const VerifyResult r = run_verify(o, {m, *find_builtin("pn-vertex")});
    const MethodStats& s = r.distributions[0].methods[0];
    const MethodStats& free = r.distributions[0].methods[1];
    EXPECT_EQ(c->longest, int(gen::kPathFrames)) << "paths are run frame after frame";
    EXPECT_GE(c->resets, 3);
    EXPECT_EQ(s.cases, free.cases) << "every box of every frame answered";
    EXPECT_EQ(s.false_intersect, free.false_intersect);
    EXPECT_EQ(s.false_reject, 0u);
  }
}

// A coherency cache that trusts a stale answer (an object culled last frame is culled again
// without a test) and its correct version: tests/mutants.
TEST(CameraPaths, AStaleCacheIsRefutedWithAShrunkPathThatReplays) {
  const auto dir = temp_dir("stale");
  VerifyOptions o = path_run(4 * gen::kPathFrames * gen::kPathObjects);
  o.corpus = dir;
  const Method bug = mutants::find("stale-plane-cache"), good = mutants::find("control-plane-cache");
  const VerifyResult r = run_verify(o, {bug, good});
  const MethodStats& b = r.distributions[0].methods[0];
  const MethodStats& g = r.distributions[0].methods[1];
  EXPECT_TRUE(b.refuted());
  EXPECT_GT(b.false_reject, 0u);
  EXPECT_FALSE(g.refuted()) << "plane coherency with per-object caches keeps the n/p-vertex test's claim";
  EXPECT_EQ(g.false_reject, 0u);
  EXPECT_TRUE(r.claim_broken());
  ASSERT_FALSE(b.corpus_written.empty());

  int with_path = 0;
  for (const CorpusEntry& e : load_corpus(dir)) {
    if (e.method == "control-plane-cache") {
      EXPECT_NE(e.error, ErrorClass::false_reject) << e.file;
    }
    if (e.method != "stale-plane-cache") continue;
    ASSERT_TRUE(e.path) << e.file << ": a stateful error is recorded with its camera path";
    if (e.error != ErrorClass::false_reject) continue;  // its false intersects are the n/p test's
    ++with_path;
    // Shrunk: the object alone, and at least the two frames the stale answer needs.
    EXPECT_EQ(e.path->objects.size(), 1u) << e.file;
    EXPECT_GE(e.path->frames.size(), 2u) << e.file;
    EXPECT_LT(e.path->frames.size(), gen::kPathFrames) << e.file << ": leading frames dropped";
    const ReplayResult rr = replay(e, {bug, good});
    EXPECT_TRUE(rr.reproduces) << e.file;
    EXPECT_FALSE(rr.truth_changed) << e.file;
    // Alone, as a path of one frame, the case does not show the error: the path is the evidence.
    EXPECT_EQ(checked_classify(bug, e.c.frustum, e.c.volume), oracle::truth(e.c.frustum, e.c.volume)) << e.file;
    // The index reproduces it from the distribution (the run replays its path from frame 0).
    VerifyOptions one = path_run(1);
    one.only_index = e.c.extra.at("index").get<std::uint64_t>();
    const VerifyResult again = run_verify(one, {bug});
    const MethodStats& a = again.distributions[0].methods[0];
    EXPECT_EQ(a.false_reject, 1u) << e.file << " index " << *one.only_index;
    EXPECT_EQ(a.claim_violations, e.c.extra.at("violates_claim").get<bool>() ? 1u : 0u) << e.file;
  }
  EXPECT_GT(with_path, 0);
  std::filesystem::remove_all(dir);
}

// A per-frame state leaking from one volume to the next (plane masks kept from the previous
// volume, a sibling, not the parent): tests/mutants. Alone, each volume is right; in a frame of
// many, boxes beyond a skipped plane are kept and called inside.
TEST(CameraPaths, AStateLeakingBetweenVolumesOfAFrameIsRefutedAndRecordedWithItsFrame) {
  const auto dir = temp_dir("leak");
  VerifyOptions o = path_run(2 * gen::kPathFrames * gen::kPathObjects);
  o.corpus = dir;
  const Method m = mutants::find("mask-leak");
  const VerifyResult r = run_verify(o, {m});
  EXPECT_TRUE(r.distributions[0].methods[0].refuted());
  int recorded = 0;
  for (const CorpusEntry& e : load_corpus(dir)) {
    if (!e.c.extra.at("violates_claim").get<bool>()) continue;
    ASSERT_TRUE(e.path) << e.file << ": the error needs the frame's earlier objects";
    EXPECT_EQ(e.path->frames.size(), 1u) << e.file;
    EXPECT_TRUE(replay(e, {m}).reproduces) << e.file;
    const Answer alone = checked_classify(m, e.c.frustum, e.c.volume);
    ASSERT_TRUE(alone);
    EXPECT_NE(error_class(*alone, oracle::truth(e.c.frustum, e.c.volume)), e.error)
        << e.file << ": alone the volume is classified without that error";
    ++recorded;
  }
  EXPECT_GT(recorded, 0);
  std::filesystem::remove_all(dir);
}

// The framed families' frames (gen::kFrameCases volumes about one camera) are classified in order
// too: the same leak is found there and recorded with its frame, which replays; a family of one
// case per frustum (touch) has no earlier volume to leak from.
TEST(CameraPaths, AStateLeakingBetweenVolumesOfAFamilysFrameIsRecordedWithItsFrame) {
  const auto dir = temp_dir("leak-framed");
  VerifyOptions o = path_run(3000);
  o.distributions = {Distribution::near_boundary, Distribution::corner};
  o.corpus = dir;
  const Method m = mutants::find("mask-leak");
  const VerifyResult r = run_verify(o, {m});
  EXPECT_TRUE(r.claim_broken());
  int framed = 0;
  for (const CorpusEntry& e : load_corpus(dir)) {
    if (!e.c.extra.at("violates_claim").get<bool>() || !e.path) continue;
    EXPECT_EQ(e.path->frames.size(), 1u) << e.file;
    EXPECT_LE(e.path->objects.size(), gen::kFrameCases) << e.file;
    EXPECT_TRUE(replay(e, {m}).reproduces) << e.file;
    ++framed;
  }
  EXPECT_GT(framed, 0);
  VerifyOptions single = path_run(3000);
  single.distributions = {Distribution::touch};
  EXPECT_FALSE(run_verify(single, {m}).claim_broken());
  std::filesystem::remove_all(dir);
}

TEST(CameraPaths, TheBuiltInCoherentCullersKeepStateAcrossFramesAndHoldTheirClaims) {
  const VerifyResult r = run_verify(path_run(4 * gen::kPathFrames * gen::kPathObjects),
                                    builtin_methods({"pn-vertex", "plane-coherency", "tr-coherency"}));
  const auto& ms = r.distributions[0].methods;
  for (const MethodStats& s : ms) {
    EXPECT_FALSE(s.refuted()) << s.method;
    EXPECT_EQ(s.false_reject, 0u) << s.method;
    EXPECT_EQ(s.cases, ms[0].cases) << s.method;
  }
  // Plane coherency only reorders the planes: the same verdicts as the frame-free test.
  EXPECT_EQ(ms[1].false_intersect, ms[0].false_intersect);
  EXPECT_EQ(ms[1].under_inside, ms[0].under_inside);
}

TEST(CameraPaths, AFaultOnAPathNamesTheFrameAndSavesThePath) {
  const auto dir = temp_dir("path-fault");
  auto frames = std::make_shared<int>(0);
  MethodInfo info;
  info.name = "fails-on-frame-3";
  info.stateful = true;
  Method m = make_method(
      info,
      [frames](const CaseFrustum& f) {
        if ((*frames)++ == 3) throw std::runtime_error("cache overflow");
        return f.planes;
      },
      [](const Frustum& f, const Aabb& b) { return pn_vertex(f, b); });
  m.on_reset([frames] { *frames = 0; });
  VerifyOptions o = path_run(gen::kPathFrames * gen::kPathObjects);
  o.faults = dir;
  const VerifyResult r = run_verify(o, {m});
  ASSERT_TRUE(r.distributions[0].methods[0].fault) << "the fault was not reported";
  const MethodFault& e = *r.distributions[0].methods[0].fault;
  const std::string what = e.message(r.distributions[0].distribution, o.seed);
  EXPECT_NE(what.find("cache overflow"), std::string::npos) << what;
  EXPECT_NE(what.find("camera path frame 3"), std::string::npos) << what;
  ASSERT_TRUE(e.saved);
  const Case c = read_case_file(*e.saved);
  const PathCase p = path_from_json(c.extra.at("path"), e.saved->string());
  EXPECT_EQ(p.frames.size(), 4u);
  EXPECT_EQ(format_frustum(p.frustum()), format_frustum(c.frustum));
  // Frame 3 of the first path: the method's counts are over its first three frames.
  ASSERT_TRUE(e.index);
  EXPECT_EQ(gen::path_index(*e.index).path, 0u);
  EXPECT_EQ(gen::path_index(*e.index).frame, 3u);
  EXPECT_LE(r.distributions[0].methods[0].cases, *e.index);
  std::filesystem::remove_all(dir);
}

TEST(CameraPaths, ARecordedPathIsReadWithItsChecks) {
  const gen::CameraPath cp = gen::draw_path(2, 0);
  PathCase p;
  p.frames = {cp.frames[0], cp.frames[1]};
  p.objects = {cp.objects[0], cp.objects[1]};
  p.object = 1;
  p.motion = cp.motion;
  const PathCase q = path_from_json(to_json(p), "x.json");
  ASSERT_EQ(q.frames.size(), 2u);
  EXPECT_EQ(format_frustum(q.frames[1]), format_frustum(p.frames[1]));
  EXPECT_EQ(format_volume(q.volume()), format_volume(p.volume()));
  nlohmann::json j = to_json(p);
  j["object"] = 2;
  EXPECT_THROW(
      {
        try {
          path_from_json(j, "x.json");
        } catch (const std::runtime_error& e) {
          EXPECT_NE(std::string(e.what()).find("x.json: field 'path.object'"), std::string::npos) << e.what();
          throw;
        }
      },
      std::runtime_error);
  j = to_json(p);
  j["objects"][0] = {{"sphere", {{"center", {0, 0, 0}}, {"radius", -1}}}};
  try {
    path_from_json(j, "x.json");
    FAIL() << "a negative radius was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("path.objects[0]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cullproof

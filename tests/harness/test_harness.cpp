// Harness units: the error-class table, the claim rules, the confidence interval, deterministic
// generation, the hard families' construction, and the campaign's corpus writing.
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/oracle/oracle.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

using namespace cullproof;
using V = Visibility;

TEST(ErrorClass, ConventionsTable) {
  EXPECT_EQ(error_class(V::outside, V::outside), ErrorClass::correct);
  EXPECT_EQ(error_class(V::outside, V::intersecting), ErrorClass::false_reject);
  EXPECT_EQ(error_class(V::outside, V::inside), ErrorClass::false_reject);
  EXPECT_EQ(error_class(V::intersecting, V::outside), ErrorClass::false_intersect);
  EXPECT_EQ(error_class(V::intersecting, V::inside), ErrorClass::under_inside);
  EXPECT_EQ(error_class(V::inside, V::outside), ErrorClass::false_inside);
  EXPECT_EQ(error_class(V::inside, V::intersecting), ErrorClass::false_inside);
}

TEST(Claims, RulesPerClaim) {
  // distance 1e-3 with tolerance 1e-5 at scale 10: beyond tolerance (1e-4); 1e-5: within.
  EXPECT_TRUE(violates_claim(Claim::certified_conservative, ErrorClass::false_reject, 0.0, 0.0, 1.0, false));
  EXPECT_FALSE(violates_claim(Claim::certified_conservative, ErrorClass::false_intersect, 5.0, 0.0, 1.0, false));
  EXPECT_TRUE(violates_claim(Claim::conservative, ErrorClass::false_inside, 1e-3, 1e-5, 10.0, false));
  EXPECT_FALSE(violates_claim(Claim::conservative, ErrorClass::false_inside, 1e-5, 1e-5, 10.0, false));
  EXPECT_FALSE(violates_claim(Claim::conservative, ErrorClass::false_intersect, 7.0, 1e-5, 10.0, false));
  EXPECT_TRUE(violates_claim(Claim::exact, ErrorClass::false_intersect, 7.0, 1e-5, 10.0, false));
  EXPECT_FALSE(violates_claim(Claim::exact, ErrorClass::under_inside, 1e-6, 1e-5, 10.0, false));
  EXPECT_TRUE(violates_claim(Claim::certified_exact, ErrorClass::false_inside, 0.0, 1.0, 1.0, false));
  EXPECT_FALSE(violates_claim(Claim::none, ErrorClass::false_reject, 100.0, 0.0, 1.0, false));
  // A zero tolerance forgives nothing, not even an error at distance 0 (a volume touching the
  // boundary): a certified-exact method with a zero band may make no error at all.
  EXPECT_TRUE(violates_claim(Claim::certified_exact, ErrorClass::under_inside, 0.0, 0.0, 1.0, false));
  EXPECT_TRUE(violates_claim(Claim::certified_exact, ErrorClass::false_intersect, 0.0, 0.0, 1.0, false));
  EXPECT_TRUE(violates_claim(Claim::exact, ErrorClass::under_inside, 0.0, 0.0, 1.0, false));
  EXPECT_FALSE(violates_claim(Claim::conservative, ErrorClass::under_inside, 0.0, 0.0, 1.0, false));
  // Float-exact cases: no rounding allowance for conservative and exact claims, at any distance;
  // a certified band is not a rounding allowance and stays.
  EXPECT_TRUE(violates_claim(Claim::conservative, ErrorClass::false_reject, 0.0, 1e-5, 10.0, true));
  EXPECT_TRUE(violates_claim(Claim::conservative, ErrorClass::false_inside, 1e-5, 1e-5, 10.0, true));
  EXPECT_FALSE(violates_claim(Claim::conservative, ErrorClass::false_intersect, 0.0, 1e-5, 10.0, true));
  EXPECT_TRUE(violates_claim(Claim::exact, ErrorClass::under_inside, 0.0, 1e-5, 10.0, true));
  EXPECT_FALSE(violates_claim(Claim::certified_exact, ErrorClass::false_intersect, 0.5, 1.0, 1.0, true));
  EXPECT_FALSE(violates_claim(Claim::none, ErrorClass::false_reject, 0.0, 0.0, 1.0, true));
}

TEST(Claims, TheDistanceIsMeasuredOnlyWhereItDecides) {
  // needs_distance is false exactly where violates_claim does not depend on the distance.
  for (Claim c : {Claim::certified_conservative, Claim::certified_exact, Claim::conservative, Claim::exact, Claim::none})
    for (ErrorClass e : {ErrorClass::correct, ErrorClass::false_reject, ErrorClass::false_inside,
                         ErrorClass::false_intersect, ErrorClass::under_inside})
      for (bool exact : {false, true}) {
        const bool near = violates_claim(c, e, 0.0, 1e-5, 1.0, exact);
        const bool far = violates_claim(c, e, 1.0, 1e-5, 1.0, exact);
        EXPECT_EQ(needs_distance(c, e, exact), near != far) << to_string(c) << " " << to_string(e) << " " << exact;
      }
}

// The judge forgives what rounding explains, measured toward the verdict given: a box 2^-21 from
// the frustum (a boundary distance well inside a 1e-5 allowance) called inside is 0.375 from being
// inside, and no rounding explains that; nor does it explain `outside` for a box resting 2^-21
// inside a plane and reaching 0.5 in, or `inside` for one that penetrates by 2^-21 and protrudes by
// 0.375. On the cube [-1, 1]^3; the extents of 0.1 make the plane sums round (1 + 0.1 is no
// float), so the cases are not float-exact and the allowance applies.
TEST(Claims, ErrorsTwoClassesAwayAreNotForgivenByNearnessToTheBoundary) {
  Frustum f;
  for (int a = 0; a < 3; ++a) {  // x >= -1, x <= 1, y >= -1, y <= 1, z >= -1, z <= 1
    glm::vec3 n(0.0f);
    n[a] = 1.0f;
    f[2 * a] = Plane{n, 1};
    f[2 * a + 1] = Plane{-n, 1};
  }
  const CaseFrustum cube = frustum_spec(f);
  const float just = 0x1p-21f;
  struct Pair {
    Volume box;
    Visibility verdict, truth;
    double boundary, to_verdict;
  };
  const Pair pairs[] = {
      {Aabb{{1 + just, -0.1f, -0.1f}, {1.375f, 0.1f, 0.1f}}, V::inside, V::outside, just, 0.375},
      {Aabb{{0.5f, -0.1f, -0.1f}, {1 - just, 0.1f, 0.1f}}, V::outside, V::inside, just, 0.5},
      {Aabb{{1 - just, -0.1f, -0.1f}, {1.375f, 0.1f, 0.1f}}, V::inside, V::intersecting, just, 0.375},
  };
  for (const Pair& p : pairs) {
    const oracle::Result r = oracle::classify(cube, p.box);
    ASSERT_EQ(r.truth, p.truth);
    EXPECT_NEAR(r.distance, p.boundary, 1e-12);
    const double d = error_distance(cube, p.box, p.verdict);
    EXPECT_NEAR(d, p.to_verdict, 1e-7);
    const ErrorClass e = error_class(p.verdict, p.truth);
    const double scale = gen::case_scale(cube, p.box);
    ASSERT_FALSE(gen::float_exact(cube, p.box));
    EXPECT_FALSE(violates_claim(Claim::conservative, e, r.distance, 1e-5, scale, false))
        << "measured to the boundary, the error would be forgiven";
    EXPECT_TRUE(violates_claim(Claim::conservative, e, d, 1e-5, scale, false)) << "measured to the verdict, it is not";
  }
}

TEST(Wilson, KnownIntervals) {
  auto [lo, hi] = wilson95(0, 10);
  EXPECT_EQ(lo, 0.0);
  EXPECT_NEAR(hi, 0.2775, 1e-4);
  std::tie(lo, hi) = wilson95(50, 100);
  EXPECT_NEAR(lo, 0.4038, 1e-4);
  EXPECT_NEAR(hi, 0.5962, 1e-4);
  EXPECT_EQ(wilson95(0, 0), std::make_pair(0.0, 0.0));
  // No success in many trials: the lower bound is exactly 0, with no rounding residue (at these
  // counts centre - half comes out near 1e-19 or below).
  for (std::uint64_t n : {1000ull, 22787ull, 218799ull, 4282471ull, 123456789ull}) {
    EXPECT_EQ(wilson95(0, n).first, 0.0) << n;
    EXPECT_EQ(wilson95(n, n).second, 1.0) << n;
  }
}

TEST(Generators, SameSeedSameCasesOtherSeedOtherCases) {
  for (gen::Distribution d : gen::parse_distributions("all")) {
    for (std::uint64_t i = 0; i < 20; ++i) {
      Case a, b, c;
      a.frustum = gen::draw_case(d, 7, i).frustum;
      a.volume = gen::draw_case(d, 7, i).volume;
      b.frustum = gen::draw_case(d, 7, i).frustum;
      b.volume = gen::draw_case(d, 7, i).volume;
      c.frustum = gen::draw_case(d, 8, i).frustum;
      c.volume = gen::draw_case(d, 8, i).volume;
      EXPECT_EQ(format_case(a), format_case(b)) << gen::to_string(d) << " " << i;
      EXPECT_NE(format_case(a), format_case(c)) << gen::to_string(d) << " " << i;
    }
  }
}

// The Shrinkable the campaign shrinks from is rooted at the case it judged, bit for bit, and its
// shrinks are valid cases of the same family.
TEST(Generators, TheShrinkableOfACaseIsRootedAtTheCaseDrawn) {
  for (gen::Distribution d : gen::parse_distributions("all")) {
    for (std::uint64_t i : {0ull, 1ull, 517ull, 9000ull}) {
      Case fast, root;
      const gen::GenCase g = gen::draw_case(d, 3, i);
      fast.frustum = g.frustum;
      fast.volume = g.volume;
      const rc::Shrinkable<gen::GenCase> s = gen::draw(d, 3, i);
      root.frustum = s.value().frustum;
      root.volume = s.value().volume;
      EXPECT_EQ(format_case(fast), format_case(root)) << gen::to_string(d) << " " << i;
      EXPECT_EQ(g.scene_size, s.value().scene_size) << gen::to_string(d) << " " << i;
      int shrinks = 0;
      for (auto seq = s.shrinks(); auto next = seq.next();) {
        EXPECT_NO_THROW(validate(next->value().volume)) << gen::to_string(d) << " " << i;
        if (++shrinks == 5) break;
      }
      EXPECT_GT(shrinks, 0) << gen::to_string(d) << " " << i;
    }
  }
}

// A case depends on its index alone: drawn on several threads in any order, the same cases.
TEST(Generators, CasesDrawnOnThreadsInAnyOrderAreTheSame) {
  constexpr std::uint64_t kCases = 600;
  for (gen::Distribution d : {gen::Distribution::uniform, gen::Distribution::touch, gen::Distribution::huge}) {
    std::vector<std::string> serial(kCases), threaded(kCases);
    auto text = [d](std::uint64_t i) {
      const gen::GenCase g = gen::draw_case(d, 11, i);
      Case c;
      c.frustum = g.frustum;
      c.volume = g.volume;
      return format_case(c);
    };
    for (std::uint64_t i = 0; i < kCases; ++i) serial[i] = text(i);
    std::vector<std::thread> threads;
    for (std::uint64_t t = 0; t < 3; ++t)
      threads.emplace_back([&, t] {
        for (std::uint64_t k = 0; k < kCases; ++k) {
          const std::uint64_t i = kCases - 1 - k;  // backwards, interleaved
          if (i % 3 == t) threaded[i] = text(i);
        }
      });
    for (auto& th : threads) th.join();
    EXPECT_EQ(serial, threaded) << gen::to_string(d);
  }
}

TEST(Generators, EveryDistributionGivesValidCases) {
  for (gen::Distribution d : gen::parse_distributions("all"))
    for (std::uint64_t i = 0; i < 300; ++i) {
      const gen::GenCase g = gen::draw_case(d, 1, i);
      EXPECT_NO_THROW(validate(g.volume)) << gen::to_string(d) << " " << i;
      EXPECT_NO_THROW(validate(g.frustum.planes)) << gen::to_string(d) << " " << i;
      EXPECT_GT(g.scene_size, 0.0);
    }
}

// The touch family is built to touch: never strictly separated from the frustum.
TEST(Generators, TouchCasesAreNeverOutside) {
  int intersecting = 0, inside = 0;
  for (std::uint64_t i = 0; i < 400; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::touch, 3, i);
    const V t = oracle::truth(g.frustum, g.volume);
    EXPECT_NE(t, V::outside) << "touch case " << i;
    intersecting += t == V::intersecting;
    inside += t == V::inside;
  }
  EXPECT_GT(intersecting, 100);
  EXPECT_GT(inside, 50);
}

// Rods cross the frustum with no corner inside it.
TEST(Generators, RodsHaveNoCornerInside) {
  int crossing = 0;
  for (std::uint64_t i = 0; i < 300; ++i) {
    const gen::GenCase g = gen::draw_case(gen::Distribution::rod, 5, i);
    const Obb b = std::holds_alternative<Obb>(g.volume) ? std::get<Obb>(g.volume) : to_obb(std::get<Aabb>(g.volume));
    int corners_inside = 0;
    for (int k = 0; k < 8; ++k) {
      glm::vec3 p = b.center;
      for (int a = 0; a < 3; ++a) p += ((k >> a) & 1 ? 1.0f : -1.0f) * b.half[a] * b.axes[a];
      bool in = true;
      for (const Plane& pl : g.frustum.planes.planes) in = in && pl.eval(p) >= 0.0f;
      corners_inside += in;
    }
    EXPECT_EQ(corners_inside, 0) << "rod " << i;
    crossing += oracle::truth(g.frustum, g.volume) == V::intersecting;
  }
  EXPECT_GT(crossing, 150);
}

TEST(Campaign, SameSeedSameVerdictsAndCorpusDeduplicates) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-campaign-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o;
  o.cases = 400;
  o.seed = 11;
  o.distributions = {gen::Distribution::rod, gen::Distribution::corner};
  o.methods = {"hoff96", "pn-vertex-reverse"};
  o.threads = 2;
  o.corpus = dir;
  o.progress = false;
  o.timing = false;
  const VerifyResult a = run_verify(o);
  auto counts = [](const VerifyResult& r) {
    nlohmann::json j = to_json(r);
    for (auto& d : j["distributions"])
      for (auto& m : d["methods"]) {
        m.erase("ns_per_test");
        m.erase("ns_setup_per_frame");
        m.erase("corpus_written");
      }
    j.erase("wall_seconds");
    return j;
  };
  // hoff96 falsely rejects rods: the campaign finds it and writes the evidence.
  EXPECT_GT(a.distributions[0].methods[0].false_reject, 0u);
  EXPECT_TRUE(a.distributions[0].methods[0].refuted());
  EXPECT_FALSE(a.claim_broken());
  const auto entries = load_corpus(dir);
  EXPECT_FALSE(entries.empty());
  for (const CorpusEntry& e : entries) {
    const ReplayResult r = replay(e);
    EXPECT_TRUE(r.reproduces) << e.file;
    EXPECT_FALSE(r.truth_changed) << e.file;
  }
  const VerifyResult b = run_verify(o);
  EXPECT_EQ(counts(a), counts(b));
  std::size_t written_again = 0;
  for (const auto& d : b.distributions)
    for (const auto& m : d.methods) written_again += m.corpus_written.size();
  EXPECT_EQ(written_again, 0u);  // the same minimal cases exist already
  EXPECT_EQ(load_corpus(dir).size(), entries.size());

  // rerecord_verdicts after a (pretended) change to pn-vertex-reverse: a record whose
  // "verdicts" lists another answer for it is rewritten with the answer now, and only that entry.
  const CorpusEntry* other = nullptr;
  for (const CorpusEntry& e : entries)
    if (e.method == "hoff96" && e.c.extra.at("verdicts").contains("pn-vertex-reverse")) other = &e;
  ASSERT_NE(other, nullptr);
  Case edited = other->c;
  const std::string now = edited.extra["verdicts"]["pn-vertex-reverse"].get<std::string>();
  const std::string wrong = now == "outside" ? "inside" : "outside";
  edited.extra["verdicts"]["pn-vertex-reverse"] = wrong;
  write_case_file(other->file, edited, true);
  const std::vector<Rerecorded> changed = rerecord_verdicts(dir, *find_builtin("pn-vertex-reverse"));
  ASSERT_EQ(changed.size(), 1u);
  EXPECT_EQ(changed[0].file, other->file);
  EXPECT_EQ(changed[0].before, wrong);
  EXPECT_EQ(changed[0].after, now);
  EXPECT_EQ(format_case(read_case_file(other->file), true), format_case(other->c, true)) << "only that entry changes";
  EXPECT_TRUE(rerecord_verdicts(dir, *find_builtin("pn-vertex-reverse")).empty());
  std::filesystem::remove_all(dir);
}

TEST(Corpus, AFilePastTheCaseLimitsIsRefusedNamingIt) {
  // Corpus files are case files: the same limits (case_io.hpp), the file named.
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-corpus-limits-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "pn-vertex" / "uniform");
  const auto file = dir / "pn-vertex" / "uniform" / "false-reject-000000000000.json";
  std::ofstream(file) << std::string(100000, '[');
  auto refusal = [&] {
    try {
      load_corpus(dir);
    } catch (const CaseError& e) {
      EXPECT_EQ(e.file(), file.string());
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal(), file.string() + ":1: arrays and objects nested deeper than 64, the limit for one case");
  std::filesystem::resize_file(file, kMaxCaseBytes + 1);
  EXPECT_EQ(refusal(), file.string() + ": a file of 1048577 bytes, over the limit of 1048576 bytes (1 MiB) for a one-case file");
  std::filesystem::remove_all(dir);
}

TEST(Corpus, FaultRecordsAndTemporaryFilesAreNotCases) {
  // A run that faulted saves its case under faults/ (no truth, no verdict); a writer killed
  // mid-write leaves its hidden temporary file. The corpus reader reads neither as a case.
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-corpus-litter-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const auto real = std::filesystem::path(CULLPROOF_CORPUS_DIR) / "hoff96";
  std::filesystem::path one;
  for (const auto& e : std::filesystem::recursive_directory_iterator(real))
    if (e.path().extension() == ".json") one = e.path();
  ASSERT_FALSE(one.empty());
  const auto kept = dir / "hoff96" / "rod" / one.filename();
  std::filesystem::create_directories(kept.parent_path());
  std::filesystem::copy_file(one, kept);
  std::filesystem::create_directories(dir / "faults" / "my-culler");
  std::ofstream(dir / "faults" / "my-culler" / "0123456789ab.json") << R"({"id": "f", "fault": "threw"})";
  std::ofstream(kept.parent_path() / ("." + one.filename().string() + ".tmp-123-456")) << "{\"id\": \"half";
  const std::vector<CorpusEntry> entries = load_corpus(dir);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].file, kept);
  // The record reader on text reads the same record.
  std::ifstream in(kept);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(format_case(parse_corpus_entry(text, kept).c, true), format_case(entries[0].c, true));
  EXPECT_THROW(parse_corpus_entry(R"({"id": "x", "frustum": {"planes": [[1,0,0,0],[1,0,0,0],[1,0,0,0],[1,0,0,0],[1,0,0,0],[1,0,0,0]]},
                                     "volume": {"point": [0,0,0]}, "truth": "inside"})", "x.json"),
               std::runtime_error);
  std::filesystem::remove_all(dir);
}

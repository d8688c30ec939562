// Culling systems behind the process protocol, version 2: the reference adapter (written from
// docs/protocol.md alone) verified like an in-process system; its planted bug refuted; a crash, a
// hang, a wrong-sized answer and an unknown id stop it with the frame named; version-2 handshakes
// read, version 1 still accepted.
#include "cullproof/gtest/gtest.hpp"
#include "cullproof/protocol/external.hpp"
#include "cullproof/protocol/protocol.hpp"
#include "cullproof/scenes/scenes.hpp"

#include "fault_of.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

using namespace cullproof;

namespace {

System reference(const std::string& fault = "", int timeout_ms = 10000) {
  ExternalOptions o;
  o.command = {CULLPROOF_REFERENCE_SYSTEM_ADAPTER};
  if (!fault.empty()) o.command.push_back(fault);
  o.timeout = std::chrono::milliseconds(timeout_ms);
  const std::vector<System> s = external_systems(o);
  if (s.size() != 1) throw std::runtime_error("the reference adapter offers one system");
  return s.front();
}

cullproof::testing::SystemOptions small() {
  cullproof::testing::SystemOptions o;
  o.runs = 2;
  o.size = {60, 8};
  o.corpus = std::filesystem::path(::testing::TempDir()) / "cullproof-system-protocol";
  return o;
}

std::string fault_of_run(const System& s) { return cullproof::test::fault_of(s, 30); }

}  // namespace

TEST(SystemProtocol, ReferenceAdapterHoldsItsClaimOnEveryFamily) {
  const System s = reference();
  EXPECT_EQ(s.name, "reference-flat");
  EXPECT_EQ(s.claim, Claim::conservative);
  EXPECT_EQ(s.program, CULLPROOF_REFERENCE_SYSTEM_ADAPTER);
  EXPECT_TRUE(cullproof::testing::system_holds(s, small()));
}

TEST(SystemProtocol, AProgramsOwnCullTimeIsTalliedApartFromCullproofsClock) {
  scenes::VerifyRuns runs;
  runs.runs = 1;
  runs.size = {40, 5};
  runs.families = {"clusters", "instances"};
  // The reference adapter reports "ns" for every cull: every frame counts, with its object-frames.
  for (const scenes::FamilyTally& t : scenes::verify_system(reference(), runs)) {
    EXPECT_EQ(t.own_culls, 5u) << t.family;
    EXPECT_EQ(t.own_object_frames, t.judged) << t.family;
    EXPECT_GT(t.own_cull_ns, 0.0) << t.family;
    EXPECT_LT(t.own_cull_ns * 1e-9, t.cull_seconds) << t.family << ": its own time is part of what cullproof's clock saw";
  }
  // A system that reports none (cullproof's own) has none tallied.
  for (const scenes::FamilyTally& t : scenes::verify_system(builtin_systems({"bvh-masked"}).front(), runs)) {
    EXPECT_EQ(t.own_culls, 0u) << t.family;
    EXPECT_EQ(t.own_cull_ns, 0.0) << t.family;
  }
}

TEST(SystemProtocol, ItsPlantedBugIsRefutedAndShrunk) {
  const ::testing::AssertionResult r = cullproof::testing::system_holds(reference("drop-near"), small());
  ASSERT_FALSE(r);
  EXPECT_NE(std::string(r.message()).find("reference-flat (user system) breaks its claim 'conservative'"), std::string::npos)
      << r.message();
  EXPECT_NE(std::string(r.message()).find("  record: "), std::string::npos) << r.message();
}

TEST(SystemProtocol, FaultsStopTheSystemNamingTheMessage) {
  EXPECT_NE(fault_of_run(reference("crash-on-scene")).find("before answering scene message 1 (30 object(s) for system 'reference-flat')"),
            std::string::npos)
      << fault_of_run(reference("crash-on-scene"));
  const std::string hang = fault_of_run(reference("hang-on-cull", 300));
  EXPECT_NE(hang.find("no answer within 300 ms to cull message 2"), std::string::npos) << hang;
  const std::string count = fault_of_run(reference("wrong-count"));
  EXPECT_NE(count.find("verdict(s) for"), std::string::npos) << count;
  EXPECT_NE(count.find("visible id(s)"), std::string::npos) << count;
  const std::string unknown = fault_of_run(reference("unknown-id"));
  EXPECT_NE(unknown.find("id 4000000000 is not in the scene"), std::string::npos) << unknown;
}

TEST(SystemProtocol, HandshakesOfBothVersionsAreRead) {
  // Version 1: methods only, no systems.
  const std::string v1 = R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb"]}]})";
  EXPECT_EQ(protocol::parse_handshake(v1, "prog").size(), 1u);
  EXPECT_TRUE(protocol::parse_offered_systems(v1, "prog").empty());
  // Version 2: systems alone are enough.
  const std::string v2 = R"({"protocol": 2, "systems": [{"name": "s", "claim": "conservative", "volumes": ["aabb", "sphere"], "three_way": false}]})";
  EXPECT_TRUE(protocol::parse_handshake(v2, "prog").empty());
  const std::vector<SystemInfo> s = protocol::parse_offered_systems(v2, "prog");
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].volumes, unsigned(kAabbKind | kSphereKind));
  EXPECT_FALSE(s[0].three_way);
  auto refused = [](const std::string& line) {
    try {
      protocol::parse_offered_systems(line, "prog");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(refused(R"({"protocol": 2, "systems": [{"name": "s", "volumes": ["aabb"], "claimm": "exact"}]})")
                .find("systems[0]: unknown field \"claimm\""),
            std::string::npos);
  EXPECT_NE(refused(R"({"protocol": 2})").find("neither \"methods\" nor \"systems\" offered"), std::string::npos);
  EXPECT_NE(refused(R"({"protocol": 1, "systems": [{"name": "s", "volumes": ["aabb"]}]})").find("no \"methods\" array"),
            std::string::npos);
}

TEST(SystemProtocol, VisibleSetAnswersAreChecked) {
  auto refused = [](const std::string& line, bool three_way = true) {
    try {
      protocol::parse_visible(line, 5, 3, three_way, "cull message 5");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(refused(R"({"frame": 5, "visible": [1, 2], "verdicts": ["inside", "intersecting"], "ns": 10})"), "");
  EXPECT_EQ(refused(R"({"frame": 5, "visible": [1, 2]})", false), "");
  EXPECT_NE(refused(R"({"frame": 5, "visible": [1, 2]})").find("without \"verdicts\""), std::string::npos);
  EXPECT_NE(refused(R"({"frame": 5, "visible": [1, 2, 3, 4], "verdicts": []})").find("4 visible id(s) for a scene of 3"),
            std::string::npos);
  EXPECT_NE(refused(R"({"frame": 5, "visible": [-1], "verdicts": ["inside"]})").find("visible[0] = -1, which is not an id"),
            std::string::npos);
  EXPECT_NE(refused(R"({"frame": 5, "visible": [1], "verdicts": ["outside"]})").find("verdicts[0] = \"outside\""),
            std::string::npos);
  EXPECT_NE(refused(R"({"frame": 5, "visible": [1], "verdicts": ["inside"]})", false).find("two-way"), std::string::npos);
  EXPECT_NE(refused(R"({"frame": 4, "visible": []})").find("answered frame 4 when cull message 5 was asked"),
            std::string::npos);
  EXPECT_NE(refused(R"({"frame": 5, "error": "out of memory"})").find("reported an error for cull message 5: out of memory"),
            std::string::npos);
}

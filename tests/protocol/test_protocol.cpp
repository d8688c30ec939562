// The process protocol: the reference adapter (tests/protocol/reference_adapter.cpp, written from
// docs/protocol.md) is a method like any other, with the same verdicts as the built-in n/p-vertex
// test; adapters that crash, hang, miscount, print garbage, answer an unknown verdict or out of
// order are each stopped with the documented error and the case saved.
#include "cullproof/campaign/campaign.hpp"
#include "cullproof/core/cull.hpp"
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/protocol/external.hpp"
#include "cullproof/protocol/protocol.hpp"
#include "cullproof/io/case_io.hpp"

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <regex>
#include <tuple>

namespace cullproof {
namespace {

ExternalOptions adapter(const std::vector<std::string>& modes) {
  ExternalOptions o;
  o.command = {CULLPROOF_REFERENCE_ADAPTER};
  o.command.insert(o.command.end(), modes.begin(), modes.end());
  o.timeout = std::chrono::milliseconds(1500);
  return o;
}

VerifyOptions small_run() {
  VerifyOptions o;
  o.cases = 1500;
  o.seed = 3;
  o.distributions = {gen::Distribution::near_boundary, gen::Distribution::corner, gen::Distribution::contact};
  o.threads = 2;
  o.progress = false;
  o.timing = false;
  return o;
}

// The cases on which the adapter's `reference-fragile` aborts (reference_adapter.cpp, `several`):
// boxes whose min.x has float bits divisible by 61.
bool fragile_on(const Volume& v) {
  const Aabb* b = std::get_if<Aabb>(&v);
  if (!b) return false;
  std::uint32_t bits = 0;
  std::memcpy(&bits, &b->min.x, sizeof bits);
  return bits % 61 == 0;
}

struct FragileCase {
  std::uint64_t index = 0;       // the first case it faults on
  std::uint64_t boxes_before = 0;  // the boxes before it (the cases its counts are over)
};

FragileCase first_fragile(gen::Distribution d, std::uint64_t seed, std::uint64_t cases) {
  FragileCase f;
  for (std::uint64_t i = 0; i < cases; ++i) {
    const Volume v = gen::draw_case(d, seed, i).volume;
    if (fragile_on(v)) {
      f.index = i;
      return f;
    }
    f.boxes_before += std::holds_alternative<Aabb>(v);
  }
  ADD_FAILURE() << "no fragile case in " << cases << " cases of " << gen::to_string(d);
  return f;
}

// One of a program's three methods aborts the program on known cases; two threads ask two copies
// of it. The fault names that method and its first such case in each distribution, whatever the
// threads did; the other two methods finish with the counts they have alone.
TEST(Protocol, AFaultStopsOnlyItsMethodAndNamesItsFirstCaseWithThreadsAndCopies) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-protocol-several-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::uniform, gen::Distribution::corner};
  o.faults = dir;
  ExternalOptions a = adapter({"several"});
  a.instances = 2;
  const std::vector<Method> ms = external_methods(a);
  ASSERT_EQ(ms.size(), 3u);
  EXPECT_EQ(ms[1].name, "reference-fragile");
  const VerifyResult r = run_verify(o, ms);
  const VerifyResult alone = run_verify(o, {ms[0], ms[2]});
  EXPECT_EQ(r.faults(), 2u);
  EXPECT_TRUE(r.failed());
  for (std::size_t k = 0; k < r.distributions.size(); ++k) {
    const DistributionResult& d = r.distributions[k];
    const std::string family(gen::to_string(d.distribution));
    const FragileCase expected = first_fragile(d.distribution, o.seed, o.cases);
    const MethodStats& fragile = d.methods[1];
    ASSERT_TRUE(fragile.fault) << family;
    EXPECT_EQ(fragile.fault->method, "reference-fragile");
    EXPECT_EQ(fragile.fault->index, expected.index) << family;
    EXPECT_EQ(fragile.cases, expected.boxes_before) << family;
    EXPECT_NE(fragile.fault->problem.find("exited (signal 6) before answering"), std::string::npos) << fragile.fault->problem;
    EXPECT_NE(fragile.fault->problem.find("for method 'reference-fragile'"), std::string::npos) << fragile.fault->problem;
    EXPECT_EQ(fragile.fault->reproduce,
              fmt::format("cullproof verify --seed 3 --distribution {} --index {} --external reference-fragile -- {} several",
                          family, expected.index, CULLPROOF_REFERENCE_ADAPTER));
    ASSERT_TRUE(fragile.fault->saved) << family;
    const Case saved = read_case_file(*fragile.fault->saved);
    EXPECT_TRUE(fragile_on(saved.volume)) << "the case saved is the one it faulted on";
    for (std::size_t j : {0, 2}) {
      const MethodStats& m = d.methods[j];
      const MethodStats& same = alone.distributions[k].methods[j == 0 ? 0 : 1];
      EXPECT_FALSE(m.fault) << m.method << " on " << family << ": " << m.fault->problem;
      EXPECT_EQ(m.cases, same.cases) << m.method << " on " << family;
      EXPECT_EQ(m.false_intersect, same.false_intersect) << m.method << " on " << family;
      EXPECT_EQ(m.under_inside, same.under_inside) << m.method << " on " << family;
      EXPECT_FALSE(m.refuted()) << m.method;
    }
  }
  std::filesystem::remove_all(dir);
}

// The same in process: a method that throws on those cases beside two built-in ones, two threads.
TEST(Protocol, AnInProcessFaultStopsOnlyItsMethodAtItsFirstCase) {
  MethodInfo info;
  info.name = "fragile-in-process";
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  const Method fragile = make_method(info, [](const CaseFrustum& f) { return f.planes; },
                                     [](const Frustum& f, const Aabb& b) {
                                       if (fragile_on(b)) throw std::runtime_error("fragile: this box");
                                       return pn_vertex(f, b);
                                     });
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::uniform};
  o.cases = 4000;
  const VerifyResult r = run_verify(o, {*find_builtin("pn-vertex"), fragile, *find_builtin("sphere-certified")});
  const FragileCase expected = first_fragile(gen::Distribution::uniform, o.seed, o.cases);
  const auto& ms = r.distributions[0].methods;
  ASSERT_TRUE(ms[1].fault);
  EXPECT_EQ(ms[1].fault->index, expected.index);
  EXPECT_EQ(ms[1].cases, expected.boxes_before);
  EXPECT_NE(ms[1].fault->problem.find("fragile: this box"), std::string::npos) << ms[1].fault->problem;
  EXPECT_FALSE(ms[0].fault);
  EXPECT_FALSE(ms[2].fault);
  EXPECT_GT(ms[0].cases, expected.boxes_before);
  EXPECT_GT(ms[2].cases, 0u);
  EXPECT_FALSE(r.interrupted);
}

// The handshake has a time limit of its own, apart from the answers'.
TEST(Protocol, TheHandshakeHasItsOwnTimeLimit) {
  ExternalOptions o = adapter({"slow-start"});
  o.handshake_timeout = std::chrono::milliseconds(500);
  try {
    external_methods(o);
    ADD_FAILURE() << "a handshake 2 s late was accepted within 500 ms";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no answer within 500 ms to the handshake (hung? the limit is "
                                         "--external-handshake-timeout)"),
              std::string::npos)
        << e.what();
  }
  o.handshake_timeout = std::chrono::milliseconds(20000);  // the answers keep their 1,500 ms
  EXPECT_EQ(external_methods(o).size(), 1u);
}

// The program's command line as the reproduce lines print it reads back to the same words in a
// shell: a word with a space or a quote is quoted.
TEST(Protocol, TheProgramIsNamedAsAShellReadsIt) {
  const std::vector<Method> ms = external_methods(adapter({"ok", "two words", "it's"}));
  EXPECT_EQ(ms.at(0).program, std::string(CULLPROOF_REFERENCE_ADAPTER) + R"( ok 'two words' 'it'\''s')");
}

TEST(Protocol, TheReferenceAdapterIsAMethodLikeAnyOther) {
  const std::vector<Method> ext = external_methods(adapter({"ok"}));
  ASSERT_EQ(ext.size(), 1u);
  EXPECT_EQ(ext[0].name, "reference-pn-vertex");
  EXPECT_EQ(ext[0].origin, Origin::user);
  EXPECT_EQ(ext[0].volumes, unsigned(kAabbKind));
  const VerifyResult r = run_verify(small_run(), {ext[0], *find_builtin("pn-vertex")});
  for (const auto& d : r.distributions) {
    const MethodStats& a = d.methods[0];
    const MethodStats& b = d.methods[1];
    EXPECT_GT(a.cases, 0u);
    EXPECT_EQ(a.cases, b.cases);
    EXPECT_EQ(a.false_intersect, b.false_intersect) << gen::to_string(d.distribution);
    EXPECT_EQ(a.under_inside, b.under_inside) << gen::to_string(d.distribution);
    EXPECT_FALSE(a.refuted()) << gen::to_string(d.distribution);
  }
}

TEST(Protocol, APlantedBugIsFoundThroughTheProtocolAsInProcess) {
  // The touching `<=` of tests/mutants, behind the protocol: refuted on float-exact contact cases,
  // its shrunk case written under its name.
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-protocol-bug-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::contact};
  o.corpus = dir;
  const VerifyResult r = run_verify(o, external_methods(adapter({"reject-touching"})));
  const MethodStats& s = r.distributions[0].methods[0];
  EXPECT_TRUE(s.refuted());
  EXPECT_GT(s.false_reject, 0u);
  EXPECT_EQ(s.float_exact_violations, s.claim_violations);
  EXPECT_TRUE(r.claim_broken());
  EXPECT_FALSE(s.corpus_written.empty());
  EXPECT_TRUE(std::filesystem::exists(dir / "reference-pn-vertex" / "contact"));
  std::filesystem::remove_all(dir);
}

// The fault's message, which must match `pattern` (an ECMAScript regular expression: a frame's
// volume count depends on the frame's kinds, and on which frame of the campaign's threads is asked
// third).
std::string expect_fault(const std::vector<std::string>& modes, const std::string& pattern) {
  const std::string mode = modes.back();
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-protocol-" + mode + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o = small_run();
  // Binary messages carry a chunk of about 1,024 cases: enough cases that the first family asks
  // the third message.
  if (modes.front() == "binary") o.cases = 6000;
  o.faults = dir;
  const VerifyResult r = run_verify(o, external_methods(adapter(modes)));
  EXPECT_TRUE(r.distributions[0].methods[0].fault) << mode << ": not stopped";
  if (!r.distributions[0].methods[0].fault) return {};
  const MethodFault& f = *r.distributions[0].methods[0].fault;
  const std::string what = f.message(r.distributions[0].distribution, o.seed);
  EXPECT_NE(what.find("external program '"), std::string::npos) << what;
  EXPECT_TRUE(std::regex_search(what, std::regex(pattern))) << mode << ": " << what << "\n(expected: " << pattern << ")";
  EXPECT_TRUE(f.saved && std::filesystem::exists(*f.saved)) << mode << ": the case was not saved";
  EXPECT_TRUE(r.failed());
  std::filesystem::remove_all(dir);
  return what;
}
std::string expect_fault(const std::string& mode, const std::string& pattern) {
  return expect_fault(std::vector<std::string>{mode}, pattern);
}

TEST(Protocol, ACrashIsStopped) { expect_fault("crash", R"(exited \(signal 6\) before answering frame 3)"); }
TEST(Protocol, AHangIsStoppedAtTheTimeout) { expect_fault("hang", "no answer within 1500 ms to frame 3"); }
TEST(Protocol, TheWrongCountIsStopped) {
  // One verdict more than the volumes asked about.
  const std::string what = expect_fault("wrong-count", R"(with \d+ verdict\(s\) for \d+ volume\(s\))");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(what, m, std::regex(R"(with (\d+) verdict\(s\) for (\d+) volume\(s\))"))) << what;
  EXPECT_EQ(std::stoi(m[1]), std::stoi(m[2]) + 1) << what;
}
TEST(Protocol, GarbageIsStopped) { expect_fault("garbage", R"(a line that is not JSON: segfault\? no, just text)"); }
TEST(Protocol, AnUnknownVerdictIsStopped) { expect_fault("bad-verdict", R"(verdict "visible" for volume 0)"); }
TEST(Protocol, AnswersOutOfOrderAreStopped) { expect_fault("out-of-order", "answered frame 4 when frame 3"); }

TEST(Protocol, ABadTimeIsStopped) { expect_fault("bad-ns", R"(with "ns" "fast", which is not a number)"); }

// Lines past the limits (external.hpp) are faults as soon as they pass them; an answer's limit
// grows with the volumes asked about.
TEST(Protocol, AnOverLongAnswerIsStoppedAtTheLimit) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string what = expect_fault(
      "long-answer", R"(its answer to frame 3 \((\d+) volume\(s\) for method 'reference-pn-vertex'\) is a line longer than )"
                     R"((\d+) bytes, the limit for an answer about \1 volume\(s\) \(64 KiB and 64 bytes a volume\))");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 10.0);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(what, m, std::regex(R"(\((\d+) volume\(s\) for method 'reference-pn-vertex'\) is a line longer than (\d+) bytes)"))) << what;
  EXPECT_EQ(std::stoll(m[2]), 65536 + 64 * std::stoll(m[1])) << what;
}
TEST(Protocol, ADeeplyNestedAnswerIsStopped) {
  expect_fault("deep-answer", R"(answered frame 3 \(\d+ volume\(s\) for method 'reference-pn-vertex'\) with arrays and objects )"
                              R"(nested deeper than 64, the limit for a protocol message)");
}

// The handshake of the program `o` runs is refused with an error naming the program, then `words`.
void expect_refused_handshake(const ExternalOptions& o, const std::string& words) {
  std::string program;
  for (const std::string& a : o.command) program += (program.empty() ? "" : " ") + a;
  try {
    external_methods(o);
    FAIL() << program << ": accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("external program '" + program + "': " + words), std::string::npos) << e.what();
  }
}
void expect_refused_handshake(const std::string& mode, const std::string& words) {
  expect_refused_handshake(adapter({mode}), words);
}
TEST(Protocol, AnOverLongHandshakeIsRefused) {
  expect_refused_handshake("long-handshake",
                           "its handshake is a line longer than 1048576 bytes (1 MiB), the limit for a handshake");
}
TEST(Protocol, ADeeplyNestedHandshakeIsRefused) {
  expect_refused_handshake("deep-handshake",
                           "its handshake has arrays and objects nested deeper than 64, the limit for a protocol message");
}

TEST(Protocol, AProgramsOwnTimeIsShownBesideTheMeasuredCost) {
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::corner};
  o.cases = 200;
  o.timing = true;
  const VerifyResult r = run_verify(o, external_methods(adapter({"ok"})));
  const MethodStats& s = r.distributions[0].methods[0];
  ASSERT_TRUE(std::isfinite(s.ns_per_test) && std::isfinite(s.ns_per_test_own));
  EXPECT_GT(s.ns_per_test_own, 0.0);
  EXPECT_LT(s.ns_per_test_own, s.ns_per_test);  // its classification alone, without the messages
  // A method that reports nothing has no own figure.
  const VerifyResult b = run_verify(o, {*find_builtin("pn-vertex")});
  EXPECT_TRUE(std::isnan(b.distributions[0].methods[0].ns_per_test_own));
}

TEST(Protocol, APublishedMethodsRefutedClaimIsAFindingNotAFailure) {
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::contact};
  const std::vector<Method> user = external_methods(adapter({"reject-touching"}));
  const std::vector<Method> published = external_methods(adapter({"reject-touching", "published"}));
  EXPECT_EQ(user[0].origin, Origin::user);
  EXPECT_EQ(published[0].origin, Origin::published);
  EXPECT_TRUE(run_verify(o, user).claim_broken());
  const VerifyResult r = run_verify(o, published);
  EXPECT_TRUE(r.distributions[0].methods[0].refuted());
  EXPECT_FALSE(r.claim_broken());
}

TEST(Protocol, AMatrixMethodIsAskedAboutMatrixFrustaOnly) {
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::uniform};
  o.cases = 600;
  // The adapter answers an error for a frustum without a matrix: none may reach it.
  const VerifyResult r = run_verify(o, external_methods(adapter({"matrix"})));
  const MethodStats& s = r.distributions[0].methods[0];
  EXPECT_GT(s.cases, 0u);
  EXPECT_FALSE(s.refuted());
  const VerifyResult all = run_verify(o, external_methods(adapter({"ok"})));
  EXPECT_LT(s.cases, all.distributions[0].methods[0].cases);
}

TEST(Protocol, AHandshakeFieldOutOfItsListIsRefused) {
  expect_refused_handshake("bad-origin", "handshake, methods[0]: \"origin\" \"own\" is not \"user\" or \"published\"");
}

TEST(Protocol, CopiesOfTheProgramGiveTheSameResultsAsOne) {
  ExternalOptions two = adapter({"ok"});
  two.instances = 2;
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::corner, gen::Distribution::camera_path};
  const VerifyResult a = run_verify(o, external_methods(adapter({"ok"})));
  const VerifyResult b = run_verify(o, external_methods(two));
  for (std::size_t d = 0; d < a.distributions.size(); ++d) {
    const MethodStats& x = a.distributions[d].methods[0];
    const MethodStats& y = b.distributions[d].methods[0];
    EXPECT_EQ(x.cases, y.cases);
    EXPECT_EQ(x.false_intersect, y.false_intersect);
    EXPECT_EQ(x.under_inside, y.under_inside);
  }
}

TEST(Protocol, CopiesThatOfferDifferentMethodsAreRefused) {
  ExternalOptions o = adapter({"unstable"});
  o.instances = 2;
  expect_refused_handshake(o, "copy 2 of the program offered another handshake than the first");
}

TEST(Protocol, AnotherVersionIsRefusedAtTheHandshake) {
  expect_refused_handshake("bad-version", "handshake: protocol version 99, this cullproof speaks versions 1 to 3");
}

TEST(Protocol, AProgramThatCannotRunIsReported) {
  ExternalOptions o;
  o.command = {"/nonexistent/culler"};
  o.timeout = std::chrono::milliseconds(1500);
  EXPECT_THROW(external_methods(o), std::runtime_error);
}

// The reference adapter's own arithmetic, in process, on the planes cullproof extracts: the same
// verdicts as the adapter's on every frustum exactly when every number reaches the program as
// the float it is (numbers near FLT_MAX, subnormal ones, and the planes of a matrix whose row
// sums overflow float, which cullproof sends as extracted from halved rows).
Method adapter_arithmetic() {
  MethodInfo info;
  info.name = "reference-arithmetic";
  info.claim = Claim::none;
  return make_method(info, [](const CaseFrustum& f) { return f.planes; },
                     [](const Frustum& f, const Aabb& b) {
                       bool inside = true;
                       for (const Plane& p : f.planes) {
                         float pv = p.d, nv = p.d;
                         for (int i = 0; i < 3; ++i) {
                           pv += p.n[i] * (p.n[i] >= 0 ? b.max[i] : b.min[i]);
                           nv += p.n[i] * (p.n[i] >= 0 ? b.min[i] : b.max[i]);
                         }
                         if (pv < 0) return Visibility::outside;
                         if (nv < 0) inside = false;
                       }
                       return inside ? Visibility::inside : Visibility::intersecting;
                     });
}

TEST(Protocol, FrustaAtTheEndsOfTheFloatRangeArriveAsTheyAre) {
  VerifyOptions o = small_run();
  o.cases = 1000;
  o.distributions = {gen::Distribution::huge, gen::Distribution::subnormal};
  const std::vector<Method> ext = external_methods(adapter({"ok"}));
  ASSERT_EQ(ext.size(), 1u);
  // No fault: every frame was well-formed JSON with finite numbers, and answered.
  const VerifyResult r = run_verify(o, {ext[0], adapter_arithmetic()});
  for (const auto& d : r.distributions) {
    const MethodStats& a = d.methods[0];
    const MethodStats& b = d.methods[1];
    EXPECT_GT(a.cases, 200u) << gen::to_string(d.distribution);
    EXPECT_EQ(a.cases, b.cases) << gen::to_string(d.distribution);
    EXPECT_EQ(a.truth_outside, b.truth_outside) << gen::to_string(d.distribution);
    EXPECT_EQ(a.false_reject, b.false_reject) << gen::to_string(d.distribution);
    EXPECT_EQ(a.false_inside, b.false_inside) << gen::to_string(d.distribution);
    EXPECT_EQ(a.false_intersect, b.false_intersect) << gen::to_string(d.distribution);
    EXPECT_EQ(a.under_inside, b.under_inside) << gen::to_string(d.distribution);
  }
}

// The readers of a program's lines, on text (cullproof/protocol/protocol.hpp): every field of a handshake
// is checked for its type, so a handshake of the wrong shape is refused naming the field, never
// with the JSON library's type error.
std::string handshake_error(const std::string& line) {
  try {
    protocol::parse_handshake(line, "prog");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "accepted";
}

TEST(ProtocolReader, AHandshakeOfTheWrongShapeIsRefusedNamingTheField) {
  const std::string ok = R"({"name": "m", "volumes": ["aabb"])";
  auto with = [&](const std::string& more) { return R"({"protocol": 1, "methods": [)" + ok + more + "}]}"; };
  EXPECT_EQ(handshake_error(with("")), "accepted");
  EXPECT_EQ(handshake_error(with(R"(, "description": 5)")),
            "external program 'prog': handshake, methods[0]: \"description\" 5 is not a string");
  EXPECT_EQ(handshake_error(with(R"(, "three_way": "yes")")),
            "external program 'prog': handshake, methods[0]: \"three_way\" \"yes\" is not true or false");
  EXPECT_EQ(handshake_error(with(R"(, "tolerance": -1e-6)")),
            "external program 'prog': handshake, methods[0]: \"tolerance\" -1e-06 is not a number >= 0");
  EXPECT_EQ(handshake_error(with(R"(, "claim": "sound\u0000")")),
            "external program 'prog': handshake, methods[0]: \"claim\" \"sound\\u0000\" is not a claim "
            "(certified-conservative, certified-exact, conservative, exact, none)");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [)" + ok + "}, " + ok + "}]}"),
            "external program 'prog': handshake, methods[1]: \"name\" \"m\" is offered twice");
  // 2^32 + 1 is not version 1, however an int would hold it.
  EXPECT_EQ(handshake_error(R"({"protocol": 4294967297, "methods": [)" + ok + "}]}"),
            "external program 'prog': handshake: protocol version 4294967297, this cullproof speaks versions 1 to 3");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": [1e999]}]})"),
            "external program 'prog': its handshake has a number beyond the range of a double (number overflow parsing "
            "'1e999'): {\"protocol\": 1, \"methods\": [{\"name\": \"m\", \"volumes\": [1e999]}]}");
}

// A misspelt field would leave its default in force (a misspelt "claim" makes the claim `none`,
// which nothing can refute): every field outside the list is refused, named.
TEST(ProtocolReader, AnUnknownHandshakeFieldIsRefusedNamingIt) {
  const std::string ok = R"({"name": "m", "volumes": ["aabb"])";
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb"], "claimm": "exact"}]})"),
            "external program 'prog': handshake, methods[0]: unknown field \"claimm\" (a method's fields: name, description, "
            "source, claim, tolerance, volumes, three_way, touching, origin, stateful, frustum, depth)");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [)" + ok + R"(}], "engine": "x"})"),
            "external program 'prog': handshake: unknown field \"engine\" (a version-1 handshake's fields: protocol, methods)");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [)" + ok + R"(}], "systems": []})"),
            "external program 'prog': handshake: unknown field \"systems\" (a version-1 handshake's fields: protocol, methods)");
}

// A matrix culler that reads some depth conventions only declares them; the others' cases do not
// apply to it.
TEST(ProtocolReader, AMatrixCullerDeclaresTheDepthConventionsItReads) {
  auto offered = [](const std::string& more) {
    return protocol::parse_handshake(R"({"protocol": 2, "methods": [{"name": "m", "volumes": ["aabb"], "frustum": "matrix")" +
                                         more + "}]}",
                                     "prog")
        .at(0);
  };
  EXPECT_EQ(offered("").depths, 0xFu);
  const unsigned gl = protocol::depth_convention_bit({DepthRange::negative_one_to_one, false});
  const unsigned reversed_d3d = protocol::depth_convention_bit({DepthRange::zero_to_one, true});
  EXPECT_EQ(offered(R"(, "depth": ["negative_one_to_one", "reversed_zero_to_one"])").depths, gl | reversed_d3d);
  EXPECT_NE(gl, reversed_d3d);
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb"], "depth": ["zero_to_one"]}]})"),
            "external program 'prog': handshake, methods[0]: \"depth\" is declared by a method with \"frustum\": \"matrix\" only");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb"], "frustum": "matrix", "depth": ["gl"]}]})"),
            "external program 'prog': handshake, methods[0]: \"depth\" \"gl\" is not a depth convention (negative_one_to_one, "
            "zero_to_one, reversed_negative_one_to_one, reversed_zero_to_one)");
  EXPECT_EQ(handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb"], "frustum": "matrix", "depth": []}]})"),
            "external program 'prog': handshake, methods[0]: \"depth\" must be a non-empty array of depth conventions "
            "(negative_one_to_one, zero_to_one, reversed_negative_one_to_one, reversed_zero_to_one)");
}

// A culler whose box test is three-way and whose sphere test is visible / not visible is one method.
TEST(ProtocolReader, ThreeWayIsDeclaredPerKind) {
  auto offered = [](const std::string& three_way) {
    return protocol::parse_handshake(
               R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb", "sphere"], "three_way": )" + three_way + "}]}",
               "prog")
        .at(0)
        .info;
  };
  const MethodInfo mixed = offered(R"({"sphere": false, "aabb": true})");
  EXPECT_TRUE(mixed.three_way);
  EXPECT_EQ(mixed.two_way_kinds, unsigned(kSphereKind));
  EXPECT_TRUE(mixed.three_way_on(kAabbKind));
  EXPECT_FALSE(mixed.three_way_on(kSphereKind));
  EXPECT_TRUE(offered(R"({"sphere": true})").three_way_on(kSphereKind));  // a kind not named is three-way
  const MethodInfo two_way = offered(R"({"sphere": false, "aabb": false})");  // two-way on all it takes
  EXPECT_FALSE(two_way.three_way);
  EXPECT_EQ(two_way.two_way_kinds, 0u);
  auto error = [](const std::string& three_way) {
    return handshake_error(R"({"protocol": 1, "methods": [{"name": "m", "volumes": ["aabb", "sphere"], "three_way": )" +
                           three_way + "}]}");
  };
  EXPECT_EQ(error(R"({"obb": false})"),
            "external program 'prog': handshake, methods[0]: \"three_way\" names \"obb\", which is not among its \"volumes\"");
  EXPECT_EQ(error(R"({"sphere": "no"})"),
            "external program 'prog': handshake, methods[0]: \"three_way\" \"sphere\" \"no\" is not true or false");
  EXPECT_EQ(error(R"({"ball": false})"),
            "external program 'prog': handshake, methods[0]: \"three_way\": unknown volume kind \"ball\" (point, sphere, aabb, obb)");
  EXPECT_EQ(error("[]"), "external program 'prog': handshake, methods[0]: \"three_way\" [] is not true or false");
}

// ---- the binary encoding (version 3)

// The same cases through JSON Lines, through binary messages (a chunk's frames in one message)
// with one copy and two, and in process: the same counts on every kind of family (framed, one
// case a frame, camera paths).
TEST(Protocol, TheBinaryEncodingGivesTheSameCountsAsJsonAndAsInProcess) {
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::uniform, gen::Distribution::corner, gen::Distribution::contact,
                     gen::Distribution::camera_path};
  const std::vector<Method> binary = external_methods(adapter({"binary"}));
  ASSERT_EQ(binary.size(), 1u);
  EXPECT_TRUE(binary[0].has_frames()) << "asked a chunk's frames at once";
  ExternalOptions two = adapter({"binary"});
  two.instances = 2;
  const VerifyResult r = run_verify(o, {binary[0], *find_builtin("pn-vertex")});
  const VerifyResult j = run_verify(o, external_methods(adapter({"ok"})));
  const VerifyResult c = run_verify(o, external_methods(two));
  for (std::size_t d = 0; d < r.distributions.size(); ++d) {
    const std::string family(gen::to_string(r.distributions[d].distribution));
    const MethodStats& b = r.distributions[d].methods[0];
    for (const MethodStats* x : {&r.distributions[d].methods[1], &j.distributions[d].methods[0], &c.distributions[d].methods[0]}) {
      EXPECT_GT(x->cases, 0u) << family;
      EXPECT_EQ(b.cases, x->cases) << family;
      EXPECT_EQ(b.truth_outside, x->truth_outside) << family;
      EXPECT_EQ(b.false_intersect, x->false_intersect) << family;
      EXPECT_EQ(b.under_inside, x->under_inside) << family;
      EXPECT_EQ(b.false_reject, x->false_reject) << family;
    }
    EXPECT_FALSE(b.fault) << family;
  }
}

TEST(Protocol, APlantedBugIsFoundThroughBinaryMessages) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-protocol-binary-bug-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  VerifyOptions o = small_run();
  o.distributions = {gen::Distribution::contact};
  o.corpus = dir;
  const VerifyResult r = run_verify(o, external_methods(adapter({"binary", "reject-touching"})));
  const MethodStats& s = r.distributions[0].methods[0];
  EXPECT_TRUE(s.refuted());
  EXPECT_GT(s.false_reject, 0u);
  EXPECT_FALSE(s.corpus_written.empty());
  for (const CorpusEntry& e : load_corpus(dir))
    EXPECT_TRUE(replay(e, external_methods(adapter({"binary", "reject-touching"}))).reproduces) << e.file;
  std::filesystem::remove_all(dir);
}

// A binary fault: the message names the frame (the first of a message of several, or the one the
// fault is in) and, asked frame by frame again, the case it strikes on is saved.
TEST(Protocol, BinaryFaultsAreStoppedNamingTheFrame) {
  const std::string frames = R"(frames? \d+( to \d+)? \(\d+ volume\(s\) for method 'reference-pn-vertex'\))";
  expect_fault(std::vector<std::string>{"binary", "crash"}, R"(exited \(signal 6\) before answering )" + frames);
  expect_fault(std::vector<std::string>{"binary", "hang"}, "no answer within 1500 ms to " + frames);
  expect_fault(std::vector<std::string>{"binary", "truncated"}, R"(exited \(status 0\) before answering )" + frames);
  expect_fault(std::vector<std::string>{"binary", "garbage"}, "answered " + frames + R"( with a binary answer that does not begin with "CP3A": segf)");
  expect_fault(std::vector<std::string>{"binary", "wrong-count"}, R"(answered (frame \d+ of )?)" + frames + R"( with (\d+) verdict\(s\) for \d+ volume\(s\))");
  expect_fault(std::vector<std::string>{"binary", "bad-verdict"}, R"(answered (frame \d+ of )?)" + frames + R"( with verdict byte 7 for volume 0, which is not 0)");
  expect_fault(std::vector<std::string>{"binary", "out-of-order"}, R"(answered frame (\d+) when frame \d+ of )" + frames);
  expect_fault(std::vector<std::string>{"binary", "bad-ns"}, R"(with ns nan, which is not a number of nanoseconds)");
  expect_fault(std::vector<std::string>{"binary", "error"}, "reported an error for " + frames + ": cannot cull this frame");
  expect_fault(std::vector<std::string>{"binary", "long-answer"},
               "(wrote \\d+ byte\\(s\\) or more past its binary answer to |does not begin with \"CP3A\": xxx)");
}

TEST(ProtocolReader, AVersion3HandshakeChoosesItsEncoding) {
  const auto offered = protocol::parse_handshake(
      R"({"protocol": 3, "encoding": "binary", "methods": [{"name": "a", "volumes": ["aabb"]}, {"name": "b", "volumes": ["sphere"]}]})",
      "prog");
  ASSERT_EQ(offered.size(), 2u);
  EXPECT_TRUE(offered[0].binary && offered[1].binary);
  EXPECT_EQ(offered[1].index, 1u);
  EXPECT_FALSE(protocol::parse_handshake(R"({"protocol": 3, "methods": [{"name": "a", "volumes": ["aabb"]}]})", "prog")[0].binary);
  auto refused = [](const std::string& line) {
    try {
      protocol::parse_handshake(line, "prog");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refused(R"({"protocol": 3, "encoding": "xml", "methods": [{"name": "a", "volumes": ["aabb"]}]})"),
            "external program 'prog': handshake: \"encoding\" \"xml\" is not \"json\" or \"binary\"");
  EXPECT_EQ(refused(R"({"protocol": 2, "encoding": "binary", "methods": [{"name": "a", "volumes": ["aabb"]}]})"),
            "external program 'prog': handshake: unknown field \"encoding\" (a version-2 handshake's fields: protocol, methods, "
            "systems)");
}

// A binary answer built by hand: "CP3A", the frame count, then per frame its number, its verdict
// count, its ns (a double) and a byte per verdict.
std::string binary_answer(std::uint32_t frames, const std::vector<std::tuple<std::uint64_t, std::uint32_t, double, std::string>>& f) {
  std::string s = "CP3A";
  s.append(reinterpret_cast<const char*>(&frames), 4);
  for (const auto& [id, n, ns, verdicts] : f) {
    s.append(reinterpret_cast<const char*>(&id), 8);
    s.append(reinterpret_cast<const char*>(&n), 4);
    s.append(reinterpret_cast<const char*>(&ns), 8);
    s += verdicts;
  }
  return s;
}

TEST(ProtocolReader, ABinaryAnswerIsReadOrRefusedNamingTheFrame) {
  const std::vector<protocol::AskedFrame> asked{{7, 2}, {8, 1}};
  EXPECT_EQ(protocol::binary_answer_size(asked), 8u + 20 + 2 + 20 + 1);
  const auto r = protocol::parse_binary_answer(
      binary_answer(2, {{7, 2, 12.5, std::string("\x02\xff", 2)}, {8, 1, -1.0, std::string(1, '\0')}}), asked, "frames 7 to 8");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].verdicts, (std::vector<Answer>{Visibility::inside, std::nullopt}));
  EXPECT_EQ(r[0].ns, 12.5);
  EXPECT_EQ(r[1].verdicts, (std::vector<Answer>{Visibility::outside}));
  EXPECT_FALSE(r[1].ns) << "-1: not given";
  auto refused = [&](const std::string& bytes) {
    try {
      protocol::parse_binary_answer(bytes, asked, "frames 7 to 8");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string ok1 = std::string("\x01\x01", 2), ok2 = std::string(1, '\x01');
  EXPECT_EQ(refused(binary_answer(2, {{7, 2, 0, ok1}, {8, 1, 0, ok2}}).substr(0, 30)),
            "answered frames 7 to 8 with 30 byte(s) where the binary answer has 51");
  EXPECT_EQ(refused("CP3B" + binary_answer(2, {{7, 2, 0, ok1}, {8, 1, 0, ok2}}).substr(4)),
            "answered frames 7 to 8 with a binary answer that does not begin with \"CP3A\": CP3B");
  EXPECT_EQ(refused(binary_answer(1, {{7, 2, 0, ok1}, {8, 1, 0, ok2}})), "answered frames 7 to 8 with 1 frame(s) where 2 were asked");
  EXPECT_EQ(refused(binary_answer(2, {{7, 2, 0, ok1}, {9, 1, 0, ok2}})),
            "answered frame 9 when frame 8 of frames 7 to 8 was asked (answers come in order)");
  EXPECT_EQ(refused(binary_answer(2, {{7, 1, 0, ok1}, {8, 2, 0, ok2}})),
            "answered frame 7 of frames 7 to 8 with 1 verdict(s) for 2 volume(s)");
  EXPECT_EQ(refused(binary_answer(2, {{7, 2, 0, std::string("\x01\x03", 2)}, {8, 1, 0, ok2}})),
            "answered frame 7 of frames 7 to 8 with verdict byte 3 for volume 1, which is not 0 (outside), 1 (intersecting), "
            "2 (inside) or 255 (does not apply)");
  EXPECT_EQ(refused(binary_answer(2, {{7, 2, -2.0, ok1}, {8, 1, 0, ok2}})),
            "answered frame 7 of frames 7 to 8 with ns -2, which is not a number of nanoseconds (or -1)");
  try {
    protocol::refuse_json_instead_of_binary(R"({"frame": 7, "error": "out of memory"})", 7, "frames 7 to 8");
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "reported an error for frames 7 to 8: out of memory");
  }
  try {
    protocol::refuse_json_instead_of_binary(R"({"frame": 7, "verdicts": ["inside"]})", 7, "frames 7 to 8");
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "answered frames 7 to 8 with a JSON line where a binary answer (\"CP3A\") was due: "
                                     "{\"frame\": 7, \"verdicts\": [\"inside\"]}");
  }
}

// A frame entry as docs/protocol.md lays it out, byte by byte.
TEST(ProtocolReader, ABinaryFrameIsLaidOutAsDocumented) {
  const CaseFrustum f = frustum_spec(frustum_from_matrix(off_axis_projection(-1, 1, -1, 1, 1, 10)));
  const CaseFrustum m = frustum_spec(off_axis_projection(-1, 1, -1, 1, 1, 10), DepthConvention{DepthRange::zero_to_one, true});
  const std::vector<Volume> boxes{Aabb{{1, 2, 3}, {4, 5, 6}}, Aabb{{-1, -1, -9}, {1, 1, -8}}};
  std::string entries(protocol::kBinaryFramesHeader, '\0');
  protocol::append_binary_frame(entries, 5, 2, true, f, boxes.data(), boxes.size());
  protocol::append_binary_frame(entries, 6, 2, false, m, boxes.data(), 1);
  protocol::put_binary_header(entries, 2);
  auto u32 = [&](std::size_t at) {
    std::uint32_t x;
    std::memcpy(&x, entries.data() + at, 4);
    return x;
  };
  auto f32 = [&](std::size_t at) {
    float x;
    std::memcpy(&x, entries.data() + at, 4);
    return x;
  };
  const std::size_t first = 20 + 96 + 2 * 24, second = 20 + 96 + 64 + 24;
  ASSERT_EQ(entries.size(), 12 + first + second);
  EXPECT_EQ(entries.substr(0, 4), "CP3F");
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), first + second);
  std::uint64_t id;
  std::memcpy(&id, entries.data() + 12, 8);
  EXPECT_EQ(id, 5u);
  EXPECT_EQ(u32(20), 2u) << "the method's index";
  EXPECT_EQ(u32(24), 2u) << "the volume count";
  EXPECT_EQ(entries[28], 2) << "kind: aabb";
  EXPECT_EQ(entries[29], 1) << "flags: reset, no matrix";
  EXPECT_EQ(f32(32), f.planes[0].n.x);
  EXPECT_EQ(f32(32 + 23 * 4), f.planes[5].d);
  EXPECT_EQ(f32(12 + 20 + 96), 1.0f) << "the first box's min.x";
  EXPECT_EQ(f32(12 + first - 4), -8.0f) << "the second box's max.z";
  const std::size_t b = 12 + first;
  EXPECT_EQ(entries[b + 17], 2) << "flags: a matrix, no reset";
  EXPECT_EQ(entries[b + 18], 1) << "depth: zero to one";
  EXPECT_EQ(entries[b + 19], 1) << "reversed-Z";
  EXPECT_EQ(f32(b + 20 + 96), (*m.matrix)[0][0]) << "the matrix, column-major";
  EXPECT_EQ(f32(b + 20 + 96 + 4 * 14), (*m.matrix)[3][2]);
}

TEST(ProtocolReader, AnAnswerIsReadOrRefusedNamingTheFrame) {
  const protocol::Reply r = protocol::parse_answer(R"({"frame": 4, "verdicts": ["inside", null], "ns": 12.5})", 4, 2, "frame 4");
  ASSERT_EQ(r.verdicts.size(), 2u);
  EXPECT_EQ(r.verdicts[0], Visibility::inside);
  EXPECT_FALSE(r.verdicts[1].has_value());
  EXPECT_EQ(r.ns, 12.5);
  std::string raw = "{\"frame\": 4, \"verdicts\": [\"in";
  raw += '\0';
  raw += "side\"]}\x01";  // control characters, raw: not JSON, and quoted escaped
  try {
    protocol::parse_answer(raw, 4, 1, "frame 4");
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "answered frame 4 with a line that is not JSON: {\"frame\": 4, \"verdicts\": "
                                     "[\"in\\u0000side\"]}\\u0001");
  }
}

}  // namespace
}  // namespace cullproof

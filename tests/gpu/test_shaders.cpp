// ctest -L gpu: culling shaders on the Vulkan device (Mesa's lavapipe in CI). The example shader
// (examples/shaders/plane-tests.glsl) holds its claim through the test helper's defaults; each
// planted bug (the example with one change) is refuted with a shrunk, claim-breaking case written;
// many frames in one dispatch answer as each frame alone; what is wrong with a shader is named.
// Under the arithmetic a device may use (gpu::Arithmetic), emulated: the certified shader holds
// under every variant of the arithmetic, the example falls to two of them, half storage to nearest
// breaks every shader and rounded outward none; the view-space shaders hold on the frustums they
// describe, and the description keeps the promise the certified view-space test relies on.
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/gen/generators.hpp"
#include "cullproof/gpu/gpu.hpp"
#include "cullproof/gtest/gtest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>

namespace cullproof {
namespace {

std::string read(const std::string& relative) {
  std::ifstream in(std::string(CULLPROOF_SOURCE_DIR) + "/" + relative);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw std::runtime_error("cannot read " + relative);
  return text.str();
}

// One device for the whole binary (opening one measures its arithmetic).
const std::shared_ptr<gpu::Device>& device() {
  static const std::shared_ptr<gpu::Device> d = [] {
    auto opened = gpu::open_device();
    std::cout << gpu::describe(gpu::info(*opened));
    return opened;
  }();
  return d;
}

MethodInfo described(const std::string& name, unsigned volumes) {
  MethodInfo info;
  info.name = name;
  info.claim = Claim::conservative;
  info.tolerance = 1e-6;
  info.volumes = volumes;
  return info;
}

constexpr unsigned kAllKinds = kPointKind | kSphereKind | kAabbKind | kObbKind;

Method example(const gpu::Arithmetic& a = {}) {
  return gpu::make_shader_method(described("glsl-plane-tests", kAllKinds),
                                 {read("examples/shaders/plane-tests.glsl"), "plane-tests.glsl"}, device(), a);
}

Method certified(const gpu::Arithmetic& a) {
  MethodInfo info = described("glsl-certified-plane-tests", kAllKinds);
  info.claim = Claim::certified_conservative;
  info.tolerance = 0.0;
  return gpu::make_shader_method(info, {read("examples/shaders/certified-plane-tests.glsl"), "certified-plane-tests.glsl"},
                                 device(), a);
}

// One of the view-space sphere shaders (two-way).
Method view_space(const std::string& stem, const gpu::Arithmetic& a = {}, Claim claim = Claim::conservative) {
  MethodInfo info = described("glsl-" + stem, kSphereKind);
  info.three_way = false;
  info.claim = claim;
  if (claim == Claim::certified_conservative) info.tolerance = 0.0;
  return gpu::make_shader_method(info, {read("examples/shaders/" + stem + ".glsl"), stem + ".glsl", true}, device(), a);
}

// claim_holds with its corpus in a fresh folder of its own, removed after.
::testing::AssertionResult holds(const Method& m, std::uint64_t cases = 2000) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-gpu-" + m.name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  testing::ClaimOptions o;
  o.corpus = dir;
  o.cases = cases;
  ::testing::AssertionResult r = testing::claim_holds(m, o);
  std::filesystem::remove_all(dir);
  return r;
}

gpu::Arithmetic variant(const std::string& text) { return gpu::parse_arithmetic(text); }

TEST(GpuDevice, StatesItsFloatControlsAndItsMeasuredArithmetic) {
  const gpu::DeviceInfo& d = gpu::info(*device());
  EXPECT_FALSE(d.name.empty());
  const std::string text = gpu::describe(d);
  EXPECT_NE(text.find("float32: subnormals preserved"), std::string::npos) << text;
  EXPECT_NE(text.find("measured (float32, a probe shader)"), std::string::npos) << text;
}

TEST(GpuShader, TheExampleHoldsItsClaimOnEveryFamily) {
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-gpu-control-" + std::to_string(::getpid()));
  testing::ClaimOptions o;
  o.corpus = dir;
  EXPECT_TRUE(testing::claim_holds(example(), o));
  std::filesystem::remove_all(dir);
}

// A planted bug: the example with every `from` replaced by `to`, on the kinds it breaks.
struct Planted {
  std::string name, defect, from, to;
  unsigned volumes;
};

void PrintTo(const Planted& p, std::ostream* os) { *os << p.name; }

std::string planted_source(const Planted& p) {
  std::string glsl = read("examples/shaders/plane-tests.glsl");
  std::size_t changed = 0;
  for (std::size_t at = glsl.find(p.from); at != std::string::npos; at = glsl.find(p.from, at + p.to.size()), ++changed)
    glsl.replace(at, p.from.size(), p.to);
  if (changed == 0) throw std::logic_error(p.name + ": the example has no '" + p.from + "' to change");
  return glsl;
}

class GpuPlantedBug : public ::testing::TestWithParam<Planted> {};

TEST_P(GpuPlantedBug, IsRefutedWithAShrunkCase) {
  const Planted& p = GetParam();
  const Method method = gpu::make_shader_method(described(p.name, p.volumes), {planted_source(p), p.name + ".glsl"}, device());
  const auto dir = std::filesystem::temp_directory_path() / ("cullproof-gpu-" + p.name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  testing::ClaimOptions o;
  o.corpus = dir;
  const ::testing::AssertionResult r = testing::claim_holds(method, o);
  EXPECT_FALSE(r) << p.name << " (" << p.defect << ") survived: " << r.message();
  EXPECT_NE(std::string(r.message()).find("corpus file: "), std::string::npos) << "no shrunk case shown:\n" << r.message();
  std::size_t kept = 0;
  for (const CorpusEntry& e : load_corpus(dir)) kept += e.method == p.name && e.c.extra.at("violates_claim").get<bool>();
  EXPECT_GT(kept, 0u) << "no claim-breaking case written under " << dir;
  for (const Rejudged& stale : rejudge(dir, {method}))
    ADD_FAILURE() << stale.id << ": recorded judgement is stale (violates " << stale.violated_before << " -> "
                  << stale.violates_now << ")";
  std::filesystem::remove_all(dir);
}

std::string name_of(const ::testing::TestParamInfo<Planted>& p) {
  std::string s = p.param.name;
  for (char& c : s)
    if (c == '-') c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(
    Shaders, GpuPlantedBug,
    ::testing::Values(
        Planted{"glsl-skip-far-plane", "a plane skipped: every loop stops before the far plane", "i < 6", "i < 5", kAabbKind},
        Planted{"glsl-half-radius", "the radius stored in half precision, rounded to nearest (packHalf2x16)",
                "vec3 c, float r) {", "vec3 c, float radius) {\n  float r = unpackHalf2x16(packHalf2x16(vec2(radius, 0.0))).x;",
                kSphereKind},
        Planted{"glsl-cull-touching", "<= where < belongs: a volume touching a plane from outside culled", "< 0.0) return 0u;",
                "<= 0.0) return 0u;", kPointKind | kAabbKind}),
    name_of);

// The frames of a chunk in one dispatch per kind (Method::on_frames) answer as each volume asked
// alone, in the same order, kinds mixed.
TEST(GpuShader, ManyFramesInOneDispatchAnswerAsEachVolumeAlone) {
  const Method m = example();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-20.0f, 20.0f);
  std::vector<CaseFrustum> frusta;
  std::vector<std::vector<Volume>> volumes(40);
  for (int j = 0; j < 40; ++j) {
    const glm::mat4 p = off_axis_projection(-1.0f, 1.0f, -1.0f, 1.0f, 1.0f, 30.0f + float(j));
    frusta.push_back(frustum_spec(p, {}));
    for (int i = 0; i < 50; ++i) {
      const glm::vec3 c(u(rng), u(rng), u(rng) - 15.0f);
      switch (i % 3) {
        case 0: volumes[std::size_t(j)].push_back(Point(c)); break;
        case 1: volumes[std::size_t(j)].push_back(Sphere{c, std::abs(u(rng)) / 4.0f}); break;
        default: volumes[std::size_t(j)].push_back(Aabb{c - glm::vec3(1.0f), c + glm::vec3(2.0f)}); break;
      }
    }
  }
  std::vector<FrameRequest> frames;
  for (int j = 0; j < 40; ++j) frames.push_back({&frusta[std::size_t(j)], volumes[std::size_t(j)].data(), volumes[std::size_t(j)].size()});
  std::vector<Answer> together(40 * 50);
  m.classify_frames(frames.data(), frames.size(), together.data());
  std::size_t k = 0, seen[3] = {0, 0, 0};
  for (int j = 0; j < 40; ++j)
    for (const Volume& v : volumes[std::size_t(j)]) {
      const Answer alone = m.classify(frusta[std::size_t(j)], v);
      ASSERT_TRUE(alone.has_value());
      EXPECT_EQ(together[k], alone) << "frame " << j << ", volume " << k;
      ++seen[int(*alone)];
      ++k;
    }
  // Every verdict occurs, so the comparison can tell a misplaced answer.
  EXPECT_GT(seen[0], 0u);
  EXPECT_GT(seen[1], 0u);
  EXPECT_GT(seen[2], 0u);
}

TEST(GpuShader, ACompilerErrorNamesTheShadersFileAndLine) {
  try {
    gpu::make_shader_method(described("broken", kAabbKind),
                            {"uint cull_aabb(vec4 planes[6], vec3 lo, vec3 hi) {\n  return 1.5;\n}\n", "broken.glsl"}, device());
    FAIL() << "a shader that does not compile was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("broken.glsl:2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("shader method 'broken'"), std::string::npos) << e.what();
  }
}

TEST(GpuShader, AMissingFunctionNamesTheKindThatCallsIt) {
  try {
    gpu::make_shader_method(described("no-spheres", kAabbKind | kSphereKind),
                            {"uint cull_aabb(vec4 planes[6], vec3 lo, vec3 hi) { return 1u; }\n", "boxes-only.glsl"}, device());
    FAIL() << "a shader without cull_sphere was taken for spheres";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cull_sphere"), std::string::npos) << e.what();
  }
}

TEST(GpuShader, AnAnswerThatIsNotAVerdictIsAFaultNamingIt) {
  const Method m = gpu::make_shader_method(
      described("seven", kPointKind), {"uint cull_point(vec4 planes[6], vec3 p) { return 7u; }\n", "seven.glsl"}, device());
  Frustum f;
  for (Plane& p : f.planes) p = Plane{glm::vec3(0.0f), 1.0f};
  try {
    m.classify(frustum_spec(f), Volume(Point(0.0f, 0.0f, 0.0f)));
    FAIL() << "7 was taken for a verdict";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("answered 7"), std::string::npos) << e.what();
  }
}

// ---- the arithmetic a device may use, emulated (docs/gpu.md)

TEST(GpuArithmetic, TheCertifiedShadersHoldUnderEveryArithmeticTheSpecificationAllows) {
  for (const gpu::Arithmetic& a : gpu::all_arithmetic()) {
    if (a.half_storage == gpu::HalfStorage::nearest) continue;
    EXPECT_TRUE(holds(certified(a))) << gpu::to_string(a);
    EXPECT_TRUE(holds(view_space("certified-view-sphere", a, Claim::certified_conservative))) << gpu::to_string(a);
  }
}

TEST(GpuArithmetic, HalfStorageRefutesEvenTheCertifiedShader) {
  // A change of the volume, not of the arithmetic: no margin in the shader covers it.
  EXPECT_FALSE(holds(certified(variant("half")), 500));
}

TEST(GpuArithmetic, AMediumpShaderHoldsAtThirtyTwoBitsAndBreaksWhereMediumpIsSixteen) {
  // The example with one change, its default precision mediump, as mobile shaders are often
  // written: lavapipe computes it at 32 bits, where it holds; a device computing mediump at 16
  // bits breaks it. The example as it is (highp) is not changed by the variant.
  const gpu::Shader mediump{"precision mediump float;\n" + read("examples/shaders/plane-tests.glsl"), "mediump.glsl"};
  EXPECT_TRUE(holds(gpu::make_shader_method(described("glsl-mediump-plane-tests", kAllKinds), mediump, device())));
  EXPECT_FALSE(holds(
      gpu::make_shader_method(described("glsl-mediump-plane-tests", kAllKinds), mediump, device(), variant("relaxed")), 500));
  EXPECT_TRUE(holds(example(variant("relaxed"))));
}

TEST(GpuArithmetic, HalfStorageRoundedOutwardKeepsTheClaims) {
  // The stored volume contains the case's: what the shader proves of it holds of the case's.
  EXPECT_TRUE(holds(example(variant("half-outward"))));
  EXPECT_TRUE(holds(view_space("view-symmetric-sphere", variant("half-outward"))));
}

TEST(GpuArithmetic, HalfOutwardTakesNoPoints) {
  const Method m = example(variant("half-outward"));
  EXPECT_EQ(m.volumes, kAllKinds & ~unsigned(kPointKind));
  EXPECT_NE(m.source.find("points not taken"), std::string::npos) << m.source;
  try {
    gpu::make_shader_method(described("points", kPointKind), {read("examples/shaders/plane-tests.glsl"), "plane-tests.glsl"},
                            device(), variant("half-outward"));
    FAIL() << "a method of points only was made under half-outward";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("takes no volume"), std::string::npos) << e.what();
  }
}

TEST(GpuArithmetic, TheExampleFallsToLengthAtItsLowerBoundAndToFlushing) {
  // r * length(n) a few ulps short culls spheres that touch the frustum (the contact family);
  // tiny planes flushed to zero lose the sphere test's scaling (the subnormal family).
  EXPECT_FALSE(holds(example(variant("bounds-low")), 500));
  EXPECT_FALSE(holds(example(variant("flush"))));
  EXPECT_TRUE(holds(example(variant("contract"))));  // every expression precise: nothing to fuse
}

TEST(GpuArithmetic, AVariantNamesTheMethod) {
  EXPECT_EQ(example(variant("flush+contract")).name, "glsl-plane-tests@contract+flush");
  EXPECT_EQ(example().name, "glsl-plane-tests");
  EXPECT_NE(example(variant("half")).source.find("arithmetic emulated: half"), std::string::npos);
}

// ---- the view-space form

TEST(GpuShader, TheViewSpaceShadersHoldTheirClaimsOnTheFrustaTheyDescribe) {
  EXPECT_TRUE(holds(view_space("view-symmetric-sphere")));
  EXPECT_TRUE(holds(view_space("projected-sphere")));
}

TEST(GpuShader, TheViewSpaceDescriptionKeepsItsPromiseToACertifiedShader) {
  // gpu.hpp: at any point, each described plane's value lies within 2^-14 |y| + 2^-20 (|t|_1 + |e|)
  // + 2^-126 of the case's plane's, its normal made unit; checked in long double on the frusta of
  // every family (seed 3, not the runs' seed), at points about the case's volume and far from it.
  using L = long double;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  std::size_t described = 0, points = 0;
  for (const gen::Distribution dist : gen::parse_distributions("all")) {
    for (std::uint64_t index = 0; index < 4000; index += gen::cases_per_frame(dist)) {
      const gen::GenCase c = gen::draw_case(dist, 3, index);
      const Frustum& planes = c.frustum.planes;
      const auto v = gpu::view_space_frustum(planes);
      if (!v) continue;
      ++described;
      const std::array<float, 24>& x = *v;
      const L t[3] = {x[12], x[13], x[14]};
      const L t1 = std::fabs(t[0]) + std::fabs(t[1]) + std::fabs(t[2]);
      const bool infinite = std::isinf(x[21]);
      const glm::vec3 centre = std::visit(
          [](const auto& volume) -> glm::vec3 {
            using T = std::decay_t<decltype(volume)>;
            if constexpr (std::is_same_v<T, Point>) return volume;
            else if constexpr (std::is_same_v<T, Aabb>) return 0.5f * volume.min + 0.5f * volume.max;  // no overflow
            else return volume.center;
          },
          c.volume);
      for (int k = 0; k < 8; ++k) {
        const L scale = L(c.scene_size) * (k < 4 ? 1 : 1000);
        const L p[3] = {centre.x + scale * L(g(rng)), centre.y + scale * L(g(rng)), centre.z + scale * L(g(rng))};
        L y[3];
        for (int row = 0; row < 3; ++row) y[row] = t[row] + x[row] * p[0] + x[4 + row] * p[1] + x[8 + row] * p[2];
        const L length_y = std::sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        const L lx = x[16], lz = x[17], by = x[18], bz = x[19];
        const L described_value[6] = {lx * y[0] + lz * y[2], -lx * y[0] + lz * y[2], by * y[1] + bz * y[2],
                                      -by * y[1] + bz * y[2], y[2] - x[20], infinite ? 0 : x[21] - y[2]};
        const L offset[6] = {0, 0, 0, 0, x[20], infinite ? 0 : x[21]};
        for (int i = 0; i < (infinite ? 5 : 6); ++i) {
          const Plane& q = planes[i];
          const L norm = std::sqrt(L(q.n.x) * q.n.x + L(q.n.y) * q.n.y + L(q.n.z) * q.n.z);
          const L case_value = (L(q.n.x) * p[0] + L(q.n.y) * p[1] + L(q.n.z) * p[2] + q.d) / norm;
          const L promise = std::ldexp(L(1), -14) * length_y + std::ldexp(L(1), -20) * (t1 + offset[i]) +
                            std::ldexp(L(1), -126) + std::ldexp(L(1), -60) * (length_y + std::fabs(case_value) + t1);
          ASSERT_LE(std::fabs(described_value[i] - case_value), promise)
              << gen::to_string(dist) << " case " << index << ", plane " << i << ", point " << k;
          ++points;
        }
      }
    }
  }
  // The frusta the description takes: 31,517 here. A promise computed wrongly refuses most of them
  // (a transposed inverse leaves 3,431), so it is kept from being vacuous by a floor.
  EXPECT_GT(described, 30000u);
  std::cout << described << " frusta described, " << points << " plane values compared\n";
}

TEST(GpuShader, TheViewSpaceFormDescribesSymmetricPerspectiveFrustaOnly) {
  const glm::vec3 eye(3.0f, -2.0f, 5.0f);
  const glm::mat4 view = glm::lookAtRH(eye, eye + glm::vec3(1.0f, 0.5f, -1.0f), glm::vec3(0.0f, 1.0f, 0.0f));
  const float n = 0.5f, f = 80.0f, t = n * 0.75f, r = t * 1.5f;  // tan(half fov up) = 0.75, across 1.125
  const auto v = gpu::view_space_frustum(frustum_spec(glm::frustumRH_NO(-r, r, -t, t, n, f) * view, {}).planes);
  ASSERT_TRUE(v.has_value());
  const auto& x = *v;
  EXPECT_NEAR(x[20], n, 1e-5);                // near
  EXPECT_NEAR(x[21], f, 1e-3);                // far
  EXPECT_NEAR(x[22], 1.0 / 1.125, 1e-5);      // P00 = cot(half fov across)
  EXPECT_NEAR(x[23], 1.0 / 0.75, 1e-5);       // P11
  EXPECT_NEAR(x[17] / x[16], 1.125, 1e-5);    // the left plane's (x, z): tan of the half angle
  // The eye goes to the origin; a point ahead of it to (0, 0, its distance).
  const glm::mat4 to_view(glm::vec4(x[0], x[1], x[2], x[3]), glm::vec4(x[4], x[5], x[6], x[7]),
                          glm::vec4(x[8], x[9], x[10], x[11]), glm::vec4(x[12], x[13], x[14], x[15]));
  const glm::vec3 at_eye = glm::vec3(to_view * glm::vec4(eye, 1.0f));
  EXPECT_NEAR(glm::length(at_eye), 0.0f, 1e-5f);
  const glm::vec3 ahead = glm::vec3(to_view * glm::vec4(eye + 6.0f * glm::normalize(glm::vec3(1.0f, 0.5f, -1.0f)), 1.0f));
  EXPECT_NEAR(ahead.z, 6.0f, 1e-4f);
  EXPECT_NEAR(ahead.x, 0.0f, 1e-4f);
  EXPECT_NEAR(ahead.y, 0.0f, 1e-4f);
  // Off-axis and orthographic frusta are not described; an infinite far plane is.
  EXPECT_FALSE(gpu::view_space_frustum(frustum_spec(glm::frustumRH_NO(-r, 2 * r, -t, t, n, f) * view, {}).planes));
  EXPECT_FALSE(gpu::view_space_frustum(frustum_spec(glm::orthoRH_NO(-r, r, -t, t, n, f) * view, {}).planes));
  const auto infinite = gpu::view_space_frustum(frustum_spec(glm::infinitePerspectiveRH(1.0f, 1.5f, n) * view, {}).planes);
  ASSERT_TRUE(infinite.has_value());
  EXPECT_TRUE(std::isinf((*infinite)[21]));
}

}  // namespace
}  // namespace cullproof

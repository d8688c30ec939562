// ctest -L gpu: culling shaders on the Vulkan device (Mesa's lavapipe in CI). The example shader
// (examples/shaders/plane-tests.glsl) holds its claim through the test helper's defaults; each
// planted bug (the example with one change) is refuted with a shrunk, claim-breaking case written;
// many frames in one dispatch answer as each frame alone; what is wrong with a shader is named.
#include "cullproof/corpus/corpus.hpp"
#include "cullproof/gpu/gpu.hpp"
#include "cullproof/gtest/gtest.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

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

Method example() {
  return gpu::make_shader_method(described("glsl-plane-tests", kPointKind | kSphereKind | kAabbKind | kObbKind),
                                 {read("examples/shaders/plane-tests.glsl"), "plane-tests.glsl"}, device());
}

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

}  // namespace
}  // namespace cullproof

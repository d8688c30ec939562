// A culling shader as a Method: the user's functions wrapped in a compute shader per volume kind,
// compiled with glslang, and run over many frames in one dispatch per kind.
#include "vulkan.hpp"

#include <fmt/format.h>
#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>

#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <utility>

namespace cullproof::gpu {

namespace {

struct Kind {
  unsigned bit;
  const char* name;     // the kind's name, as volume_kind_name
  const char* call;     // the user's function and its arguments, read from the record at r
  std::uint32_t words;  // the record's 32-bit words: the frame, then the volume's floats
};

// A record: [frame, floats...]; f(k) reads float k of the record.
const std::array<Kind, 4> kKinds{{
    {kPointKind, "point", "cull_point(planes, vec3(f(1u), f(2u), f(3u)))", 4},
    {kSphereKind, "sphere", "cull_sphere(planes, vec3(f(1u), f(2u), f(3u)), f(4u))", 5},
    {kAabbKind, "aabb", "cull_aabb(planes, vec3(f(1u), f(2u), f(3u)), vec3(f(4u), f(5u), f(6u)))", 7},
    {kObbKind, "obb",
     "cull_obb(planes, vec3(f(1u), f(2u), f(3u)), mat3(f(4u), f(5u), f(6u), f(7u), f(8u), f(9u), f(10u), f(11u), f(12u)), "
     "vec3(f(13u), f(14u), f(15u)))",
     16},
}};

const Kind& kind_of(unsigned bit) {
  for (const Kind& k : kKinds)
    if (k.bit == bit) return k;
  throw std::logic_error("cullproof::gpu: no volume kind " + std::to_string(bit));
}

// The volume's floats after the frame word.
void put(std::vector<std::uint32_t>& out, float x) {
  std::uint32_t w;
  static_assert(sizeof w == sizeof x, "32-bit floats");
  std::memcpy(&w, &x, sizeof w);
  out.push_back(w);
}
void put(std::vector<std::uint32_t>& out, const glm::vec3& v) {
  for (int i = 0; i < 3; ++i) put(out, v[i]);
}
void put_volume(std::vector<std::uint32_t>& out, const Volume& v) {
  if (const auto* p = std::get_if<Point>(&v)) return put(out, *p);
  if (const auto* s = std::get_if<Sphere>(&v)) {
    put(out, s->center);
    return put(out, s->radius);
  }
  if (const auto* b = std::get_if<Aabb>(&v)) {
    put(out, b->min);
    return put(out, b->max);
  }
  const Obb& o = std::get<Obb>(v);
  put(out, o.center);
  for (int c = 0; c < 3; ++c) put(out, o.axes[c]);
  put(out, o.half);
}

// glslang's process-wide state, made once (glslang_initialize_process is not reentrant).
void start_glslang() {
  static const bool started = glslang_initialize_process() != 0;
  if (!started) throw std::runtime_error("glslang: cannot start the GLSL compiler");
}

}  // namespace

std::vector<std::uint32_t> compile_glsl(const std::string& source, const std::string& file) {
  static std::mutex compiling;  // glslang's front end is not safe to run on two threads at once
  std::lock_guard<std::mutex> lock(compiling);
  start_glslang();
  glslang_input_t in{};
  in.language = GLSLANG_SOURCE_GLSL;
  in.stage = GLSLANG_STAGE_COMPUTE;
  in.client = GLSLANG_CLIENT_VULKAN;
  in.client_version = GLSLANG_TARGET_VULKAN_1_0;
  in.target_language = GLSLANG_TARGET_SPV;
  in.target_language_version = GLSLANG_TARGET_SPV_1_0;
  in.code = source.c_str();
  in.default_version = 450;
  in.default_profile = GLSLANG_NO_PROFILE;
  in.messages = GLSLANG_MSG_DEFAULT_BIT;
  in.resource = glslang_default_resource();
  std::string errors;
  std::vector<std::uint32_t> out;
  glslang_shader_t* sh = glslang_shader_create(&in);
  glslang_program_t* program = nullptr;
  if (!glslang_shader_preprocess(sh, &in) || !glslang_shader_parse(sh, &in)) {
    errors = glslang_shader_get_info_log(sh);
  } else {
    program = glslang_program_create();
    glslang_program_add_shader(program, sh);
    if (!glslang_program_link(program, GLSLANG_MSG_SPV_RULES_BIT | GLSLANG_MSG_VULKAN_RULES_BIT)) {
      errors = glslang_program_get_info_log(program);
    } else {
      glslang_spv_options_t spv{};
      spv.disable_optimizer = true;
      spv.validate = true;
      glslang_program_SPIRV_generate_with_options(program, GLSLANG_STAGE_COMPUTE, &spv);
      out.resize(glslang_program_SPIRV_get_size(program));
      glslang_program_SPIRV_get(program, out.data());
      if (const char* m = glslang_program_SPIRV_get_messages(program); m && *m) errors = m;
    }
  }
  if (program) glslang_program_delete(program);
  glslang_shader_delete(sh);
  if (!errors.empty() || out.empty()) throw std::invalid_argument(file + " does not compile:\n" + errors);
  return out;
}

MeasuredArithmetic probe_arithmetic(const std::shared_ptr<Device>& device) {
  // Inputs: 2^-140 (subnormal), 1, 2^-70, and a, b, c with a * b + c = -2^-46 exactly, whose
  // product rounds to 1 in float (so the sum is 0 unless it is fused).
  const std::string source = R"GLSL(#version 450
layout(local_size_x = 1) in;
layout(std430, set = 0, binding = 0) readonly buffer Unused { vec4 unused[]; };
layout(std430, set = 0, binding = 1) readonly buffer In { float x[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Out { uint y[]; };
layout(push_constant) uniform Count { uint count; };
void main() {
  y[0] = floatBitsToUint(x[0] * x[1]);
  y[1] = floatBitsToUint(x[2] * x[2]);
  y[2] = floatBitsToUint(x[3] * x[4] + x[5]);
  precise float p = x[3] * x[4] + x[5];
  y[3] = floatBitsToUint(p);
  y[4] = floatBitsToUint(fma(x[3], x[4], x[5]));
}
)GLSL";
  Pipeline probe(device, compile_glsl(source, "cullproof arithmetic probe"));
  const float e = std::ldexp(1.0f, -23);
  std::vector<std::uint32_t> in;
  for (float x : {std::ldexp(1.0f, -140), 1.0f, std::ldexp(1.0f, -70), 1.0f + e, 1.0f - e, -1.0f}) put(in, x);
  std::vector<std::uint32_t> out;
  std::lock_guard<std::mutex> lock(device->mutex());
  probe.dispatch({0.0f, 0.0f, 0.0f, 0.0f}, in, 5, out);  // one invocation (a group of one) writes the 5 words
  const auto as_float = [](std::uint32_t w) {
    float f;
    std::memcpy(&f, &w, sizeof f);
    return f;
  };
  MeasuredArithmetic m;
  m.subnormal_inputs_flushed = as_float(out[0]) == 0.0f;
  m.subnormal_results_flushed = as_float(out[1]) == 0.0f;
  m.contracts = as_float(out[2]) != 0.0f;
  m.fuses_precise = as_float(out[3]) != 0.0f;
  m.fma_fused = as_float(out[4]) != 0.0f;
  return m;
}

namespace {

// SPIR-V of the wrapped shader; std::invalid_argument with the compiler's messages, which name the
// shader's file and line.
std::vector<std::uint32_t> compile(const Shader& shader, const Kind& kind, const std::string& method) {
  try {
    return compile_glsl(wrapped_source(shader, kind.bit), shader.file);
  } catch (const std::invalid_argument& e) {
    const std::string call = kind.call;
    throw std::invalid_argument(fmt::format("shader method '{}': {} (wrapped for {} volumes, which calls {})", method,
                                            e.what(), kind.name, call.substr(0, call.find('('))));
  }
}

// The pipelines of one shader method and the device they run on; the device's own time tallied.
class Runner {
 public:
  Runner(const MethodInfo& info, const Shader& shader, std::shared_ptr<Device> device) : info_(info), device_(std::move(device)) {
    for (std::size_t k = 0; k < kKinds.size(); ++k)
      if (info.volumes & kKinds[k].bit) pipelines_[k] = std::make_unique<Pipeline>(device_, compile(shader, kKinds[k], info.name));
  }

  // Answers for every volume of the frames, frame after frame (Method::on_frames).
  void run(const FrameRequest* frames, std::size_t n, Answer* answers) {
    std::vector<float> planes;
    planes.reserve(n * 24);
    std::size_t total = 0;
    for (std::size_t j = 0; j < n; ++j) {
      for (const Plane& p : frames[j].frustum->planes.planes) planes.insert(planes.end(), {p.n.x, p.n.y, p.n.z, p.d});
      total += frames[j].count;
    }
    if (n > 0xffffffffu / 6 || total > 0xffffffffu)
      throw std::runtime_error(fmt::format("shader method '{}': {} frames of {} volumes exceed one dispatch's 32-bit indices",
                                           info_.name, n, total));
    for (std::size_t i = 0; i < total; ++i) answers[i] = Answer{};
    std::lock_guard<std::mutex> lock(device_->mutex());
    for (std::size_t k = 0; k < kKinds.size(); ++k) {
      if (!pipelines_[k]) continue;
      records_.clear();
      where_.clear();
      std::size_t at = 0;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < frames[j].count; ++i, ++at) {
          const Volume& v = frames[j].volumes[i];
          if (volume_kind(v) != kKinds[k].bit) continue;
          records_.push_back(std::uint32_t(j));
          put_volume(records_, v);
          where_.push_back(at);
        }
      if (where_.empty()) continue;
      const double ns = pipelines_[k]->dispatch(planes, records_, std::uint32_t(where_.size()), verdicts_);
      for (std::size_t i = 0; i < where_.size(); ++i) {
        const std::uint32_t x = verdicts_[i];
        if (x > 2)
          throw std::runtime_error(fmt::format(
              "shader method '{}': cull_{} answered {} for a volume (the {}th asked): not 0 (outside), 1 (intersecting) or "
              "2 (inside)",
              info_.name, kKinds[k].name, x, where_[i] + 1));
        answers[where_[i]] = static_cast<Visibility>(x);
      }
      own_ns_ += ns;
      own_volumes_ += where_.size();
    }
  }

  std::pair<double, std::uint64_t> take_own_timing() {
    std::lock_guard<std::mutex> lock(device_->mutex());
    const std::pair<double, std::uint64_t> r{own_ns_, own_volumes_};
    own_ns_ = 0.0;
    own_volumes_ = 0;
    return r;
  }

 private:
  MethodInfo info_;
  std::shared_ptr<Device> device_;
  std::array<std::unique_ptr<Pipeline>, 4> pipelines_;
  // Reused from dispatch to dispatch (under the device's mutex).
  std::vector<std::uint32_t> records_, verdicts_;
  std::vector<std::size_t> where_;
  double own_ns_ = 0.0;
  std::uint64_t own_volumes_ = 0;
};

class Prepared : public PreparedFrustum {
 public:
  Prepared(std::shared_ptr<Runner> r, const CaseFrustum& f) : runner_(std::move(r)), frustum_(f) {}
  Answer classify(const Volume& v) override {
    Answer a;
    const FrameRequest one{&frustum_, &v, 1};
    runner_->run(&one, 1, &a);
    return a;
  }
  void classify_batch(const Point* v, std::size_t n, Answer* a) override { many(v, n, a); }
  void classify_batch(const Sphere* v, std::size_t n, Answer* a) override { many(v, n, a); }
  void classify_batch(const Aabb* v, std::size_t n, Answer* a) override { many(v, n, a); }
  void classify_batch(const Obb* v, std::size_t n, Answer* a) override { many(v, n, a); }

 private:
  template <class K>
  void many(const K* v, std::size_t n, Answer* a) {
    volumes_.assign(v, v + n);
    const FrameRequest one{&frustum_, volumes_.data(), n};
    runner_->run(&one, 1, a);
  }
  std::shared_ptr<Runner> runner_;
  CaseFrustum frustum_;
  std::vector<Volume> volumes_;
};

}  // namespace

std::string wrapped_source(const Shader& shader, unsigned kind_bit) {
  const Kind& kind = kind_of(kind_bit);
  // The user's functions come first, as their own file for the compiler's messages
  // (GL_GOOGLE_cpp_style_line_directive: #line with a file name).
  return fmt::format(R"GLSL(#version 450
#extension GL_GOOGLE_cpp_style_line_directive : require
layout(local_size_x = {group}) in;
layout(std430, set = 0, binding = 0) readonly buffer CullproofPlanes {{ vec4 cullproof_planes[]; }};
layout(std430, set = 0, binding = 1) readonly buffer CullproofVolumes {{ uint cullproof_volumes[]; }};
layout(std430, set = 0, binding = 2) writeonly buffer CullproofVerdicts {{ uint cullproof_verdicts[]; }};
layout(push_constant) uniform CullproofCount {{ uint cullproof_count; }};
#define CULLPROOF_KIND_{upper} 1
#line 1 "{file}"
{glsl}
#line 1 "cullproof wrapper ({kind})"
void main() {{
  uint i = gl_GlobalInvocationID.x;
  if (i >= cullproof_count) return;
  uint r = i * {words}u;
  uint p = cullproof_volumes[r] * 6u;
  vec4 planes[6] = vec4[6](cullproof_planes[p], cullproof_planes[p + 1u], cullproof_planes[p + 2u],
                           cullproof_planes[p + 3u], cullproof_planes[p + 4u], cullproof_planes[p + 5u]);
#define f(k) uintBitsToFloat(cullproof_volumes[r + (k)])
  cullproof_verdicts[i] = {call};
#undef f
}}
)GLSL",
                     fmt::arg("group", kGroupSize), fmt::arg("upper", [&] {
                       std::string u = kind.name;
                       for (char& c : u) c = char(c - 'a' + 'A');
                       return u;
                     }()),
                     fmt::arg("file", shader.file), fmt::arg("glsl", shader.glsl), fmt::arg("kind", kind.name),
                     fmt::arg("words", kind.words), fmt::arg("call", kind.call));
}

Method make_shader_method(MethodInfo info, const Shader& shader, std::shared_ptr<Device> device) {
  if (info.volumes == 0) throw std::invalid_argument("shader method '" + info.name + "': no volume kinds (\"volumes\")");
  if (info.stateful) throw std::invalid_argument("shader method '" + info.name + "': a shader is not stateful");
  if (!device) device = open_device();
  const DeviceInfo& d = device->info();
  info.source += (info.source.empty() ? "" : "; ") +
                 fmt::format("run on {} ({})", d.name, d.driver_info.empty() ? d.driver_name : d.driver_name + " " + d.driver_info);
  auto runner = std::make_shared<Runner>(info, shader, device);
  Method m(
      info, [runner](const CaseFrustum& f) -> std::unique_ptr<PreparedFrustum> { return std::make_unique<Prepared>(runner, f); },
      /*batch=*/true);
  m.on_frames([runner](const FrameRequest* frames, std::size_t n, Answer* answers) { runner->run(frames, n, answers); });
  m.on_own_timing([runner] { return runner->take_own_timing(); });
  return m;
}

}  // namespace cullproof::gpu

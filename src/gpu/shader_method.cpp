// A culling shader as a Method: the user's functions wrapped in a compute shader per volume kind,
// compiled with glslang, and run over many frames in one dispatch per kind.
#include "vulkan.hpp"

#include "cullproof/core/frustum_build.hpp"

#include <fmt/format.h>
#include <glslang/Include/glslang_c_interface.h>
#include <glslang/Public/resource_limits_c.h>

#include <array>
#include <cctype>
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

// A record: [frame, floats...]; f(k) reads float k of the record. The last kind is the view-space
// form of spheres (Shader::view_space), whose frame is the view-space frustum's 24 floats.
const std::array<Kind, 5> kKinds{{
    {kPointKind, "point", "cull_point(planes, vec3(f(1u), f(2u), f(3u)))", 4},
    {kSphereKind, "sphere", "cull_sphere(planes, vec3(f(1u), f(2u), f(3u)), f(4u))", 5},
    {kAabbKind, "aabb", "cull_aabb(planes, vec3(f(1u), f(2u), f(3u)), vec3(f(4u), f(5u), f(6u)))", 7},
    {kObbKind, "obb",
     "cull_obb(planes, vec3(f(1u), f(2u), f(3u)), mat3(f(4u), f(5u), f(6u), f(7u), f(8u), f(9u), f(10u), f(11u), f(12u)), "
     "vec3(f(13u), f(14u), f(15u)))",
     16},
    {kSphereKind, "sphere_view",
     "cull_sphere_view(mat4(planes[0], planes[1], planes[2], planes[3]), planes[4], planes[5], vec3(f(1u), f(2u), f(3u)), "
     "f(4u))",
     5},
}};
constexpr std::size_t kSphereView = 4;

// The kind a shader's volumes of `bit` go to.
const Kind& kind_of(unsigned bit, bool view_space) {
  if (bit == kSphereKind && view_space) return kKinds[kSphereView];
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

std::string float_kernel_head(std::uint32_t local_size) {
  return fmt::format(R"GLSL(#version 450
layout(local_size_x = {}) in;
layout(std430, set = 0, binding = 0) readonly buffer Unused {{ vec4 unused[]; }};
layout(std430, set = 0, binding = 1) readonly buffer In {{ float x[]; }};
layout(std430, set = 0, binding = 2) writeonly buffer Out {{ uint y[]; }};
layout(push_constant) uniform Count {{ uint count; }};
)GLSL",
                     local_size);
}

MeasuredArithmetic probe_arithmetic(const std::shared_ptr<Device>& device) {
  // Inputs: 2^-140 (subnormal), 1, 2^-70, and a, b, c with a * b + c = -2^-46 exactly, whose
  // product rounds to 1 in float (so the sum is 0 unless it is fused).
  const std::string source = float_kernel_head(1) + R"GLSL(
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
std::vector<std::uint32_t> compile(const Shader& shader, const Kind& kind, const std::string& method,
                                   const Arithmetic& arithmetic) {
  try {
    return emulate_arithmetic(compile_glsl(wrapped_source(shader, kind.bit), shader.file), arithmetic);
  } catch (const std::invalid_argument& e) {
    const std::string call = kind.call;
    throw std::invalid_argument(fmt::format("shader method '{}': {} (wrapped for {} volumes, which calls {})", method,
                                            e.what(), kind.name, call.substr(0, call.find('('))));
  }
}

// The pipelines of one shader method and the device they run on; the device's own time tallied.
class Runner {
 public:
  Runner(const MethodInfo& info, const Shader& shader, std::shared_ptr<Device> device, const Arithmetic& arithmetic)
      : info_(info), device_(std::move(device)), half_(arithmetic.half_storage), view_space_(shader.view_space) {
    for (std::size_t k = 0; k < kSphereView; ++k)
      if (info.volumes & kKinds[k].bit)
        pipelines_[k] = std::make_unique<Pipeline>(
            device_, compile(shader, kind_of(kKinds[k].bit, shader.view_space), info.name, arithmetic));
  }

  // Answers for every volume of the frames, frame after frame (Method::on_frames); a frame the
  // view-space form does not describe leaves its spheres unanswered.
  void run(const FrameRequest* frames, std::size_t n, Answer* answers) {
    std::vector<float> planes, views;
    std::vector<bool> described;
    planes.reserve(n * 24);
    std::size_t total = 0;
    for (std::size_t j = 0; j < n; ++j) {
      for (const Plane& p : frames[j].frustum->planes.planes) planes.insert(planes.end(), {p.n.x, p.n.y, p.n.z, p.d});
      if (view_space_) {
        const auto v = view_space_frustum(frames[j].frustum->planes);
        described.push_back(v.has_value());
        if (v) views.insert(views.end(), v->begin(), v->end());
        else views.insert(views.end(), 24, 0.0f);
      }
      total += frames[j].count;
    }
    if (n > 0xffffffffu / 6 || total > 0xffffffffu)
      throw std::runtime_error(fmt::format("shader method '{}': {} frames of {} volumes exceed one dispatch's 32-bit indices",
                                           info_.name, n, total));
    for (std::size_t i = 0; i < total; ++i) answers[i] = Answer{};
    std::lock_guard<std::mutex> lock(device_->mutex());
    for (std::size_t k = 0; k < kSphereView; ++k) {
      if (!pipelines_[k]) continue;
      const bool view = view_space_ && kKinds[k].bit == kSphereKind;
      records_.clear();
      where_.clear();
      std::size_t at = 0;
      for (std::size_t j = 0; j < n; ++j)
        for (std::size_t i = 0; i < frames[j].count; ++i, ++at) {
          const Volume& v = frames[j].volumes[i];
          if (volume_kind(v) != kKinds[k].bit || (view && !described[j])) continue;
          records_.push_back(std::uint32_t(j));
          if (half_ == HalfStorage::none) put_volume(records_, v);
          else put_volume(records_, stored_volume(v, half_));
          where_.push_back(at);
        }
      if (where_.empty()) continue;
      const double ns = pipelines_[k]->dispatch(view ? views : planes, records_, std::uint32_t(where_.size()), verdicts_);
      const char* name = kind_of(kKinds[k].bit, view).name;
      for (std::size_t i = 0; i < where_.size(); ++i) {
        const std::uint32_t x = verdicts_[i];
        if (x > 2)
          throw std::runtime_error(fmt::format(
              "shader method '{}': cull_{} answered {} for a volume (the {}th asked): not 0 (outside), 1 (intersecting) or "
              "2 (inside)",
              info_.name, name, x, where_[i] + 1));
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
  HalfStorage half_;
  bool view_space_;
  std::array<std::unique_ptr<Pipeline>, 4> pipelines_;  // by kKinds' first four
  // Reused from dispatch to dispatch (under the device's mutex).
  std::vector<std::uint32_t> records_, verdicts_;
  std::vector<std::size_t> where_;
  double own_ns_ = 0.0;
  std::uint64_t own_volumes_ = 0;
};

class Prepared : public BatchesByKind<Prepared> {
 public:
  Prepared(std::shared_ptr<Runner> r, const CaseFrustum& f) : runner_(std::move(r)), frustum_(f) {}
  Answer classify(const Volume& v) override {
    Answer a;
    const FrameRequest one{&frustum_, &v, 1};
    runner_->run(&one, 1, &a);
    return a;
  }

 private:
  friend class BatchesByKind<Prepared>;
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

// How far a description's planes may lie from the case's (gpu.hpp): their normals (the symmetry
// is checked to within 2^-16) and their offsets.
constexpr double kNormalError = 0x1p-14, kOffsetError = 0x1p-20;

// How far the planes `out` describes lie from the case's planes (unit normals n, offsets d): at a
// point whose view coordinates are y (y = V x + t, V and t as `out` holds them), a described
// plane's value minus the case's is h_i . y + k_i. The largest |h_i|, and the largest |k_i| less
// 2^-126 over |t|_1 + |e_i| (e_i the plane's offset in view space: 0, -near, far); in double, from
// the floats as the shader reads them.
std::pair<double, double> description_error(const std::array<float, 24>& out, const glm::dvec3 n[6], const double d[6],
                                            bool infinite) {
  glm::dmat3 v;  // v[column][row]: row k is view axis k (r, u, f), column j world axis j
  for (int j = 0; j < 3; ++j)
    for (int k = 0; k < 3; ++k) v[j][k] = double(out[std::size_t(4 * j + k)]);
  const glm::dvec3 t(out[12], out[13], out[14]);
  const glm::dmat3 w = glm::inverse(v);
  const glm::dvec3 wt = w * t;
  const double lx = out[16], lz = out[17], by = out[18], bz = out[19];
  const glm::dvec3 m[6] = {{lx, 0.0, lz}, {-lx, 0.0, lz}, {0.0, by, bz}, {0.0, -by, bz}, {0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}};
  const double e[6] = {0.0, 0.0, 0.0, 0.0, -double(out[20]), double(out[21])};
  double h = 0.0, k = 0.0;
  for (int i = 0; i < (infinite ? 5 : 6); ++i) {
    const double normal = glm::length(m[i] - glm::transpose(w) * n[i]);
    const double off = std::fabs(e[i] - d[i] + glm::dot(n[i], wt));
    const double scale = std::fabs(t.x) + std::fabs(t.y) + std::fabs(t.z) + std::fabs(e[i]);
    // A float that overflowed, or axes with no inverse: no promise, no description.
    if (!std::isfinite(normal) || !std::isfinite(off) || !std::isfinite(scale)) return {NAN, NAN};
    h = std::max(h, normal);
    if (off > 0x1p-126) k = std::max(k, scale > 0.0 ? (off - 0x1p-126) / scale : double(INFINITY));
  }
  return {h, k};
}

}  // namespace

std::optional<std::array<float, 24>> view_space_frustum(const Frustum& frustum) {
  // In double, from the float planes: unit normals, the view's axes from the side planes' normals,
  // the eye where the side planes meet; every symmetry checked to within 2^-16.
  constexpr double kTolerance = 1.0 / 65536;
  glm::dvec3 n[6];
  double d[6];
  for (int i = 0; i < 6; ++i) {
    n[i] = glm::dvec3(frustum[i].n);
    d[i] = double(frustum[i].d);
    const double length = glm::length(n[i]);
    if (!std::isfinite(length) || !std::isfinite(d[i])) return std::nullopt;
    if (length > 0.0) {
      n[i] /= length;
      d[i] /= length;
    } else if (i != 5 || !(d[i] > 0.0)) {
      return std::nullopt;  // only the far plane may be all space (an infinite projection)
    }
  }
  const bool infinite = glm::length(n[5]) == 0.0;
  const auto small = [&](double x) { return std::fabs(x) <= kTolerance; };
  const glm::dvec3 f = n[4], r_sum = n[0] - n[1], u_sum = n[2] - n[3];
  if (glm::length(r_sum) < kTolerance || glm::length(u_sum) < kTolerance) return std::nullopt;
  const glm::dvec3 r = glm::normalize(r_sum), u = glm::normalize(u_sum);
  if (!small(glm::dot(r, f)) || !small(glm::dot(u, f)) || !small(glm::dot(r, u))) return std::nullopt;
  if (!infinite && glm::length(n[5] + f) > kTolerance) return std::nullopt;
  // Left and right mirror each other across the view's y-z plane, bottom and top across x-z.
  if (!small(glm::dot(n[0], r) + glm::dot(n[1], r)) || !small(glm::dot(n[0], f) - glm::dot(n[1], f)) ||
      !small(glm::dot(n[0], u)) || !small(glm::dot(n[1], u)) || !small(glm::dot(n[2], u) + glm::dot(n[3], u)) ||
      !small(glm::dot(n[2], f) - glm::dot(n[3], f)) || !small(glm::dot(n[2], r)) || !small(glm::dot(n[3], r)))
    return std::nullopt;
  const double lx = (glm::dot(n[0], r) - glm::dot(n[1], r)) / 2, lz = (glm::dot(n[0], f) + glm::dot(n[1], f)) / 2;
  const double by = (glm::dot(n[2], u) - glm::dot(n[3], u)) / 2, bz = (glm::dot(n[2], f) + glm::dot(n[3], f)) / 2;
  if (!(lx > 0.0 && lz > 0.0 && by > 0.0 && bz > 0.0)) return std::nullopt;  // a perspective frustum, under 180 degrees
  // The eye: where left, right and bottom meet, their unit normals spanning a volume over 2^-16
  // (else the point is ill-defined), then where all four side planes come nearest; the top passes
  // through it.
  if (!(std::fabs(glm::dot(n[0], glm::cross(n[1], n[2]))) > kTolerance)) return std::nullopt;
  const auto meet = planes_meet(glm::dvec4(n[0], d[0]), glm::dvec4(n[1], d[1]), glm::dvec4(n[2], d[2]));
  if (!meet) return std::nullopt;
  // In least squares over the four: three of them fix the point badly when two are nearly
  // opposite (a field of view near 180 degrees), and the fourth then misses it by up to 2^-16.
  glm::dmat3 normal_equations(0.0);
  glm::dvec3 rhs(0.0);
  for (int i = 0; i < 4; ++i) {
    normal_equations += glm::outerProduct(n[i], n[i]);
    rhs -= d[i] * n[i];
  }
  const glm::dvec3 refined = glm::inverse(normal_equations) * rhs;
  const glm::dvec3 eye = std::isfinite(refined.x) && std::isfinite(refined.y) && std::isfinite(refined.z) ? refined : *meet;
  if (std::fabs(glm::dot(n[3], eye) + d[3]) > kTolerance * (1.0 + glm::length(eye))) return std::nullopt;
  const double znear = -(glm::dot(f, eye) + d[4]);
  const double zfar = infinite ? INFINITY : -(glm::dot(n[5], eye) + d[5]) / glm::dot(n[5], f);
  if (!(znear > 0.0 && zfar > znear)) return std::nullopt;
  std::array<float, 24> out{};
  for (int j = 0; j < 3; ++j) {  // view's columns: world axis j in view coordinates
    out[std::size_t(4 * j)] = float(r[j]);
    out[std::size_t(4 * j + 1)] = float(u[j]);
    out[std::size_t(4 * j + 2)] = float(f[j]);
  }
  out[12] = float(-glm::dot(r, eye));
  out[13] = float(-glm::dot(u, eye));
  out[14] = float(-glm::dot(f, eye));
  out[15] = 1.0f;
  const double frustum_out[4] = {lx, lz, by, bz}, depth[4] = {znear, zfar, lx / lz, by / bz};
  for (int k = 0; k < 4; ++k) {
    out[std::size_t(16 + k)] = float(frustum_out[k]);
    out[std::size_t(20 + k)] = float(depth[k]);
  }
  // The description's promise to a certified shader (gpu.hpp), checked on the floats it hands over
  // (the double arithmetic here errs by some 2^-50, far inside the 2^-20 of the bounds left over).
  const auto [h, k] = description_error(out, n, d, infinite);
  if (!(h <= kNormalError * (1.0 - 0x1p-20) && k <= kOffsetError * (1.0 - 0x1p-20))) return std::nullopt;
  return out;
}

std::string wrapped_source(const Shader& shader, unsigned kind_bit) {
  const Kind& kind = kind_of(kind_bit, shader.view_space);
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
                       for (char& c : u) c = char(std::toupper(static_cast<unsigned char>(c)));
                       return u;
                     }()),
                     fmt::arg("file", shader.file), fmt::arg("glsl", shader.glsl), fmt::arg("kind", kind.name),
                     fmt::arg("words", kind.words), fmt::arg("call", kind.call));
}

Method make_shader_method(MethodInfo info, const Shader& shader, std::shared_ptr<Device> device,
                          const Arithmetic& arithmetic) {
  if (info.volumes == 0) throw std::invalid_argument("shader method '" + info.name + "': no volume kinds (\"volumes\")");
  if (info.stateful) throw std::invalid_argument("shader method '" + info.name + "': a shader is not stateful");
  if (!device) device = open_device();
  const DeviceInfo& d = device->info();
  if ((arithmetic.contract || arithmetic.bounds != 0) && !(d.float64 && d.int64))
    throw std::invalid_argument(fmt::format(
        "shader method '{}': arithmetic {} is emulated in 64-bit floats and integers, which {} does not have "
        "(shaderFloat64 {}, shaderInt64 {})",
        info.name, to_string(arithmetic), d.name, d.float64 ? "yes" : "no", d.int64 ? "yes" : "no"));
  info.source += (info.source.empty() ? "" : "; ") +
                 fmt::format("run on {} ({})", d.name, d.driver_info.empty() ? d.driver_name : d.driver_name + " " + d.driver_info);
  if (!arithmetic.device_only()) {
    info.name += "@" + to_string(arithmetic);
    info.source += "; arithmetic emulated: " + to_string(arithmetic) + " (docs/gpu.md)";
  }
  if (arithmetic.half_storage == HalfStorage::outward && (info.volumes & kPointKind)) {
    info.volumes &= ~unsigned(kPointKind);
    if (info.volumes == 0)
      throw std::invalid_argument("shader method '" + info.name +
                                  "': stored half-outward it takes no volume (a point cannot grow to contain its rounding)");
    info.source += "; points not taken (a point cannot grow to contain its rounding)";
  }
  auto runner = std::make_shared<Runner>(info, shader, device, arithmetic);
  Method m(
      info, [runner](const CaseFrustum& f) -> std::unique_ptr<PreparedFrustum> { return std::make_unique<Prepared>(runner, f); },
      /*batch=*/true);
  m.on_frames([runner](const FrameRequest* frames, std::size_t n, Answer* answers) { runner->run(frames, n, answers); });
  m.on_own_timing([runner] { return runner->take_own_timing(); });
  return m;
}

}  // namespace cullproof::gpu

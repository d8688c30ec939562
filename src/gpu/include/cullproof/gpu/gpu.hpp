// cullproof::gpu: a culling shader verified on a GPU. A user's GLSL culling functions are wrapped
// in a compute shader, compiled to SPIR-V (glslang), dispatched over frames of volumes through
// Vulkan, and their verdicts read back: a Method like any other, judged by the oracle (docs/gpu.md).
//
// The functions a shader defines, one per volume kind it takes (the method's `volumes`):
//
//   uint cull_point(vec4 planes[6], vec3 p);
//   uint cull_sphere(vec4 planes[6], vec3 center, float radius);
//   uint cull_aabb(vec4 planes[6], vec3 lo, vec3 hi);
//   uint cull_obb(vec4 planes[6], vec3 center, mat3 axes, vec3 half_extents);  // axes: columns
//
// returning 0 (outside), 1 (intersecting) or 2 (inside); a two-way culler answers 1 for visible.
// planes[i] = (a, b, c, d) with a x + b y + c z + d >= 0 inside, in the order left, right, bottom,
// top, near, far, as floats (a frustum given by a clip matrix: the planes extracted from it in
// float, docs/semantics.md); not unit. The shader sees nothing else (no bindings of its own).
#pragma once

#include "cullproof/methods/methods.hpp"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace cullproof::gpu {

/// How a device treats floats in shaders, per width (16, 32, 64 bits):
/// VkPhysicalDeviceFloatControlsProperties (Vulkan 1.2), as the driver states it.
struct FloatControls {
  bool known = false;  ///< false: the device is older than Vulkan 1.2 and states nothing
  std::string denorm_independence, rounding_independence;  ///< "none", "32-bit only", "all"
  bool signed_zero_inf_nan_preserve[3]{}, denorm_preserve[3]{}, denorm_flush_to_zero[3]{};
  bool rounding_rte[3]{}, rounding_rtz[3]{};
};

/// What the device was seen to do with 32-bit floats in a compute shader, measured by a probe
/// when it is opened (the float controls leave most of it to the implementation).
struct MeasuredArithmetic {
  bool subnormal_inputs_flushed = false;   ///< 2^-140 * 1 read as 0 (denormals-are-zero)
  bool subnormal_results_flushed = false;  ///< 2^-70 * 2^-70 written as 0 (flush-to-zero)
  bool contracts = false;  ///< a * b + c, where contraction is allowed, computed with one rounding
  bool fuses_precise = false;  ///< the same with `precise` (NoContraction) fused: a driver's error
  bool fma_fused = false;      ///< GLSL fma() computed with one rounding (it need not be)
};

/// A Vulkan device: what it is and how it computes.
struct DeviceInfo {
  std::uint32_t index = 0;  ///< its place among the instance's physical devices
  std::string name;         ///< deviceName, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string type;         ///< "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
  std::string api_version;  ///< "1.3.230"
  std::string driver_name, driver_info;  ///< VkPhysicalDeviceDriverProperties (empty before 1.2)
  std::string driver_version;
  FloatControls float_controls;
  MeasuredArithmetic measured;
  bool timestamps = false;  ///< compute queues write timestamps (the device's own time is measured)
};

/// The float controls as lines "float32: subnormals preserved no, flushed no; ...".
std::string describe(const FloatControls& f);
/// The measured arithmetic as one line.
std::string describe(const MeasuredArithmetic& m);
/// One line per field of the device, then its float controls and its measured arithmetic.
std::string describe(const DeviceInfo& d);

/// Every Vulkan device the loader finds (none when there is no Vulkan driver), each opened to
/// measure its arithmetic.
std::vector<DeviceInfo> list_devices();

class Device;

/// Opens a device: `selector` empty picks the first GPU (discrete, integrated, virtual) and else
/// the first device of any type; a number picks that index; any other text the first device whose
/// name contains it (e.g. "llvmpipe", Mesa's CPU driver, lavapipe). Throws std::runtime_error
/// naming the devices there are when none matches, or when there is no Vulkan device.
std::shared_ptr<Device> open_device(const std::string& selector = "");
/// The device's description.
const DeviceInfo& info(const Device& d);

/// A culling shader: its GLSL source (the functions above), and the name to report it by in a
/// compiler message (its file).
struct Shader {
  std::string glsl;
  std::string file = "shader.glsl";
};

/// The shader as a Method with `info`'s description (claim, tolerance, volumes, three_way, ...),
/// run on `device` (open_device() when null). Each kind of info.volumes is compiled at once: a
/// compiler error throws std::invalid_argument with the compiler's messages (file and line of the
/// shader); a Vulkan failure throws std::runtime_error. The method is not stateful; it answers many frames in one dispatch per kind
/// (Method::on_frames) and reports the device's own time (Method::on_own_timing). A verdict not
/// 0, 1 or 2 throws, naming the volume. Calls from several threads take turns on the device.
Method make_shader_method(MethodInfo info, const Shader& shader, std::shared_ptr<Device> device = nullptr);

/// The compute shader that wraps `shader` for volumes of `kind_bit` (kPointKind ...): what is
/// compiled (for a reader of docs/gpu.md, and for a compiler message's context).
std::string wrapped_source(const Shader& shader, unsigned kind_bit);

}  // namespace cullproof::gpu

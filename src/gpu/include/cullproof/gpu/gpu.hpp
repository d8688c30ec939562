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

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
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
  bool float64 = false, int64 = false;  ///< shaderFloat64, shaderInt64 (the emulated arithmetic needs both)
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

/// How a shader's volumes are stored (Arithmetic::half_storage).
enum class HalfStorage {
  none,     ///< as the case gives them, 32-bit
  nearest,  ///< binary16, every float rounded to nearest even, as meshlet bounds often are ("half")
  /// binary16, rounded so that the stored volume contains the case's ("half-outward"): a box's
  /// minimum rounded down and its maximum up; a sphere's and an OBB's centre (and an OBB's axes) to
  /// the nearest finite half, the radius or half extents rounded up after growing by what that
  /// moved (for an OBB, over the least stretch of its stored axes); a bound beyond the halves' range
  /// becomes infinite where that contains the volume. A point cannot grow: it is not stored so.
  outward,
};

/// `v` as a shader reads it when stored so; std::invalid_argument for a point stored outward.
Volume stored_volume(const Volume& v, HalfStorage how);

/// Arithmetic a device may use that the device at hand need not show, emulated on it: the shader's
/// SPIR-V rewritten so that it computes as such a device would (docs/gpu.md, "Arithmetic a device
/// may use"). The default, no variant, runs the shader as the device computes it.
struct Arithmetic {
  /// Every a * b + c that SPIR-V lets a compiler contract (neither operation NoContraction, GLSL
  /// `precise`), and every dot product's sum of products, fused: rounded once, exactly (in 64-bit
  /// floats rounded to odd, then to float: Boldo and Melquiond 2008); GLSL fma() fused.
  bool contract = false;
  /// Subnormal 32-bit operands and results of every floating-point instruction flushed to zero
  /// (sign kept), as a device with DenormFlushToZero does.
  bool flush = false;
  /// -1 or +1: inversesqrt, division, and what the Vulkan specification derives from them (sqrt,
  /// length, distance, normalize) return the float farthest from the exact value, toward zero (-1)
  /// or away from it (+1), that their error bound allows; 0: as the device computes them.
  int bounds = 0;
  /// Every value decorated RelaxedPrecision (GLSL `mediump`) computed at 16 bits, as many mobile
  /// GPUs compute mediump: a relaxed instruction's float operands and result, a relaxed load's
  /// result and what is stored in a relaxed variable rounded to half precision (to nearest even,
  /// subnormal halves kept, 65520 and beyond infinite); elsewhere no change.
  bool relaxed = false;
  /// How the volume's floats are stored before the shader reads them (stored_volume); the planes
  /// stay 32-bit.
  HalfStorage half_storage = HalfStorage::none;

  bool device_only() const noexcept {
    return !contract && !flush && bounds == 0 && !relaxed && half_storage == HalfStorage::none;
  }
  friend bool operator==(const Arithmetic& a, const Arithmetic& b) {
    return a.contract == b.contract && a.flush == b.flush && a.bounds == b.bounds && a.relaxed == b.relaxed &&
           a.half_storage == b.half_storage;
  }
};

/// "device", or the variants joined by '+' ("contract+flush+bounds-low+half", "relaxed+half-outward").
std::string to_string(const Arithmetic& a);
/// The inverse of to_string; std::invalid_argument naming a word that is not a variant.
Arithmetic parse_arithmetic(const std::string& text);
/// The variants `--arithmetic all` runs: device, contract, flush, bounds-low, bounds-high, relaxed,
/// half, half-outward, and contract+flush+bounds-low (a device that fuses, flushes and is as inexact as
/// allowed).
std::vector<Arithmetic> all_arithmetic();

/// A culling shader: its GLSL source (the functions above), and the name to report it by in a
/// compiler message (its file).
///
/// With `view_space`, spheres go to the view-space form GPU-driven renderers use instead:
///
///   uint cull_sphere_view(mat4 view, vec4 frustum, vec4 depth, vec3 center, float radius);
///
/// `view` maps world space to view space (x right, y up, z the distance along the view
/// direction); in view space the left plane's inward unit normal is (frustum.x, 0, frustum.y) and
/// the bottom's (0, frustum.z, frustum.w), the right's and top's their mirror images; `depth` is
/// (near, far, P00, P11): the near and far distances along z (far may be +inf) and the projection's
/// scales, cot of half the field of view across and up (frustum.x / frustum.y, frustum.z /
/// frustum.w): a point's screen coordinates are (P00 x / z, P11 y / z). This describes a symmetric perspective frustum only: a case whose frustum is not one
/// (within 2^-16, relatively, of its float planes) is not asked, and the shader's answer for its
/// spheres is left out of its counts (the method does not apply to it).
///
/// What a certified shader may rely on: at a point x, with y = V x + t its view coordinates computed
/// exactly from the floats given (V the view's upper 3x3, t its last column), each described plane's
/// value (left: frustum.x y.x + frustum.y y.z; right: -frustum.x y.x + frustum.y y.z; bottom and top
/// likewise with y.y, frustum.z, frustum.w; near: y.z - near; far: far - y.z) differs from the
/// case's float plane's value, its normal made unit, by at most 2^-14 |y| + 2^-20 (|t|_1 + |e|) +
/// 2^-126, e being 0, -near or far; a frustum the description cannot promise this of is not
/// described.
struct Shader {
  std::string glsl;
  std::string file = "shader.glsl";
  bool view_space = false;
};

/// The view-space description of a symmetric perspective frustum (Shader::view_space), as the
/// shader receives it: 24 floats (view's columns, frustum, depth); std::nullopt when the frustum is
/// not one.
std::optional<std::array<float, 24>> view_space_frustum(const Frustum& planes);

/// The shader as a Method with `info`'s description (claim, tolerance, volumes, three_way, ...),
/// run on `device` (open_device() when null). Each kind of info.volumes is compiled at once: a
/// compiler error throws std::invalid_argument with the compiler's messages (file and line of the
/// shader); a Vulkan failure throws std::runtime_error. The method is not stateful; it answers many frames in one dispatch per kind
/// (Method::on_frames) and reports the device's own time (Method::on_own_timing). A verdict not
/// 0, 1 or 2 throws, naming the volume. Calls from several threads take turns on the device.
///
/// With an `arithmetic` other than the device's own, the method is named NAME@VARIANT (to_string)
/// and its SPIR-V is rewritten to compute so; stored half-outward, it takes no points (info.volumes
/// without kPointKind; none left throws std::invalid_argument); a variant computing in 64-bit (contract, bounds) on a
/// device without shaderFloat64 and shaderInt64 throws std::invalid_argument saying so.
Method make_shader_method(MethodInfo info, const Shader& shader, std::shared_ptr<Device> device = nullptr,
                          const Arithmetic& arithmetic = {});

/// The compute shader that wraps `shader` for volumes of `kind_bit` (kPointKind ...): what is
/// compiled (for a reader of docs/gpu.md, and for a compiler message's context).
std::string wrapped_source(const Shader& shader, unsigned kind_bit);

}  // namespace cullproof::gpu

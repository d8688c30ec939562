// The Vulkan objects behind cullproof::gpu (private): a device with one compute queue, a
// host-visible buffer, and a compute pipeline of three storage buffers (planes, volumes, verdicts)
// and a push constant (the count), dispatched in groups of kGroupSize.
#pragma once

#include "cullproof/gpu/gpu.hpp"

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace cullproof::gpu {

/// The wrapper shader's local_size_x.
constexpr std::uint32_t kGroupSize = 64;

class Device {
 public:
  explicit Device(const std::string& selector);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  const DeviceInfo& info() const noexcept { return info_; }
  VkDevice device() const noexcept { return device_; }
  VkQueue queue() const noexcept { return queue_; }
  VkCommandBuffer command() const noexcept { return command_; }
  VkFence fence() const noexcept { return fence_; }
  VkQueryPool queries() const noexcept { return queries_; }
  double timestamp_period() const noexcept { return timestamp_period_; }
  /// A memory type of `bits` with every flag of `wanted`; throws when there is none.
  std::uint32_t memory_type(std::uint32_t bits, VkMemoryPropertyFlags wanted) const;
  /// Held while the device's one command buffer and queue are in use.
  std::mutex& mutex() noexcept { return mutex_; }
  void set_measured(const MeasuredArithmetic& m) { info_.measured = m; }

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t family_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkQueryPool queries_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_{};
  double timestamp_period_ = 1.0;
  DeviceInfo info_;
  std::mutex mutex_;
};

/// A storage buffer in host-visible, coherent memory, mapped for its lifetime.
struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;
  VkDeviceSize size = 0;
  /// At least `bytes`: true when a new buffer was made (its descriptors must be written again).
  bool reserve(Device& d, VkDeviceSize bytes);
  void release(Device& d);
};

/// One compute pipeline: the wrapper of one volume kind.
class Pipeline {
 public:
  Pipeline(std::shared_ptr<Device> device, const std::vector<std::uint32_t>& spirv);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  /// Runs `count` invocations over the planes (6 vec4 per frame) and the volumes (the kind's
  /// record per volume) and reads the verdicts back; returns the device's nanoseconds (its
  /// timestamps around the dispatch, else the host's clock around submit and wait). The caller
  /// holds the device's mutex.
  double dispatch(const std::vector<float>& planes, const std::vector<std::uint32_t>& volumes, std::uint32_t count,
                  std::vector<std::uint32_t>& verdicts);

 private:
  std::shared_ptr<Device> device_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  std::array<Buffer, 3> buffers_{};
};

/// SPIR-V of a compute shader (glslang: Vulkan 1.0, SPIR-V 1.0, not optimised, so the arithmetic
/// is as written); std::invalid_argument with the compiler's messages, naming `file`.
std::vector<std::uint32_t> compile_glsl(const std::string& source, const std::string& file);

/// `spirv` rewritten to compute with `a`'s arithmetic (its half_storage aside, which is the
/// volumes' upload): inlined and put in SSA form first (SPIRV-Tools; no change to any value), then
/// each instruction the variants touch replaced by its emulation; the result validated.
/// std::logic_error when it does not validate (an instruction the rewriting does not handle).
std::vector<std::uint32_t> emulate_arithmetic(const std::vector<std::uint32_t>& spirv, const Arithmetic& a);

/// x rounded to binary16, to nearest even (overflow to infinity), and back: exact.
float round_to_half(float x);
/// x rounded to binary16 and back: to nearest even (`direction` 0), down (-1) or up (+1); beyond the
/// largest half, 65504, infinity when the rounding goes that way, else 65504; infinities and NaN
/// unchanged.
double round_to_half(double x, int direction);

/// The head of a compute shader over a Pipeline's buffers read as floats in and words out:
/// `#version 450`, `local_size` invocations a group, `x[]` (floats in), `y[]` (words out), `count`
/// (the push constant); the frames' buffer, unused, as `unused[]`.
std::string float_kernel_head(std::uint32_t local_size);

/// Runs the arithmetic probe on `device` (MeasuredArithmetic).
MeasuredArithmetic probe_arithmetic(const std::shared_ptr<Device>& device);

}  // namespace cullproof::gpu

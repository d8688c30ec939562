// The Vulkan side of cullproof::gpu: devices listed and opened, their float controls read, and a
// compute pipeline per volume kind dispatched over host-visible buffers (vulkan.hpp).
#include "vulkan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <stdexcept>

namespace cullproof::gpu {

namespace {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(fmt::format("Vulkan: {} failed (VkResult {})", what, int(r)));
}

std::string version_text(std::uint32_t v) {
  return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

const char* type_text(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

const char* independence_text(VkShaderFloatControlsIndependence i) {
  switch (i) {
    case VK_SHADER_FLOAT_CONTROLS_INDEPENDENCE_32_BIT_ONLY: return "32-bit only";
    case VK_SHADER_FLOAT_CONTROLS_INDEPENDENCE_ALL: return "all";
    default: return "none";
  }
}

// The compute queue family of a physical device, or -1.
int compute_family(VkPhysicalDevice p, bool* timestamps = nullptr) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(p, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(p, &n, families.data());
  for (std::uint32_t i = 0; i < n; ++i)
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      if (timestamps) *timestamps = families[i].timestampValidBits > 0;
      return int(i);
    }
  return -1;
}

DeviceInfo describe_device(VkPhysicalDevice p, std::uint32_t index, double* timestamp_period) {
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(p, &props);
  DeviceInfo d;
  d.index = index;
  d.name = props.deviceName;
  d.type = type_text(props.deviceType);
  d.api_version = version_text(props.apiVersion);
  d.driver_version = std::to_string(props.driverVersion);
  bool queue_timestamps = false;
  compute_family(p, &queue_timestamps);
  d.timestamps = queue_timestamps && props.limits.timestampComputeAndGraphics;
  VkPhysicalDeviceFeatures features{};
  vkGetPhysicalDeviceFeatures(p, &features);
  d.float64 = features.shaderFloat64;
  d.int64 = features.shaderInt64;
  if (timestamp_period) *timestamp_period = double(props.limits.timestampPeriod);
  if (VK_API_VERSION_MINOR(props.apiVersion) >= 2 || VK_API_VERSION_MAJOR(props.apiVersion) > 1) {
    VkPhysicalDeviceVulkan12Properties v12{};
    v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_PROPERTIES;
    VkPhysicalDeviceProperties2 p2{};
    p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    p2.pNext = &v12;
    vkGetPhysicalDeviceProperties2(p, &p2);
    d.driver_name = v12.driverName;
    d.driver_info = v12.driverInfo;
    FloatControls& f = d.float_controls;
    f.known = true;
    f.denorm_independence = independence_text(v12.denormBehaviorIndependence);
    f.rounding_independence = independence_text(v12.roundingModeIndependence);
    const VkBool32 szin[3] = {v12.shaderSignedZeroInfNanPreserveFloat16, v12.shaderSignedZeroInfNanPreserveFloat32,
                              v12.shaderSignedZeroInfNanPreserveFloat64};
    const VkBool32 dp[3] = {v12.shaderDenormPreserveFloat16, v12.shaderDenormPreserveFloat32, v12.shaderDenormPreserveFloat64};
    const VkBool32 ftz[3] = {v12.shaderDenormFlushToZeroFloat16, v12.shaderDenormFlushToZeroFloat32,
                             v12.shaderDenormFlushToZeroFloat64};
    const VkBool32 rte[3] = {v12.shaderRoundingModeRTEFloat16, v12.shaderRoundingModeRTEFloat32,
                             v12.shaderRoundingModeRTEFloat64};
    const VkBool32 rtz[3] = {v12.shaderRoundingModeRTZFloat16, v12.shaderRoundingModeRTZFloat32,
                             v12.shaderRoundingModeRTZFloat64};
    for (int w = 0; w < 3; ++w) {
      f.signed_zero_inf_nan_preserve[w] = szin[w];
      f.denorm_preserve[w] = dp[w];
      f.denorm_flush_to_zero[w] = ftz[w];
      f.rounding_rte[w] = rte[w];
      f.rounding_rtz[w] = rtz[w];
    }
  }
  return d;
}

// A Vulkan instance of API version 1.2 without layers or extensions.
VkInstance make_instance() {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "cullproof";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ci{};
  ci.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ci.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult r = vkCreateInstance(&ci, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
    throw std::runtime_error(
        "no Vulkan driver: install one (Debian: mesa-vulkan-drivers, whose lavapipe runs on the CPU) or a GPU's");
  check(r, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  std::uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> out(n);
  check(vkEnumeratePhysicalDevices(instance, &n, out.data()), "vkEnumeratePhysicalDevices");
  out.resize(n);
  return out;
}

}  // namespace

std::string describe(const FloatControls& f) {
  if (!f.known) return "float controls: not stated (device older than Vulkan 1.2)\n";
  const char* yes[2] = {"no", "yes"};
  std::string s = fmt::format("float controls: subnormal behaviour set per width: {}; rounding mode set per width: {}\n",
                              f.denorm_independence, f.rounding_independence);
  const int widths[3] = {16, 32, 64};
  for (int w = 0; w < 3; ++w)
    s += fmt::format(
        "  float{}: subnormals preserved {}, flushed to zero {}; signed zero, inf and NaN preserved {}; "
        "rounding to nearest even {}, toward zero {}\n",
        widths[w], yes[f.denorm_preserve[w]], yes[f.denorm_flush_to_zero[w]], yes[f.signed_zero_inf_nan_preserve[w]],
        yes[f.rounding_rte[w]], yes[f.rounding_rtz[w]]);
  return s;
}

std::string describe(const MeasuredArithmetic& m) {
  const char* yes[2] = {"no", "yes"};
  return fmt::format(
      "measured (float32, a probe shader): subnormal inputs read as zero {}, subnormal results flushed to zero {}; "
      "a * b + c fused where allowed {}, fused though precise {}; fma() fused {}\n",
      yes[m.subnormal_inputs_flushed], yes[m.subnormal_results_flushed], yes[m.contracts], yes[m.fuses_precise],
      yes[m.fma_fused]);
}

std::string describe(const DeviceInfo& d) {
  return fmt::format("device {}: {} ({}), Vulkan {}, driver {} ({}), timestamps {}, 64-bit floats {}, 64-bit integers {}\n",
                     d.index, d.name, d.type, d.api_version, d.driver_name.empty() ? std::string("unnamed") : d.driver_name,
                     d.driver_info.empty() ? "version " + d.driver_version : d.driver_info, d.timestamps ? "yes" : "no",
                     d.float64 ? "yes" : "no", d.int64 ? "yes" : "no") +
         describe(d.float_controls) + describe(d.measured);
}

std::vector<DeviceInfo> list_devices() {
  VkInstance instance = VK_NULL_HANDLE;
  try {
    instance = make_instance();
  } catch (const std::runtime_error&) {
    return {};
  }
  std::vector<DeviceInfo> out;
  const auto devices = physical_devices(instance);
  for (std::uint32_t i = 0; i < devices.size(); ++i) out.push_back(describe_device(devices[i], i, nullptr));
  vkDestroyInstance(instance, nullptr);
  for (DeviceInfo& d : out)
    try {
      d.measured = open_device(std::to_string(d.index))->info().measured;
    } catch (const std::runtime_error&) {  // no compute queue: nothing measured
    }
  return out;
}

// ---- Device

Device::Device(const std::string& selector) {
  instance_ = make_instance();
  const auto devices = physical_devices(instance_);
  std::vector<DeviceInfo> infos;
  for (std::uint32_t i = 0; i < devices.size(); ++i) infos.push_back(describe_device(devices[i], i, nullptr));
  int chosen = -1;
  const bool numeric = !selector.empty() && std::all_of(selector.begin(), selector.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  if (selector.empty()) {
    for (const DeviceInfo& d : infos)
      if (chosen < 0 && d.type != "CPU" && d.type != "other" && compute_family(devices[d.index]) >= 0) chosen = int(d.index);
    for (const DeviceInfo& d : infos)
      if (chosen < 0 && compute_family(devices[d.index]) >= 0) chosen = int(d.index);
  } else if (numeric) {
    const unsigned long i = std::stoul(selector);
    if (i < infos.size()) chosen = int(i);
  } else {
    for (const DeviceInfo& d : infos)
      if (chosen < 0 && d.name.find(selector) != std::string::npos) chosen = int(d.index);
  }
  if (chosen < 0) {
    std::string there;
    for (const DeviceInfo& d : infos) there += fmt::format("{}{}: {}", there.empty() ? "" : "; ", d.index, d.name);
    vkDestroyInstance(instance_, nullptr);
    throw std::runtime_error(fmt::format("no Vulkan device {}{} (there are: {})",
                                         selector.empty() ? std::string("with a compute queue") : "'" + selector + "'",
                                         selector.empty() ? "" : " with a compute queue",
                                         there.empty() ? std::string("none") : there));
  }
  physical_ = devices[std::size_t(chosen)];
  info_ = describe_device(physical_, std::uint32_t(chosen), &timestamp_period_);
  const int family = compute_family(physical_);
  if (family < 0) throw std::runtime_error("Vulkan device '" + info_.name + "' has no compute queue");
  family_ = std::uint32_t(family);
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo q{};
  q.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  q.queueFamilyIndex = family_;
  q.queueCount = 1;
  q.pQueuePriorities = &priority;
  // 64-bit floats and integers where the device has them: the emulated arithmetic (arithmetic.cpp)
  // computes in them.
  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = info_.float64;
  features.shaderInt64 = info_.int64;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &q;
  dci.pEnabledFeatures = &features;
  check(vkCreateDevice(physical_, &dci, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, family_, 0, &queue_);

  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = family_;
  check(vkCreateCommandPool(device_, &pci, nullptr, &pool_), "vkCreateCommandPool");
  VkCommandBufferAllocateInfo cai{};
  cai.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
  cai.commandPool = pool_;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(device_, &cai, &command_), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
  check(vkCreateFence(device_, &fci, nullptr, &fence_), "vkCreateFence");
  if (info_.timestamps) {
    VkQueryPoolCreateInfo qci{};
    qci.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = 2;
    check(vkCreateQueryPool(device_, &qci, nullptr, &queries_), "vkCreateQueryPool");
  }
}

Device::~Device() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    if (queries_) vkDestroyQueryPool(device_, queries_, nullptr);
    vkDestroyFence(device_, fence_, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

std::uint32_t Device::memory_type(std::uint32_t bits, VkMemoryPropertyFlags wanted) const {
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
  throw std::runtime_error("Vulkan device '" + info_.name + "' has no host-visible, coherent memory for a buffer");
}

std::shared_ptr<Device> open_device(const std::string& selector) {
  auto d = std::make_shared<Device>(selector);
  d->set_measured(probe_arithmetic(d));
  return d;
}

const DeviceInfo& info(const Device& d) { return d.info(); }

// ---- Buffer

bool Buffer::reserve(Device& d, VkDeviceSize bytes) {
  if (bytes <= size) return false;
  release(d);
  bytes = std::max<VkDeviceSize>(bytes, 256);
  VkBufferCreateInfo bci{};
  bci.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  bci.size = bytes;
  bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(d.device(), &bci, nullptr, &buffer), "vkCreateBuffer");
  VkMemoryRequirements req{};
  vkGetBufferMemoryRequirements(d.device(), buffer, &req);
  VkMemoryAllocateInfo mai{};
  mai.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = d.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
  check(vkAllocateMemory(d.device(), &mai, nullptr, &memory), "vkAllocateMemory");
  check(vkBindBufferMemory(d.device(), buffer, memory, 0), "vkBindBufferMemory");
  check(vkMapMemory(d.device(), memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
  size = bytes;
  return true;
}

void Buffer::release(Device& d) {
  if (buffer) vkDestroyBuffer(d.device(), buffer, nullptr);
  if (memory) vkFreeMemory(d.device(), memory, nullptr);  // unmaps
  buffer = VK_NULL_HANDLE;
  memory = VK_NULL_HANDLE;
  mapped = nullptr;
  size = 0;
}

// ---- Pipeline

Pipeline::Pipeline(std::shared_ptr<Device> device, const std::vector<std::uint32_t>& spirv) : device_(std::move(device)) {
  VkDevice dev = device_->device();
  VkDescriptorSetLayoutBinding b[3]{};
  for (std::uint32_t i = 0; i < 3; ++i) {
    b[i].binding = i;
    b[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    b[i].descriptorCount = 1;
    b[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
  }
  VkDescriptorSetLayoutCreateInfo lci{};
  lci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  lci.bindingCount = 3;
  lci.pBindings = b;
  check(vkCreateDescriptorSetLayout(dev, &lci, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(std::uint32_t)};
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout_;
  plci.pushConstantRangeCount = 1;
  plci.pPushConstantRanges = &push;
  check(vkCreatePipelineLayout(dev, &plci, nullptr, &layout_), "vkCreatePipelineLayout");
  VkShaderModuleCreateInfo sci{};
  sci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  sci.codeSize = spirv.size() * sizeof(std::uint32_t);
  sci.pCode = spirv.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(dev, &sci, nullptr, &module), "vkCreateShaderModule");
  VkComputePipelineCreateInfo cci{};
  cci.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  cci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  cci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cci.stage.module = module;
  cci.stage.pName = "main";
  cci.layout = layout_;
  const VkResult r = vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cci, nullptr, &pipeline_);
  vkDestroyShaderModule(dev, module, nullptr);
  check(r, "vkCreateComputePipelines");
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3};
  VkDescriptorPoolCreateInfo dpci{};
  dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpci.maxSets = 1;
  dpci.poolSizeCount = 1;
  dpci.pPoolSizes = &size;
  check(vkCreateDescriptorPool(dev, &dpci, nullptr, &pool_), "vkCreateDescriptorPool");
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = pool_;
  dsai.descriptorSetCount = 1;
  dsai.pSetLayouts = &set_layout_;
  check(vkAllocateDescriptorSets(dev, &dsai, &set_), "vkAllocateDescriptorSets");
}

Pipeline::~Pipeline() {
  VkDevice dev = device_->device();
  vkDeviceWaitIdle(dev);
  for (Buffer& b : buffers_) b.release(*device_);
  vkDestroyDescriptorPool(dev, pool_, nullptr);
  vkDestroyPipeline(dev, pipeline_, nullptr);
  vkDestroyPipelineLayout(dev, layout_, nullptr);
  vkDestroyDescriptorSetLayout(dev, set_layout_, nullptr);
}

double Pipeline::dispatch(const std::vector<float>& planes, const std::vector<std::uint32_t>& volumes, std::uint32_t count,
                          std::vector<std::uint32_t>& verdicts) {
  verdicts.assign(count, 0);
  if (count == 0) return 0.0;
  Device& d = *device_;
  const VkDeviceSize sizes[3] = {planes.size() * sizeof(float), volumes.size() * sizeof(std::uint32_t), count * sizeof(std::uint32_t)};
  // A new buffer may have the handle of the one it replaces: whether one was made is what counts.
  bool rebind = false;
  for (int i = 0; i < 3; ++i) rebind = buffers_[i].reserve(d, sizes[i]) || rebind;
  if (rebind) {
    VkDescriptorBufferInfo bi[3]{};
    VkWriteDescriptorSet w[3]{};
    for (std::uint32_t i = 0; i < 3; ++i) {
      bi[i] = {buffers_[i].buffer, 0, VK_WHOLE_SIZE};
      w[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      w[i].dstSet = set_;
      w[i].dstBinding = i;
      w[i].descriptorCount = 1;
      w[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      w[i].pBufferInfo = &bi[i];
    }
    vkUpdateDescriptorSets(d.device(), 3, w, 0, nullptr);
  }
  std::memcpy(buffers_[0].mapped, planes.data(), std::size_t(sizes[0]));
  std::memcpy(buffers_[1].mapped, volumes.data(), std::size_t(sizes[1]));

  VkCommandBuffer cmd = d.command();
  check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo bbi{};
  bbi.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  bbi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &bbi), "vkBeginCommandBuffer");
  if (d.queries()) {
    vkCmdResetQueryPool(cmd, d.queries(), 0, 2);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, d.queries(), 0);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set_, 0, nullptr);
  vkCmdPushConstants(cmd, layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(count), &count);
  vkCmdDispatch(cmd, (count + kGroupSize - 1) / kGroupSize, 1, 1);
  if (d.queries()) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, d.queries(), 1);
  // The shader's writes made visible to the host's reads of the mapped memory.
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0,
                       nullptr);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo si{};
  si.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  const auto t0 = std::chrono::steady_clock::now();
  check(vkQueueSubmit(d.queue(), 1, &si, d.fence()), "vkQueueSubmit");
  const VkFence fence = d.fence();
  check(vkWaitForFences(d.device(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  const auto t1 = std::chrono::steady_clock::now();
  check(vkResetFences(d.device(), 1, &fence), "vkResetFences");
  std::memcpy(verdicts.data(), buffers_[2].mapped, std::size_t(sizes[2]));
  if (d.queries()) {
    std::uint64_t stamps[2] = {0, 0};
    if (vkGetQueryPoolResults(d.device(), d.queries(), 0, 2, sizeof(stamps), stamps, sizeof(std::uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS &&
        stamps[1] >= stamps[0])
      return double(stamps[1] - stamps[0]) * d.timestamp_period();
  }
  return double(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count());
}

}  // namespace cullproof::gpu

// `cullproof devices`: the Vulkan devices a shader can run on (--device), each with its float
// controls.
#include "commands.hpp"

#include "cullproof/gpu/gpu.hpp"

#include <cstdio>

namespace cullproof::app {

nlohmann::json device_json(const gpu::DeviceInfo& d) {
  nlohmann::json j{{"index", d.index},           {"name", d.name},
                   {"type", d.type},             {"api_version", d.api_version},
                   {"driver_name", d.driver_name}, {"driver_info", d.driver_info},
                   {"driver_version", d.driver_version}, {"timestamps", d.timestamps},
                   {"float64", d.float64},       {"int64", d.int64}};
  const gpu::FloatControls& f = d.float_controls;
  nlohmann::json fc{{"known", f.known}};
  if (f.known) {
    fc["denorm_behavior_independence"] = f.denorm_independence;
    fc["rounding_mode_independence"] = f.rounding_independence;
    const char* widths[3] = {"float16", "float32", "float64"};
    for (int w = 0; w < 3; ++w)
      fc[widths[w]] = {{"signed_zero_inf_nan_preserve", f.signed_zero_inf_nan_preserve[w]},
                       {"denorm_preserve", f.denorm_preserve[w]},
                       {"denorm_flush_to_zero", f.denorm_flush_to_zero[w]},
                       {"rounding_rte", f.rounding_rte[w]},
                       {"rounding_rtz", f.rounding_rtz[w]}};
  }
  j["float_controls"] = fc;
  const gpu::MeasuredArithmetic& m = d.measured;
  j["measured_float32"] = {{"subnormal_inputs_flushed", m.subnormal_inputs_flushed},
                           {"subnormal_results_flushed", m.subnormal_results_flushed},
                           {"contracts", m.contracts},
                           {"fuses_precise", m.fuses_precise},
                           {"fma_fused", m.fma_fused}};
  return j;
}

void add_devices(CLI::App& app, DevicesCommand& c) {
  c.cmd = app.add_subcommand("devices", "List the Vulkan devices a culling shader can run on (--device), with their float controls");
  c.cmd->add_flag("--json", c.json, "Print them as JSON (an array), as a run's JSON records the device of its shaders");
}

int run_devices_command(const DevicesCommand& c) {
  const std::vector<gpu::DeviceInfo> devices = gpu::list_devices();
  if (c.json) {
    nlohmann::json out = nlohmann::json::array();
    for (const gpu::DeviceInfo& d : devices) out.push_back(device_json(d));
    std::printf("%s\n", out.dump(2).c_str());
    return devices.empty() ? 1 : 0;
  }
  if (devices.empty()) {
    std::printf("no Vulkan device (install a driver: Debian's mesa-vulkan-drivers has lavapipe, on the CPU)\n");
    return 1;
  }
  for (const gpu::DeviceInfo& d : devices) std::printf("%s", gpu::describe(d).c_str());
  return 0;
}

}  // namespace cullproof::app

// `cullproof devices`: the Vulkan devices a shader can run on (--device), each with its float
// controls.
#include "commands.hpp"

#include "cullproof/gpu/gpu.hpp"

#include <cstdio>

namespace cullproof::app {

void add_devices(CLI::App& app, DevicesCommand& c) {
  c.cmd = app.add_subcommand("devices", "List the Vulkan devices a culling shader can run on (--device), with their float controls");
}

int run_devices_command(const DevicesCommand&) {
  const std::vector<gpu::DeviceInfo> devices = gpu::list_devices();
  if (devices.empty()) {
    std::printf("no Vulkan device (install a driver: Debian's mesa-vulkan-drivers has lavapipe, on the CPU)\n");
    return 1;
  }
  for (const gpu::DeviceInfo& d : devices) std::printf("%s", gpu::describe(d).c_str());
  return 0;
}

}  // namespace cullproof::app

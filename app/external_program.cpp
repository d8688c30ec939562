// The program under test through the process protocol (docs/protocol.md), for classify, verify
// and corpus replay alike: its options, and the methods of a run.
#include "commands.hpp"

#include "cullproof/protocol/external.hpp"
#include "cullproof/protocol/protocol.hpp"
#ifdef CULLPROOF_HAVE_GPU
#include "cullproof/gpu/gpu.hpp"
#endif

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace cullproof::app {

namespace {

constexpr int kMaxExternalTimeoutMs = 3600000;  ///< an hour for one answer of an external program

}  // namespace

void ExternalProgram::add_options(CLI::App* cmd) {
  cmd->add_option("--external", names,
                  "Run method NAME of the program given after '--' (the process protocol, docs/protocol.md; "
                  "repeatable, 'all': every method it offers); --method adds built-in ones beside it");
  cmd->add_option("--external-timeout", timeout_ms, "Milliseconds to wait for each answer of the program")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxExternalTimeoutMs));
  cmd->add_option("--external-handshake-timeout", handshake_timeout_ms,
                  "Milliseconds to wait for the program's handshake (when it starts, and when it is started again "
                  "after a fault)")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxExternalTimeoutMs));
  cmd->add_option("--external-jobs", jobs,
                  "Copies of the program to run side by side, asked by whichever thread is free (stateful "
                  "methods always through the first)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_option("--shader", shaders,
                  "Run the culling shader FILE describes (a method's description with \"shader\": its GLSL file; "
                  "docs/gpu.md) on a Vulkan device (repeatable)");
  cmd->add_option("--device", device,
                  "The Vulkan device of --shader: an index or a part of its name (default: the first GPU, else the "
                  "first device; 'cullproof devices' lists them); repeatable, or 'all': each shader runs on each "
                  "device, its name followed by #INDEX");
  cmd->add_option("--arithmetic", arithmetic,
                  "Run each --shader under these arithmetic variants, emulated on the device (comma-separated: device, "
                  "or contract, flush, bounds-low, bounds-high, relaxed, half or half-outward joined by '+'; 'all': "
                  "device, each alone, and contract+flush+bounds-low; docs/gpu.md); default: device")
      ->delimiter(',');
}

namespace {

// The entries of `offered` named by `names` ('all': every one), each once, in the order named,
// then those of `builtin`; std::invalid_argument naming a name the program does not offer.
template <class T>
std::vector<T> chosen(const std::vector<T>& offered, const std::vector<std::string>& names, std::vector<T> builtin,
                      const std::string& kind) {
  std::string on_offer;
  for (const T& x : offered) on_offer += (on_offer.empty() ? "" : ", ") + x.name;
  std::vector<T> out;
  for (const std::string& wanted : names) {
    bool found = false;
    for (const T& x : offered)
      if (wanted == "all" || x.name == wanted) {
        found = true;
        if (std::none_of(out.begin(), out.end(), [&](const T& o) { return o.name == x.name; })) out.push_back(x);
      }
    if (!found)
      throw std::invalid_argument("the program offers no " + kind + " named '" + wanted + "' (it offers: " +
                                  (on_offer.empty() ? std::string("none") : on_offer) + ")");
  }
  for (T& b : builtin) out.push_back(std::move(b));
  return out;
}

// The program's options, or nullopt when no program is named; std::invalid_argument for a program
// without --external or the reverse.
std::optional<ExternalOptions> options_of(const ExternalProgram& p, int instances) {
  if (p.names.empty()) {
    if (!p.command.empty()) throw std::invalid_argument("a program after '--' needs --external NAME");
    return std::nullopt;
  }
  if (p.command.empty()) throw std::invalid_argument("--external " + p.names[0] + " needs the program after '--'");
  ExternalOptions eo;
  eo.command = p.command;
  eo.timeout = std::chrono::milliseconds(p.timeout_ms);
  eo.handshake_timeout = std::chrono::milliseconds(p.handshake_timeout_ms);
  eo.instances = instances;
  return eo;
}

}  // namespace

namespace {

std::string read_text(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::invalid_argument("cannot read " + what + " " + file.string());
  std::ostringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) throw std::invalid_argument("cannot read " + what + " " + file.string());
  return text.str();
}

#ifdef CULLPROOF_HAVE_GPU
// The devices --device names ('all': every one), each opened once; two selectors that open one
// device are refused, naming both.
std::vector<std::pair<std::string, std::shared_ptr<gpu::Device>>> open_devices(const std::vector<std::string>& selectors) {
  std::vector<std::string> chosen;
  for (const std::string& s : selectors.empty() ? std::vector<std::string>{""} : selectors) {
    if (s != "all") {
      chosen.push_back(s);
      continue;
    }
    const std::vector<gpu::DeviceInfo> every = gpu::list_devices();
    if (every.empty()) throw std::invalid_argument("--device all: there is no Vulkan device");
    for (const gpu::DeviceInfo& d : every) chosen.push_back(std::to_string(d.index));
  }
  std::vector<std::pair<std::string, std::shared_ptr<gpu::Device>>> out;
  for (const std::string& s : chosen) {
    std::shared_ptr<gpu::Device> d = gpu::open_device(s);
    for (const auto& [other, o] : out)
      if (gpu::info(*o).index == gpu::info(*d).index)
        throw std::invalid_argument("--device '" + other + "' and --device '" + s + "' name one device, " +
                                    std::to_string(gpu::info(*d).index) + " (" + gpu::info(*d).name + ")");
    out.emplace_back(s, std::move(d));
  }
  return out;
}
#endif

// The shaders of --shader on the devices of --device, each described by a JSON file whose "shader"
// names its GLSL file (relative to the description's folder). Every description is read before
// a device is opened; a description or shader that cannot be read, or is not valid, throws
// std::invalid_argument naming its file.
std::vector<Method> shader_methods(const std::vector<std::string>& files, const std::vector<std::string>& device,
                                   const std::vector<std::string>& arithmetic, nlohmann::json& devices) {
  if (files.empty()) {
    if (!arithmetic.empty()) throw std::invalid_argument("--arithmetic applies to the shaders of --shader, and none is named");
    return {};
  }
#ifdef CULLPROOF_HAVE_GPU
  std::vector<gpu::Arithmetic> variants;
  for (const std::string& a : arithmetic)
    for (const gpu::Arithmetic& v : a == "all" ? gpu::all_arithmetic() : std::vector<gpu::Arithmetic>{gpu::parse_arithmetic(a)})
      if (std::find(variants.begin(), variants.end(), v) == variants.end()) variants.push_back(v);
  if (variants.empty()) variants.emplace_back();
  std::vector<std::pair<MethodInfo, gpu::Shader>> shaders;
  for (const std::string& file : files) {
    const std::string where = "shader description " + file;
    protocol::MethodDescription m;
    try {
      m = protocol::parse_method_description(read_text(file, "the shader description"), where, {"shader", "spheres"});
    } catch (const std::runtime_error& e) {
      throw std::invalid_argument(e.what());
    }
    std::string glsl_file, spheres = "planes";
    for (const auto& [key, value] : m.strings) {
      if (key == "shader") glsl_file = value;
      if (key == "spheres") spheres = value;
    }
    if (glsl_file.empty()) throw std::invalid_argument(where + ": no \"shader\" (its GLSL file)");
    if (spheres != "planes" && spheres != "view-space")
      throw std::invalid_argument(where + ": \"spheres\" is '" + spheres +
                                  "': 'planes' (cull_sphere, the default) or 'view-space' (cull_sphere_view)");
    const std::filesystem::path glsl_path = std::filesystem::path(file).parent_path() / glsl_file;
    shaders.push_back({m.info, {read_text(glsl_path, "the shader"), glsl_path.string(), spheres == "view-space"}});
  }
  const auto opened = open_devices(device);
  for (const auto& [selector, d] : opened) {
    std::printf("%s", gpu::describe(gpu::info(*d)).c_str());
    devices.push_back(device_json(gpu::info(*d)));
  }
  // With more than one device a method's name says which it ran on (#INDEX), and so does its
  // reproduce line; with one, both are as the command line gave them.
  std::vector<Method> out;
  for (std::size_t i = 0; i < shaders.size(); ++i)
    for (const auto& [selector, d] : opened)
      for (const gpu::Arithmetic& v : variants) {
        MethodInfo info = shaders[i].first;
        std::string chosen = selector;
        if (opened.size() > 1) {
          chosen = std::to_string(gpu::info(*d).index);
          info.name += "#" + chosen;
        }
        Method method = gpu::make_shader_method(info, shaders[i].second, d, v);
        method.reproduce = "--shader " + files[i] + (chosen.empty() ? std::string() : " --device '" + chosen + "'") +
                           (v.device_only() ? std::string() : " --arithmetic " + gpu::to_string(v));
        out.push_back(std::move(method));
      }
  return out;
#else
  (void)device;
  (void)arithmetic;
  (void)devices;
  throw std::invalid_argument("--shader " + files[0] + ": this cullproof is built without the GPU library (Vulkan, glslang)");
#endif
}

}  // namespace

std::vector<Method> ExternalProgram::methods(const std::vector<std::string>& builtin, int instances) const {
  const auto eo = options_of(*this, instances);
  std::vector<Method> out;
  if (eo) out = chosen(external_methods(*eo), names, {}, "method");
  devices = nlohmann::json::array();
  for (Method& m : shader_methods(shaders, device, arithmetic, devices)) out.push_back(std::move(m));
  if (out.empty()) return builtin_methods(builtin);
  if (!builtin.empty())
    for (Method& b : builtin_methods(builtin)) out.push_back(std::move(b));
  return out;
}

std::vector<System> ExternalProgram::systems(const std::vector<std::string>& builtin) const {
  const auto eo = options_of(*this, 1);
  if (!eo) return builtin_systems(builtin);
  return chosen(external_systems(*eo), names, builtin.empty() ? std::vector<System>{} : builtin_systems(builtin), "system");
}

}  // namespace cullproof::app

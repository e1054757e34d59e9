// Backend selection. Built with and without CUTWORK_WITH_VULKAN (host/CMakeLists.txt keeps this
// one file of host/vulkan when Vulkan is off), so the CLI and the library never need #ifdefs.
#include "host/vulkan/backend.h"

#include <tbb/info.h>
#include <tbb/version.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <ostream>

#include "host/core/error.h"

#if CUTWORK_WITH_VULKAN
#include "host/vulkan/context.h"
#endif

namespace cutwork {
namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) {
        std::string name = line.substr(colon + 1);
        name.erase(0, name.find_first_not_of(" \t"));
        return name;
      }
    }
  }
  return "CPU";
}

}  // namespace

DeviceRequest parse_device_request(std::string_view text) {
  std::string s(text);
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (s == "cpu") return DeviceRequest::Cpu;
  if (s == "vulkan") return DeviceRequest::Vulkan;
  if (s == "auto") return DeviceRequest::Auto;
  throw InputError("unknown device '" + std::string(text) + "': expected cpu, vulkan or auto");
}

std::string_view to_string(DeviceRequest request) {
  switch (request) {
    case DeviceRequest::Cpu:
      return "cpu";
    case DeviceRequest::Vulkan:
      return "vulkan";
    case DeviceRequest::Auto:
      return "auto";
  }
  return "auto";
}

bool vulkan_compiled_in() {
#if CUTWORK_WITH_VULKAN
  return true;
#else
  return false;
#endif
}

ComputeBackend cpu_backend() {
  ComputeBackend b;
  b.kind = ComputeBackend::Kind::Cpu;
  b.name = cpu_model() + " (" + std::to_string(tbb::info::default_concurrency()) + " threads)";
  b.driver =
      "oneTBB " + std::to_string(TBB_VERSION_MAJOR) + "." + std::to_string(TBB_VERSION_MINOR);
  return b;
}

bool auto_takes_vulkan_device(std::string_view device_type, bool explicitly_selected) {
  if (explicitly_selected) return true;
  return device_type == "discrete GPU" || device_type == "integrated GPU" || device_type == "virtual GPU";
}

ComputeBackend select_compute_backend(DeviceRequest request, std::ostream* warnings) {
  if (request == DeviceRequest::Cpu) {
    ComputeBackend b = cpu_backend();
    b.reason = "--device cpu";
    return b;
  }
  std::string why;
#if CUTWORK_WITH_VULKAN
  try {
    vulkan::ContextOptions options = vulkan::ContextOptions::from_environment();
    options.require_float64 = true;
    const bool selected = !options.device.empty();
    if (request == DeviceRequest::Auto) {
      // Ask which device it would be before building one: a CPU implementation is never taken.
      const vulkan::PhysicalDeviceInfo probed = vulkan::Context::probe(options);
      const std::string type(vulkan::to_string(probed.type));
      if (!auto_takes_vulkan_device(type, selected)) {
        // Not a failure: a machine without a GPU runs the kernels on the TBB twins.
        ComputeBackend b = cpu_backend();
        b.reason = "--device auto: no GPU; the best Vulkan device, " + probed.name + ", is a " + type +
                   " implementation, slower than the TBB kernels (--device vulkan uses it)";
        return b;
      }
    }
    auto context = std::make_shared<vulkan::Context>(options);  // the probed device, now built
    const vulkan::PhysicalDeviceInfo& info = context->info();
    const std::string type(vulkan::to_string(info.type));
    ComputeBackend b;
    b.kind = ComputeBackend::Kind::Vulkan;
    b.name = info.name;
    b.driver = info.driver;
    b.reason = request == DeviceRequest::Vulkan ? "--device vulkan"
               : selected ? "--device auto: CUTWORK_VK_DEVICE=" + options.device + " selects " + type + " " + info.name
                          : "--device auto: " + type + " " + info.name;
    b.context = std::move(context);
    return b;
  } catch (const DeviceError& e) {
    if (request == DeviceRequest::Vulkan) throw;
    why = e.what();
  }
#else
  why = "this cutwork was built without Vulkan (CUTWORK_WITH_VULKAN=OFF)";
  if (request == DeviceRequest::Vulkan) throw DeviceError("--device vulkan: " + why);
#endif
  ComputeBackend b = cpu_backend();
  b.fallback_reason = why;
  b.reason = "--device auto: no usable Vulkan device (" + why + ")";
  if (warnings != nullptr) {
    *warnings << "cutwork: warning: no usable Vulkan device, running the kernels on the CPU ("
              << why << ")\n";
  }
  return b;
}

}  // namespace cutwork

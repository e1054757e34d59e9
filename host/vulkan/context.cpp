#include "host/vulkan/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#ifdef CUTWORK_SANITIZE
#include <dlfcn.h>
#include <link.h>
#endif

#include "host/core/error.h"
#include "host/vulkan/vk_check.h"

#ifdef CUTWORK_SANITIZE
// Sanitizer builds only (CMake option CUTWORK_SANITIZE). The Vulkan loader, the driver (Mesa's
// lavapipe and the LLVM it JIT-compiles with) and the validation layer keep allocations until
// exit; they are not cutwork's, so LeakSanitizer is told to ignore them, by library and nothing
// else. One definition for every executable that links the Vulkan context (cutwork and the tests).
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libvulkan.so\nleak:libvulkan_lvp.so\nleak:libLLVM\nleak:libVkLayer_khronos_validation.so\n";
}
#endif

namespace cutwork::vulkan {
namespace {

#ifdef CUTWORK_SANITIZE
/// Keeps the loaded Vulkan loader, driver, layers and LLVM mapped until exit (RTLD_NODELETE). The
/// loader unloads the driver and layers at vkDestroyInstance; LeakSanitizer could then only name
/// their leftovers "<unknown module>" and the suppressions above would not apply.
void keep_vulkan_libraries_mapped() {
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) -> int {
        const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        for (const char* key : {"vulkan", "VkLayer", "LLVM"}) {
          if (name.find(key) != std::string::npos) {
            // RTLD_NOLOAD: a reference to an already-loaded library only, never released.
            dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            break;
          }
        }
        return 0;
      },
      nullptr);
}
#endif

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr size_t kKeptMessages = 64;

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  if (v == nullptr) return false;
  std::string s(v);
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s == "1" || s == "true" || s == "on" || s == "yes";
}

std::string lower(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

std::string api_string(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v));
}

bool has_extension(const std::vector<VkExtensionProperties>& list, const char* name) {
  return std::any_of(list.begin(), list.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

std::vector<VkExtensionProperties> instance_extensions(const char* layer) {
  uint32_t n = 0;
  check(vkEnumerateInstanceExtensionProperties(layer, &n, nullptr),
        "vkEnumerateInstanceExtensionProperties");
  std::vector<VkExtensionProperties> list(n);
  check(vkEnumerateInstanceExtensionProperties(layer, &n, list.data()),
        "vkEnumerateInstanceExtensionProperties");
  list.resize(n);
  return list;
}

std::vector<VkExtensionProperties> device_extensions(VkPhysicalDevice pd) {
  uint32_t n = 0;
  check(vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr),
        "vkEnumerateDeviceExtensionProperties");
  std::vector<VkExtensionProperties> list(n);
  check(vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, list.data()),
        "vkEnumerateDeviceExtensionProperties");
  list.resize(n);
  return list;
}

VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT types,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data,
                                              void* user) {
  if (user != nullptr && data != nullptr) {
    static_cast<Context*>(user)->on_debug_message(
        severity, types, data->pMessage != nullptr ? data->pMessage : "(no message)");
  }
  return VK_FALSE;  // never abort the call that triggered the message
}

// Score by type; see device_score().
int type_score(DeviceType t) {
  switch (t) {
    case DeviceType::Discrete:
      return 4;
    case DeviceType::Integrated:
      return 3;
    case DeviceType::Virtual:
      return 2;
    case DeviceType::Cpu:
      return 1;
    case DeviceType::Other:
      return 0;
  }
  return 0;
}

std::string unusable_reason(const PhysicalDeviceInfo& d, bool require_float64) {
  if (d.compute_queue_family < 0) return "it has no compute queue";
  if (require_float64 && !d.float64)
    return "it lacks shaderFloat64 (cutwork's clip and fill shaders compute in double precision)";
  return {};
}

}  // namespace

ContextOptions ContextOptions::from_environment() {
  ContextOptions o;
  o.validation = env_flag("CUTWORK_VK_VALIDATION");
  if (const char* d = std::getenv("CUTWORK_VK_DEVICE")) o.device = d;
  return o;
}

std::string_view to_string(DeviceType type) {
  switch (type) {
    case DeviceType::Discrete:
      return "discrete GPU";
    case DeviceType::Integrated:
      return "integrated GPU";
    case DeviceType::Virtual:
      return "virtual GPU";
    case DeviceType::Cpu:
      return "CPU";
    case DeviceType::Other:
      return "other";
  }
  return "other";
}

int device_score(const PhysicalDeviceInfo& device, bool require_float64) {
  if (!unusable_reason(device, require_float64).empty()) return -1;
  return type_score(device.type);
}

std::string describe_devices(std::span<const PhysicalDeviceInfo> devices) {
  std::string out;
  for (const PhysicalDeviceInfo& d : devices) {
    if (!out.empty()) out += "; ";
    out += std::to_string(d.index) + ": " + d.name + " (" + std::string(to_string(d.type)) +
           ", Vulkan " + api_string(d.api_version) + (d.float64 ? ", fp64" : ", no fp64") +
           (d.compute_queue_family < 0 ? ", no compute queue" : "") + ")";
  }
  return out.empty() ? "none" : out;
}

size_t choose_device(std::span<const PhysicalDeviceInfo> devices, std::string_view selector,
                     bool require_float64) {
  if (devices.empty()) {
    throw DeviceError(
        "no Vulkan device found (install a GPU driver, or mesa-vulkan-drivers for the CPU "
        "implementation lavapipe; or use --device cpu)");
  }
  if (!selector.empty()) {
    const bool numeric = std::all_of(selector.begin(), selector.end(),
                                     [](unsigned char c) { return std::isdigit(c) != 0; });
    size_t found = devices.size();
    if (numeric) {
      const unsigned long index = std::strtoul(std::string(selector).c_str(), nullptr, 10);
      for (size_t i = 0; i < devices.size(); ++i)
        if (devices[i].index == index) found = i;
    } else {
      const std::string needle = lower(selector);
      for (size_t i = 0; i < devices.size() && found == devices.size(); ++i)
        if (lower(devices[i].name).find(needle) != std::string::npos) found = i;
    }
    if (found == devices.size()) {
      throw DeviceError("CUTWORK_VK_DEVICE='" + std::string(selector) +
                        "' matches no Vulkan device; devices: " + describe_devices(devices));
    }
    const std::string why = unusable_reason(devices[found], require_float64);
    if (!why.empty()) {
      throw DeviceError("Vulkan device '" + devices[found].name + "' (CUTWORK_VK_DEVICE='" +
                        std::string(selector) + "') cannot run cutwork: " + why);
    }
    return found;
  }
  size_t best = devices.size();
  int best_score = -1;
  for (size_t i = 0; i < devices.size(); ++i) {
    const int s = device_score(devices[i], require_float64);
    if (s > best_score) {
      best_score = s;
      best = i;
    }
  }
  if (best == devices.size()) {
    std::string why;
    for (const PhysicalDeviceInfo& d : devices) {
      if (!why.empty()) why += "; ";
      why += d.name + ": " + unusable_reason(d, require_float64);
    }
    throw DeviceError("no usable Vulkan device: " + why);
  }
  return best;
}

Context::Context(const ContextOptions& options) : m_options(options) {
  try {
    create_instance();
    enumerate_devices();
    m_device_index = choose_device(m_devices, m_options.device, m_options.require_float64);
    create_device();
#ifdef CUTWORK_SANITIZE
    keep_vulkan_libraries_mapped();
#endif
  } catch (...) {
#ifdef CUTWORK_SANITIZE
    keep_vulkan_libraries_mapped();
#endif
    destroy();
    throw;
  }
}

PhysicalDeviceInfo Context::probe(const ContextOptions& options) {
  // A Context without its device: the destructor releases what exists.
  Context p(options, Defer{});
  try {
    p.create_instance();
    p.enumerate_devices();
    p.m_device_index = choose_device(p.m_devices, p.m_options.device, p.m_options.require_float64);
  } catch (...) {
#ifdef CUTWORK_SANITIZE
    keep_vulkan_libraries_mapped();
#endif
    throw;
  }
#ifdef CUTWORK_SANITIZE
  keep_vulkan_libraries_mapped();
#endif
  return p.info();
}

Context::~Context() { destroy(); }

void Context::destroy() noexcept {
  if (m_device != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(m_device);
    if (m_fence != VK_NULL_HANDLE) vkDestroyFence(m_device, m_fence, nullptr);
    if (m_command_pool != VK_NULL_HANDLE) vkDestroyCommandPool(m_device, m_command_pool, nullptr);
    vkDestroyDevice(m_device, nullptr);
    m_device = VK_NULL_HANDLE;
  }
  if (m_messenger != VK_NULL_HANDLE) {
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(m_instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy_messenger != nullptr) destroy_messenger(m_instance, m_messenger, nullptr);
    m_messenger = VK_NULL_HANDLE;
  }
  if (m_instance != VK_NULL_HANDLE) {
    vkDestroyInstance(m_instance, nullptr);
    m_instance = VK_NULL_HANDLE;
  }
}

void Context::create_instance() {
  uint32_t loader_version = VK_API_VERSION_1_0;
  check(vkEnumerateInstanceVersion(&loader_version), "vkEnumerateInstanceVersion");
  if (loader_version < VK_API_VERSION_1_1) {
    throw DeviceError("the Vulkan loader supports only Vulkan " + api_string(loader_version) +
                      "; cutwork needs 1.1 or newer (update libvulkan1, or use --device cpu)");
  }

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  bool validation_features = false;
  if (m_options.validation) {
    uint32_t n = 0;
    check(vkEnumerateInstanceLayerProperties(&n, nullptr), "vkEnumerateInstanceLayerProperties");
    std::vector<VkLayerProperties> available(n);
    check(vkEnumerateInstanceLayerProperties(&n, available.data()),
          "vkEnumerateInstanceLayerProperties");
    available.resize(n);
    const bool found = std::any_of(available.begin(), available.end(), [](const auto& l) {
      return std::strcmp(l.layerName, kValidationLayer) == 0;
    });
    if (!found) {
      throw DeviceError(
          "Vulkan validation was requested (CUTWORK_VK_VALIDATION) but VK_LAYER_KHRONOS_validation "
          "is not installed (Debian package vulkan-validationlayers)");
    }
    layers.push_back(kValidationLayer);
    const auto layer_ext = instance_extensions(kValidationLayer);
    validation_features = has_extension(layer_ext, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    if (validation_features) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
    m_debug_utils = has_extension(layer_ext, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  const auto loader_ext = instance_extensions(nullptr);
  if (m_options.validation && !m_debug_utils) {
    m_debug_utils = has_extension(loader_ext, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  if (m_options.validation && !m_debug_utils) {
    throw DeviceError(
        "Vulkan validation was requested but VK_EXT_debug_utils is unavailable, so "
        "its messages could not be counted");
  }
  if (m_debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  VkInstanceCreateFlags flags = 0;
#ifdef VK_KHR_portability_enumeration
  // MoltenVK and other layered implementations only show up when asked for.
  if (has_extension(loader_ext, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
    extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);
    flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
  }
#endif

  auto app = vk_struct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "cutwork";
  app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.pEngineName = "cutwork";
  app.engineVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.apiVersion = std::min<uint32_t>(loader_version, VK_API_VERSION_1_3);

  auto messenger_info = vk_struct<VkDebugUtilsMessengerCreateInfoEXT>(
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT);
  messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = debug_callback;
  messenger_info.pUserData = this;

  const VkValidationFeatureEnableEXT enables[] = {
      VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  auto features = vk_struct<VkValidationFeaturesEXT>(VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT);
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;

  auto info = vk_struct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  info.flags = flags;
  info.pApplicationInfo = &app;
  info.enabledLayerCount = uint32_t(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  // The messenger in pNext also reports on vkCreateInstance/vkDestroyInstance themselves.
  const void* chain = nullptr;
  if (m_debug_utils) {
    messenger_info.pNext = chain;
    chain = &messenger_info;
  }
  if (m_options.validation && validation_features) {
    features.pNext = chain;
    chain = &features;
  }
  info.pNext = chain;

  const VkResult r = vkCreateInstance(&info, nullptr, &m_instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    m_instance = VK_NULL_HANDLE;
    throw DeviceError(
        "no Vulkan driver found (install your GPU's Vulkan driver, or mesa-vulkan-drivers for the "
        "CPU implementation lavapipe; or use --device cpu)");
  }
  check(r, "vkCreateInstance");
  m_validation = m_options.validation;

  if (m_debug_utils) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(m_instance, "vkCreateDebugUtilsMessengerEXT"));
    m_set_object_name = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(m_instance, "vkSetDebugUtilsObjectNameEXT"));
    if (create_messenger == nullptr) {
      throw DeviceError("Vulkan: vkCreateDebugUtilsMessengerEXT is missing");
    }
    messenger_info.pNext = nullptr;
    check(create_messenger(m_instance, &messenger_info, nullptr, &m_messenger),
          "vkCreateDebugUtilsMessengerEXT");
  }
}

void Context::enumerate_devices() {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(m_instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  m_physical_devices.resize(n);
  if (n > 0) {
    check(vkEnumeratePhysicalDevices(m_instance, &n, m_physical_devices.data()),
          "vkEnumeratePhysicalDevices");
  }
  m_physical_devices.resize(n);
  m_devices.clear();
  for (uint32_t i = 0; i < n; ++i) {
    VkPhysicalDevice pd = m_physical_devices[i];
    PhysicalDeviceInfo d;
    d.index = i;
    const auto exts = device_extensions(pd);

    auto driver = vk_struct<VkPhysicalDeviceDriverProperties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    auto props2 =
        vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    VkPhysicalDeviceProperties basic{};
    vkGetPhysicalDeviceProperties(pd, &basic);
    const bool has_driver_props = basic.apiVersion >= VK_API_VERSION_1_2 ||
                                  has_extension(exts, VK_KHR_DRIVER_PROPERTIES_EXTENSION_NAME);
    if (has_driver_props) props2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(pd, &props2);
    const VkPhysicalDeviceProperties& p = props2.properties;
    d.name = p.deviceName;
    d.api_version = p.apiVersion;
    d.vendor_id = p.vendorID;
    switch (p.deviceType) {
      case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        d.type = DeviceType::Discrete;
        break;
      case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        d.type = DeviceType::Integrated;
        break;
      case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        d.type = DeviceType::Virtual;
        break;
      case VK_PHYSICAL_DEVICE_TYPE_CPU:
        d.type = DeviceType::Cpu;
        break;
      default:
        d.type = DeviceType::Other;
        break;
    }
    if (has_driver_props && driver.driverName[0] != '\0') {
      d.driver = driver.driverName;
      if (driver.driverInfo[0] != '\0') d.driver += std::string(" ") + driver.driverInfo;
    } else {
      d.driver = "driver version " + std::to_string(p.driverVersion) + " (vendor 0x" + [&] {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%04x", p.vendorID);
        return std::string(buf);
      }() + ")";
    }

    VkPhysicalDeviceFeatures features{};
    vkGetPhysicalDeviceFeatures(pd, &features);
    d.float64 = features.shaderFloat64 == VK_TRUE;
    d.int64 = features.shaderInt64 == VK_TRUE;

    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> families(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, families.data());
    // Prefer a compute family with timestamps, then a dedicated (non-graphics) one.
    int best = -1, best_rank = -1;
    for (uint32_t q = 0; q < qn; ++q) {
      if ((families[q].queueFlags & VK_QUEUE_COMPUTE_BIT) == 0 || families[q].queueCount == 0)
        continue;
      const int rank = (families[q].timestampValidBits > 0 ? 2 : 0) +
                       ((families[q].queueFlags & VK_QUEUE_GRAPHICS_BIT) == 0 ? 1 : 0);
      if (rank > best_rank) {
        best_rank = rank;
        best = int(q);
      }
    }
    d.compute_queue_family = best;

    VkPhysicalDeviceMemoryProperties mem{};
    vkGetPhysicalDeviceMemoryProperties(pd, &mem);
    for (uint32_t h = 0; h < mem.memoryHeapCount; ++h) {
      if (mem.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
        d.device_local_bytes = std::max<uint64_t>(d.device_local_bytes, mem.memoryHeaps[h].size);
    }
    // UMA: the device's own memory is host-visible and coherent (integrated GPUs, lavapipe).
    // A discrete GPU's resizable BAR also looks like that, but reading it back over PCIe is
    // slow, so only integrated/CPU devices count as UMA.
    if (d.type == DeviceType::Integrated || d.type == DeviceType::Cpu) {
      const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                         VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
      for (uint32_t t = 0; t < mem.memoryTypeCount; ++t)
        if ((mem.memoryTypes[t].propertyFlags & want) == want) d.uma = true;
    }
    m_devices.push_back(std::move(d));
  }
}

void Context::create_device() {
  const PhysicalDeviceInfo& d = m_devices[m_device_index];
  m_physical_device = m_physical_devices[d.index];
  m_queue_family = uint32_t(d.compute_queue_family);
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(m_physical_device, &props);
  m_limits = props.limits;
  vkGetPhysicalDeviceMemoryProperties(m_physical_device, &m_memory);
  uint32_t qn = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(m_physical_device, &qn, nullptr);
  std::vector<VkQueueFamilyProperties> families(qn);
  vkGetPhysicalDeviceQueueFamilyProperties(m_physical_device, &qn, families.data());
  m_timestamp_bits = families[m_queue_family].timestampValidBits;
  m_uses_staging = !d.uma || m_options.force_staging;
  m_max_workgroups = m_limits.maxComputeWorkGroupCount[0];
  if (m_options.max_workgroups_per_dispatch > 0)
    m_max_workgroups = std::min(m_max_workgroups, m_options.max_workgroups_per_dispatch);

  const float priority = 1.0f;
  auto queue_info = vk_struct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  queue_info.queueFamilyIndex = m_queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  VkPhysicalDeviceFeatures features{};
  features.shaderFloat64 = d.float64 ? VK_TRUE : VK_FALSE;
  features.shaderInt64 = d.int64 ? VK_TRUE : VK_FALSE;

  std::vector<const char*> extensions;
  // Implementations that are not fully conformant (MoltenVK) must have this enabled.
  const auto exts = device_extensions(m_physical_device);
  if (has_extension(exts, "VK_KHR_portability_subset"))
    extensions.push_back("VK_KHR_portability_subset");

  auto info = vk_struct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  info.pEnabledFeatures = &features;
  info.enabledExtensionCount = uint32_t(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  check(vkCreateDevice(m_physical_device, &info, nullptr, &m_device),
        "vkCreateDevice on '" + d.name + "'");
  vkGetDeviceQueue(m_device, m_queue_family, 0, &m_queue);

  auto pool_info = vk_struct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = m_queue_family;
  check(vkCreateCommandPool(m_device, &pool_info, nullptr, &m_command_pool), "vkCreateCommandPool");
  auto alloc =
      vk_struct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
  alloc.commandPool = m_command_pool;
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(m_device, &alloc, &m_command_buffer), "vkAllocateCommandBuffers");
  auto fence_info = vk_struct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
  check(vkCreateFence(m_device, &fence_info, nullptr, &m_fence), "vkCreateFence");
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                              VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (uint32_t t = 0; t < m_memory.memoryTypeCount; ++t) {
    if ((type_bits & (1u << t)) == 0) continue;
    const VkMemoryPropertyFlags f = m_memory.memoryTypes[t].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred) return t;
    if (fallback < 0) fallback = int(t);
  }
  if (fallback < 0) {
    throw DeviceError("Vulkan device '" + info().name +
                      "' has no memory type with the properties cutwork needs");
  }
  return uint32_t(fallback);
}

VkMemoryPropertyFlags Context::memory_type_flags(uint32_t type_index) const {
  return m_memory.memoryTypes[type_index].propertyFlags;
}

size_t Context::validation_message_count() const { return m_message_count.load(); }

std::vector<std::string> Context::validation_messages() const {
  std::lock_guard<std::mutex> lock(m_message_mutex);
  return m_messages;
}

void Context::on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                               VkDebugUtilsMessageTypeFlagsEXT types, const char* message) {
  const bool error = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0;
  const bool warning = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) != 0;
  if (!error && !warning) return;
  const char* kind = (types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT)    ? "validation"
                     : (types & VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT) ? "performance"
                                                                                 : "general";
  std::string line = std::string("vulkan ") + kind + (error ? " error: " : " warning: ") + message;
  m_message_count.fetch_add(1);
  {
    std::lock_guard<std::mutex> lock(m_message_mutex);
    if (m_messages.size() < kKeptMessages) m_messages.push_back(line);
  }
  if (m_options.print_validation_messages) std::fprintf(stderr, "cutwork: %s\n", line.c_str());
}

void Context::set_name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (m_set_object_name == nullptr || m_device == VK_NULL_HANDLE) return;
  auto info =
      vk_struct<VkDebugUtilsObjectNameInfoEXT>(VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT);
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  m_set_object_name(m_device, &info);
}

void Context::submit_and_wait() {
  auto submit = vk_struct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &m_command_buffer;
  check(vkQueueSubmit(m_queue, 1, &submit, m_fence), "vkQueueSubmit");
  check(vkWaitForFences(m_device, 1, &m_fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
  check(vkResetFences(m_device, 1, &m_fence), "vkResetFences");
}

}  // namespace cutwork::vulkan

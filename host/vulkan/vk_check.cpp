#include "host/vulkan/vk_check.h"

#include <cstdio>

#include "host/core/error.h"

namespace cutwork::vulkan {

std::string result_name(VkResult result) {
  switch (result) {
#define CUTWORK_VK_RESULT(name) \
  case name:                    \
    return #name;
    CUTWORK_VK_RESULT(VK_SUCCESS)
    CUTWORK_VK_RESULT(VK_NOT_READY)
    CUTWORK_VK_RESULT(VK_TIMEOUT)
    CUTWORK_VK_RESULT(VK_EVENT_SET)
    CUTWORK_VK_RESULT(VK_EVENT_RESET)
    CUTWORK_VK_RESULT(VK_INCOMPLETE)
    CUTWORK_VK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
    CUTWORK_VK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    CUTWORK_VK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
    CUTWORK_VK_RESULT(VK_ERROR_DEVICE_LOST)
    CUTWORK_VK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
    CUTWORK_VK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
    CUTWORK_VK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
    CUTWORK_VK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
    CUTWORK_VK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
    CUTWORK_VK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
    CUTWORK_VK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
    CUTWORK_VK_RESULT(VK_ERROR_FRAGMENTED_POOL)
    CUTWORK_VK_RESULT(VK_ERROR_UNKNOWN)
    CUTWORK_VK_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
    CUTWORK_VK_RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    CUTWORK_VK_RESULT(VK_ERROR_FRAGMENTATION)
    CUTWORK_VK_RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    CUTWORK_VK_RESULT(VK_ERROR_VALIDATION_FAILED_EXT)
#undef CUTWORK_VK_RESULT
    default:
      return "VkResult(" + std::to_string(int(result)) + ")";
  }
}

void check(VkResult result, std::string_view what) {
  if (result == VK_SUCCESS) return;
  std::string message = "Vulkan: ";
  message += what;
  message += " failed: ";
  message += result_name(result);
  if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY) {
    message += " (the problem does not fit this device; try --device cpu)";
  } else if (result == VK_ERROR_DEVICE_LOST) {
    message += " (the GPU driver reset the device; try --device cpu)";
  }
  throw DeviceError(message);
}

std::string format_bytes(unsigned long long bytes) {
  char buf[64];
  if (bytes < 1024ull) {
    std::snprintf(buf, sizeof buf, "%llu B", bytes);
  } else if (bytes < 1024ull * 1024ull) {
    std::snprintf(buf, sizeof buf, "%.1f KiB", double(bytes) / 1024.0);
  } else if (bytes < 1024ull * 1024ull * 1024ull) {
    std::snprintf(buf, sizeof buf, "%.1f MiB", double(bytes) / (1024.0 * 1024.0));
  } else {
    std::snprintf(buf, sizeof buf, "%.2f GiB", double(bytes) / (1024.0 * 1024.0 * 1024.0));
  }
  return buf;
}

}  // namespace cutwork::vulkan

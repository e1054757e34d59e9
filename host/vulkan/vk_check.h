#pragma once
/// VkResult → cutwork::DeviceError. Every Vulkan call in host/vulkan goes through check(), so a
/// failing driver surfaces as one readable line ("Vulkan: vkAllocateMemory for buffer 'pairs'
/// (64.0 MiB) failed: VK_ERROR_OUT_OF_DEVICE_MEMORY") instead of an abort.
#include <vulkan/vulkan.h>

#include <string>
#include <string_view>

namespace cutwork::vulkan {

/// The enumerator's name ("VK_ERROR_DEVICE_LOST"), or "VkResult(<n>)" for unknown codes.
std::string result_name(VkResult result);

/// Throws DeviceError("Vulkan: <what> failed: <result>") when result is not VK_SUCCESS.
/// Positive non-error codes (VK_INCOMPLETE, VK_TIMEOUT …) are treated as failures as well:
/// the callers here never expect them.
void check(VkResult result, std::string_view what);

/// A zero-initialised Vulkan struct with its sType set.
template <class T>
T vk_struct(VkStructureType type) {
  T value{};
  value.sType = type;
  return value;
}

/// "12.0 MiB", "512 B" — for messages.
std::string format_bytes(unsigned long long bytes);

}  // namespace cutwork::vulkan

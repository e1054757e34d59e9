#pragma once
/// Which twin runs the kernels: `--device cpu|vulkan|auto` as a library function.
///
///   cpu     the TBB twins.
///   vulkan  the Vulkan twins on the device Context chooses (CUTWORK_VK_DEVICE overrides);
///           DeviceError when this build has no Vulkan, no driver or no usable device exists.
///   auto    Vulkan when a usable GPU exists (discrete, integrated or virtual), else the TBB
///           twins. A CPU implementation of Vulkan (Mesa's lavapipe) is not taken: it emulates
///           the GPU on the same cores the TBB twins use, and is slower than them (the default
///           pavilion design: 15.2 s on lavapipe, 8.7 s on the CPU kernels). Without any usable
///           Vulkan device (no driver, no fp64) `auto` warns with ONE line on `warnings`; when
///           the only devices are CPU implementations it takes the CPU silently and says why in
///           `reason`. CUTWORK_VK_DEVICE set to a CPU device still makes `auto` use it.
///
/// "Usable" includes shaderFloat64: the GPU twins compute in double, like the CPU twins (see
/// host/vulkan/clip_fill_vk.h for why). This header and backend.cpp compile with or without
/// CUTWORK_WITH_VULKAN, so callers never need #ifdefs.
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>

namespace cutwork {

namespace vulkan {
class Context;
}

enum class DeviceRequest { Cpu, Vulkan, Auto };

/// "cpu", "vulkan" or "auto" (case-insensitive); anything else throws InputError naming the
/// accepted values.
DeviceRequest parse_device_request(std::string_view text);
std::string_view to_string(DeviceRequest request);

/// The resolved backend; its kind/name/driver are what report.json's `device` records.
struct ComputeBackend {
  enum class Kind { Cpu, Vulkan };
  Kind kind = Kind::Cpu;
  std::string name;    ///< GPU name, or the CPU model with the thread count
  std::string driver;  ///< Vulkan driver name and version, or the TBB version
  /// The Vulkan context, shared by everything that dispatches kernels; null for the CPU.
  std::shared_ptr<vulkan::Context> context;
  /// Non-empty when `auto` fell back to the CPU because no Vulkan device was usable: why (the
  /// warning line's text).
  std::string fallback_reason;
  /// Why this backend was chosen, for report.json's `device.reason` (always set).
  std::string reason;

  /// "cpu" or "vulkan".
  std::string_view kind_name() const { return kind == Kind::Cpu ? "cpu" : "vulkan"; }
};

/// True when this build includes the Vulkan twins (CUTWORK_WITH_VULKAN).
bool vulkan_compiled_in();

/// Resolves `request` (see the file comment). The Vulkan context is created with
/// ContextOptions::from_environment() plus require_float64. The warning goes to `warnings`
/// (nullptr: nowhere) as one line "cutwork: warning: …".
ComputeBackend select_compute_backend(DeviceRequest request, std::ostream* warnings);

/// `auto`'s rule for the device Vulkan's scoring chose (see the file comment): true for a GPU
/// of type "discrete GPU", "integrated GPU" or "virtual GPU", or any device `CUTWORK_VK_DEVICE`
/// named (`explicitly_selected`); false for "CPU" and "other" device types.
bool auto_takes_vulkan_device(std::string_view device_type, bool explicitly_selected);

/// The CPU backend's description (name = CPU model and TBB thread count, driver = TBB version).
ComputeBackend cpu_backend();

}  // namespace cutwork

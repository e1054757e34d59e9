#pragma once
/// The Vulkan context: instance (with the Khronos validation layer on request), physical-device
/// choice, logical device with one compute queue, and the command buffer every batch of work is
/// recorded into. RAII: the destructor releases everything in reverse order.
///
/// How the pieces fit (see also kernels/common/gpu_kernel.h for the layering):
///   Context            instance, device, queue, validation counters      (this file)
///   StorageBuffer      device arrays that persist across calls           (buffer.h)
///   ComputePipeline    a GpuKernel + workgroup size → VkPipeline          (pipeline.h)
///   DescriptorSet      which buffers a pipeline sees                      (pipeline.h)
///   CommandBatch       uploads → dispatches → downloads, timestamps       (command_batch.h)
///
/// Device choice (Taichi/ncnn style): every physical device gets a score — discrete GPU >
/// integrated GPU > virtual GPU > CPU implementation (lavapipe) > other; devices without a
/// compute queue, or without shaderFloat64 when the options require it, are not usable.
/// `CUTWORK_VK_DEVICE=<index>` or `=<name substring>` (case-insensitive) overrides the choice.
///
/// Validation: `CUTWORK_VK_VALIDATION=1` (or ContextOptions::validation) enables
/// VK_LAYER_KHRONOS_validation with synchronisation validation and installs a debug-utils
/// messenger that counts every warning and error; the GPU tests require the count to stay 0.
///
/// Threading: a Context is used by one thread at a time (one queue, one command buffer). The
/// messenger's counters are atomic because drivers may call back from their own threads.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cutwork::vulkan {

/// How to create a Context.
struct ContextOptions {
  /// Enable VK_LAYER_KHRONOS_validation (+ synchronisation validation) and count its messages.
  /// Throws DeviceError at creation when the layer is not installed (vulkan-validationlayers).
  bool validation = false;
  /// Device selector: "" chooses by score; digits select that index of
  /// vkEnumeratePhysicalDevices; anything else is a case-insensitive substring of the name.
  std::string device;
  /// Only devices with shaderFloat64 are usable (the clip and fill shaders compute in double).
  bool require_float64 = false;
  /// Use device-local buffers with staging copies even where the device shares host memory
  /// (UMA). Lets the tests exercise the discrete-GPU path on lavapipe.
  bool force_staging = false;
  /// Print each validation message on stderr as it arrives (they are always counted).
  bool print_validation_messages = true;
  /// Largest number of workgroups one vkCmdDispatch may launch along x; 0 = the device limit.
  /// Tests set it small to exercise the chunking of large launches.
  uint32_t max_workgroups_per_dispatch = 0;

  /// Defaults with the environment applied: CUTWORK_VK_VALIDATION (1/true/on enables),
  /// CUTWORK_VK_DEVICE (selector).
  static ContextOptions from_environment();
};

enum class DeviceType { Discrete, Integrated, Virtual, Cpu, Other };

/// "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other".
std::string_view to_string(DeviceType type);

/// What cutwork needs to know about one physical device.
struct PhysicalDeviceInfo {
  uint32_t index = 0;  ///< position in vkEnumeratePhysicalDevices
  std::string name;    ///< deviceName ("llvmpipe (LLVM 15.0.6, 256 bits)")
  std::string driver;  ///< driver name and info ("llvmpipe Mesa 22.3.6 (LLVM 15.0.6)")
  DeviceType type = DeviceType::Other;
  uint32_t api_version = 0;  ///< VK_MAKE_API_VERSION encoded
  uint32_t vendor_id = 0;
  bool float64 = false;               ///< shaderFloat64
  bool int64 = false;                 ///< shaderInt64
  bool uma = false;                   ///< device memory is also host-visible and coherent
  int32_t compute_queue_family = -1;  ///< −1: no compute queue
  uint64_t device_local_bytes = 0;    ///< size of the largest device-local heap
};

/// Score for the automatic choice: discrete 4 > integrated 3 > virtual 2 > CPU 1 > other 0;
/// −1 when unusable (no compute queue, or no shaderFloat64 while `require_float64`).
int device_score(const PhysicalDeviceInfo& device, bool require_float64);

/// Index into `devices` of the device `selector` names (see ContextOptions::device), or of the
/// best-scoring usable device when the selector is empty; ties go to the lower index.
/// Throws DeviceError listing the devices when none is usable or the selector matches none, or
/// when the selected one is unusable (the message says why).
size_t choose_device(std::span<const PhysicalDeviceInfo> devices, std::string_view selector,
                     bool require_float64);

/// One line per device: "0: llvmpipe (…) — CPU, Vulkan 1.3, fp64" — for error messages.
std::string describe_devices(std::span<const PhysicalDeviceInfo> devices);

class Context {
 public:
  /// Creates instance, device and queue. Throws DeviceError when no Vulkan driver or no usable
  /// device exists, or when validation was requested and the layer is missing.
  explicit Context(const ContextOptions& options = ContextOptions::from_environment());
  /// The device a Context with these options would choose, found without creating a logical
  /// device (instance, enumeration and choice only; the instance is destroyed again). What
  /// `--device auto` asks first: on a machine whose best device is a CPU implementation it never
  /// builds one. Throws DeviceError as the constructor does.
  static PhysicalDeviceInfo probe(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return m_instance; }
  VkPhysicalDevice physical_device() const { return m_physical_device; }
  VkDevice device() const { return m_device; }
  VkQueue queue() const { return m_queue; }
  uint32_t queue_family() const { return m_queue_family; }
  const ContextOptions& options() const { return m_options; }
  /// The chosen device.
  const PhysicalDeviceInfo& info() const { return m_devices[m_device_index]; }
  /// Every device the loader reported, chosen or not.
  const std::vector<PhysicalDeviceInfo>& devices() const { return m_devices; }
  const VkPhysicalDeviceLimits& limits() const { return m_limits; }

  /// Buffers are device-local with host staging copies (discrete GPUs, or force_staging),
  /// rather than host-visible memory the kernels read directly (UMA devices).
  bool uses_staging() const { return m_uses_staging; }
  /// Workgroups per vkCmdDispatch along x (device limit, or the option when smaller).
  uint32_t max_workgroups_per_dispatch() const { return m_max_workgroups; }

  /// Index of a memory type allowed by `type_bits` with all `required` flags, preferring one
  /// that also has the `preferred` flags. Throws DeviceError when none exists.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                       VkMemoryPropertyFlags preferred) const;
  VkMemoryPropertyFlags memory_type_flags(uint32_t type_index) const;

  /// Timestamps: supported on the compute queue, and nanoseconds per tick.
  bool timestamps_supported() const { return m_timestamp_bits > 0; }
  uint32_t timestamp_valid_bits() const { return m_timestamp_bits; }
  double timestamp_period_ns() const { return m_limits.timestampPeriod; }

  /// Validation. `validation_message_count` counts warnings and errors of the validation and
  /// performance kinds since creation (0 when validation is off).
  bool validation_enabled() const { return m_validation; }
  size_t validation_message_count() const;
  /// The first messages (up to 64), for test failure output.
  std::vector<std::string> validation_messages() const;

  /// Names a Vulkan object for validation messages (no-op without debug utils).
  void set_name(VkObjectType type, uint64_t handle, const std::string& name) const;

  /// The context's single primary command buffer and its fence; CommandBatch records into it.
  VkCommandBuffer command_buffer() const { return m_command_buffer; }
  /// Submits the command buffer and waits for it. Throws DeviceError on failure.
  void submit_and_wait();

  /// Internal: called by the debug-utils callback.
  void on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                        VkDebugUtilsMessageTypeFlagsEXT types, const char* message);

 private:
  struct Defer {};
  /// Stores the options only (probe()).
  Context(const ContextOptions& options, Defer) : m_options(options) {}

  void create_instance();
  void enumerate_devices();
  void create_device();
  void destroy() noexcept;

  ContextOptions m_options;
  bool m_validation = false;
  bool m_debug_utils = false;
  VkInstance m_instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
  PFN_vkSetDebugUtilsObjectNameEXT m_set_object_name = nullptr;
  std::vector<VkPhysicalDevice> m_physical_devices;
  std::vector<PhysicalDeviceInfo> m_devices;
  size_t m_device_index = 0;
  VkPhysicalDevice m_physical_device = VK_NULL_HANDLE;
  VkPhysicalDeviceLimits m_limits{};
  VkPhysicalDeviceMemoryProperties m_memory{};
  uint32_t m_queue_family = 0;
  uint32_t m_timestamp_bits = 0;
  uint32_t m_max_workgroups = 0;
  bool m_uses_staging = false;
  VkDevice m_device = VK_NULL_HANDLE;
  VkQueue m_queue = VK_NULL_HANDLE;
  VkCommandPool m_command_pool = VK_NULL_HANDLE;
  VkCommandBuffer m_command_buffer = VK_NULL_HANDLE;
  VkFence m_fence = VK_NULL_HANDLE;

  std::atomic<size_t> m_message_count{0};
  mutable std::mutex m_message_mutex;
  std::vector<std::string> m_messages;
};

}  // namespace cutwork::vulkan

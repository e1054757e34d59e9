#pragma once
/// Device memory: a raw RAII buffer (Buffer) and the persistent kernel array built on it
/// (StorageBuffer).
///
/// Memory strategy, chosen once per Context:
///  - UMA devices (integrated GPUs, lavapipe): one buffer in memory that is device-local AND
///    host-visible; uploads are memcpy into the mapping, downloads read it after the fence.
///  - Discrete GPUs (or ContextOptions::force_staging): a device-local buffer plus a
///    host-visible mirror of the same size; uploads copy changed ranges mirror → device inside
///    the batch's command buffer, downloads copy device → mirror.
///
/// Persistence: a StorageBuffer lives as long as its owner (a kernel runner that lives across
/// optimiser iterations). It keeps a host shadow of what it last received, and an upload only
/// transfers the 16-KiB blocks whose bytes differ — so an unchanged mesh costs a memcmp, not a
/// PCIe transfer, and a pair list that gained ten pairs transfers only its tail.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace cutwork::vulkan {

class Context;

/// A VkBuffer with its own VkDeviceMemory (cutwork allocates a handful of large buffers, so a
/// sub-allocator would buy nothing). Move-only; host-visible memory stays mapped.
class Buffer {
 public:
  enum class Memory {
    DeviceLocal,  ///< fastest for the device; not mapped
    Mirror,       ///< host-visible staging/readback mirror (prefers cached + coherent)
    Shared,       ///< device-local and host-visible (UMA); mapped
  };

  Buffer() = default;
  /// Allocates `bytes` (> 0). `name` appears in validation and error messages.
  Buffer(const Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Memory memory,
         const std::string& name);
  ~Buffer();
  Buffer(Buffer&& other) noexcept;
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  bool valid() const { return m_buffer != VK_NULL_HANDLE; }
  VkBuffer handle() const { return m_buffer; }
  VkDeviceSize bytes() const { return m_bytes; }
  /// Host pointer to the whole buffer, or nullptr for DeviceLocal memory.
  std::byte* mapped() const { return m_mapped; }
  /// Make host writes in [offset, offset+size) visible to the device (no-op when coherent).
  void flush(VkDeviceSize offset, VkDeviceSize size) const;
  /// Make device writes in [offset, offset+size) visible to the host (no-op when coherent).
  void invalidate(VkDeviceSize offset, VkDeviceSize size) const;

 private:
  void release() noexcept;
  VkMappedMemoryRange atom_range(VkDeviceSize offset, VkDeviceSize size) const;

  VkDevice m_device = VK_NULL_HANDLE;
  VkBuffer m_buffer = VK_NULL_HANDLE;
  VkDeviceMemory m_memory = VK_NULL_HANDLE;
  VkDeviceSize m_bytes = 0;
  VkDeviceSize m_atom = 1;
  std::byte* m_mapped = nullptr;
  bool m_coherent = true;
};

/// A contiguous byte range of a buffer.
struct ByteRange {
  size_t offset = 0;
  size_t size = 0;
};

/// A kernel's storage buffer that persists across calls. Its contents are set either by an
/// upload (host → device, see CommandBatch::upload) or by a kernel (CommandBatch::allocate for
/// outputs) and read back by CommandBatch::download. Grows on demand (reallocating; the
/// generation() changes so descriptor sets re-point); never shrinks.
class StorageBuffer {
 public:
  StorageBuffer(Context& ctx, std::string name);

  const std::string& name() const { return m_name; }
  /// Bytes currently defined (last upload or allocate).
  size_t size() const { return m_size; }
  size_t capacity() const { return m_capacity; }
  /// The buffer shaders bind (allocated with a minimal size on first use).
  VkBuffer handle();
  /// Changes whenever handle() changes.
  uint64_t generation() const { return m_generation; }

  /// Bytes transferred by the last upload, and in total since creation.
  size_t last_upload_bytes() const { return m_last_upload; }
  size_t total_upload_bytes() const { return m_total_upload; }

  // --- used by CommandBatch -------------------------------------------------------------
  /// Ensures capacity ≥ bytes (≥ 1); reallocation loses the contents and the shadow.
  /// Throws DeviceError when `bytes` exceeds the device's maxStorageBufferRange.
  void reserve(size_t bytes);
  /// Makes the host-side copy (mapping or mirror) equal `bytes`, comparing against the shadow
  /// in blocks; returns the ranges that changed (already written host-side and flushed). With
  /// staging, the caller must copy those ranges mirror → device before the next dispatch.
  std::vector<ByteRange> stage(std::span<const std::byte> bytes);
  /// Marks the contents as written by the device: size becomes `bytes`, the shadow is dropped.
  void mark_device_written(size_t bytes);
  /// Device-local buffer (what shaders bind) and the host mirror (staging only; else invalid).
  const Buffer& device_buffer() const { return m_device; }
  const Buffer& mirror() const { return m_mirror; }
  /// Host view of the device contents after a download was recorded and submitted.
  const std::byte* host_view() const;

  /// Block size for change detection.
  static constexpr size_t kBlockBytes = 16 * 1024;

 private:
  Context* m_ctx;
  std::string m_name;
  Buffer m_device;
  Buffer m_mirror;
  std::vector<std::byte> m_shadow;  ///< last uploaded bytes; valid iff m_shadow_valid
  bool m_shadow_valid = false;
  size_t m_size = 0;
  size_t m_capacity = 0;
  uint64_t m_generation = 0;
  size_t m_last_upload = 0;
  size_t m_total_upload = 0;
};

}  // namespace cutwork::vulkan

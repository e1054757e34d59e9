#include "host/vulkan/buffer.h"

#include <algorithm>
#include <cstring>
#include <utility>

#include "host/core/error.h"
#include "host/vulkan/context.h"
#include "host/vulkan/vk_check.h"

namespace cutwork::vulkan {

Buffer::Buffer(const Context& ctx, VkDeviceSize bytes, VkBufferUsageFlags usage, Memory memory,
               const std::string& name)
    : m_device(ctx.device()), m_bytes(bytes), m_atom(ctx.limits().nonCoherentAtomSize) {
  if (m_atom == 0) m_atom = 1;
  const std::string what = "buffer '" + name + "' (" + format_bytes(bytes) + ")";
  try {
    auto info = vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    info.size = bytes;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(m_device, &info, nullptr, &m_buffer), "vkCreateBuffer for " + what);
    VkMemoryRequirements req{};
    vkGetBufferMemoryRequirements(m_device, m_buffer, &req);
    VkMemoryPropertyFlags required = 0, preferred = 0;
    switch (memory) {
      case Memory::DeviceLocal:
        required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
        break;
      case Memory::Mirror:
        required = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
      case Memory::Shared:
        required = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
        preferred = VK_MEMORY_PROPERTY_HOST_COHERENT_BIT | VK_MEMORY_PROPERTY_HOST_CACHED_BIT;
        break;
    }
    const uint32_t type = ctx.memory_type(req.memoryTypeBits, required, preferred);
    const VkMemoryPropertyFlags flags = ctx.memory_type_flags(type);
    m_coherent = (flags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT) != 0;
    auto alloc = vk_struct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = type;
    check(vkAllocateMemory(m_device, &alloc, nullptr, &m_memory), "vkAllocateMemory for " + what);
    check(vkBindBufferMemory(m_device, m_buffer, m_memory, 0), "vkBindBufferMemory for " + what);
    if (memory != Memory::DeviceLocal) {
      void* p = nullptr;
      check(vkMapMemory(m_device, m_memory, 0, VK_WHOLE_SIZE, 0, &p), "vkMapMemory for " + what);
      m_mapped = static_cast<std::byte*>(p);
    }
    ctx.set_name(VK_OBJECT_TYPE_BUFFER, uint64_t(m_buffer), name);
  } catch (...) {
    release();
    throw;
  }
}

Buffer::~Buffer() { release(); }

Buffer::Buffer(Buffer&& other) noexcept { *this = std::move(other); }

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    release();
    m_device = std::exchange(other.m_device, VkDevice(VK_NULL_HANDLE));
    m_buffer = std::exchange(other.m_buffer, VkBuffer(VK_NULL_HANDLE));
    m_memory = std::exchange(other.m_memory, VkDeviceMemory(VK_NULL_HANDLE));
    m_bytes = std::exchange(other.m_bytes, 0);
    m_atom = std::exchange(other.m_atom, 1);
    m_mapped = std::exchange(other.m_mapped, nullptr);
    m_coherent = std::exchange(other.m_coherent, true);
  }
  return *this;
}

void Buffer::release() noexcept {
  if (m_device == VK_NULL_HANDLE) return;
  if (m_mapped != nullptr) vkUnmapMemory(m_device, m_memory);
  if (m_buffer != VK_NULL_HANDLE) vkDestroyBuffer(m_device, m_buffer, nullptr);
  if (m_memory != VK_NULL_HANDLE) vkFreeMemory(m_device, m_memory, nullptr);
  m_mapped = nullptr;
  m_buffer = VK_NULL_HANDLE;
  m_memory = VK_NULL_HANDLE;
}

VkMappedMemoryRange Buffer::atom_range(VkDeviceSize offset, VkDeviceSize size) const {
  auto r = vk_struct<VkMappedMemoryRange>(VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE);
  r.memory = m_memory;
  r.offset = offset / m_atom * m_atom;
  const VkDeviceSize end = (offset + size + m_atom - 1) / m_atom * m_atom;
  // Past the buffer's end the range must be VK_WHOLE_SIZE (the allocation may be larger).
  r.size = end >= m_bytes ? VK_WHOLE_SIZE : end - r.offset;
  return r;
}

void Buffer::flush(VkDeviceSize offset, VkDeviceSize size) const {
  if (m_coherent || m_mapped == nullptr || size == 0) return;
  const VkMappedMemoryRange r = atom_range(offset, size);
  check(vkFlushMappedMemoryRanges(m_device, 1, &r), "vkFlushMappedMemoryRanges");
}

void Buffer::invalidate(VkDeviceSize offset, VkDeviceSize size) const {
  if (m_coherent || m_mapped == nullptr || size == 0) return;
  const VkMappedMemoryRange r = atom_range(offset, size);
  check(vkInvalidateMappedMemoryRanges(m_device, 1, &r), "vkInvalidateMappedMemoryRanges");
}

StorageBuffer::StorageBuffer(Context& ctx, std::string name)
    : m_ctx(&ctx), m_name(std::move(name)) {}

VkBuffer StorageBuffer::handle() {
  if (!m_device.valid()) reserve(1);
  return m_device.handle();
}

void StorageBuffer::reserve(size_t bytes) {
  constexpr size_t kAlign = 256;
  const size_t need = std::max<size_t>(bytes, kAlign);
  if (m_device.valid() && need <= m_capacity) return;
  const size_t limit = m_ctx->limits().maxStorageBufferRange;
  if (need > limit) {
    throw DeviceError("Vulkan buffer '" + m_name + "' needs " + format_bytes(need) +
                      " but device '" + m_ctx->info().name + "' binds at most " +
                      format_bytes(limit) +
                      " per storage buffer; use --device cpu for a problem this large");
  }
  size_t cap = std::max(need, m_capacity + m_capacity / 2);  // amortised growth
  cap = (cap + kAlign - 1) / kAlign * kAlign;
  cap = std::min(cap, limit);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  // Free the old storage first so peak memory is not old + new.
  m_device = Buffer();
  m_mirror = Buffer();
  m_capacity = 0;
  if (m_ctx->uses_staging()) {
    m_device = Buffer(*m_ctx, cap, usage, Buffer::Memory::DeviceLocal, m_name);
    m_mirror =
        Buffer(*m_ctx, cap, VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
               Buffer::Memory::Mirror, m_name + " (host mirror)");
  } else {
    m_device = Buffer(*m_ctx, cap, usage, Buffer::Memory::Shared, m_name);
  }
  m_capacity = cap;
  m_size = 0;
  m_shadow.clear();
  m_shadow_valid = false;
  ++m_generation;
}

std::vector<ByteRange> StorageBuffer::stage(std::span<const std::byte> bytes) {
  const size_t n = bytes.size();
  reserve(n);
  const Buffer& host = m_ctx->uses_staging() ? m_mirror : m_device;
  const size_t known = m_shadow_valid ? std::min(m_shadow.size(), n) : 0;
  std::vector<ByteRange> ranges;
  for (size_t off = 0; off < n; off += kBlockBytes) {
    const size_t len = std::min(kBlockBytes, n - off);
    const bool dirty =
        off + len > known || std::memcmp(m_shadow.data() + off, bytes.data() + off, len) != 0;
    if (!dirty) continue;
    if (!ranges.empty() && ranges.back().offset + ranges.back().size == off) {
      ranges.back().size += len;
    } else {
      ranges.push_back({off, len});
    }
  }
  m_shadow.resize(n);
  size_t moved = 0;
  for (const ByteRange& r : ranges) {
    std::memcpy(host.mapped() + r.offset, bytes.data() + r.offset, r.size);
    std::memcpy(m_shadow.data() + r.offset, bytes.data() + r.offset, r.size);
    host.flush(r.offset, r.size);
    moved += r.size;
  }
  m_shadow_valid = true;
  m_size = n;
  m_last_upload = moved;
  m_total_upload += moved;
  return ranges;
}

void StorageBuffer::mark_device_written(size_t bytes) {
  reserve(bytes);
  m_size = bytes;
  m_shadow.clear();
  m_shadow_valid = false;
}

const std::byte* StorageBuffer::host_view() const {
  return m_ctx->uses_staging() ? m_mirror.mapped() : m_device.mapped();
}

}  // namespace cutwork::vulkan

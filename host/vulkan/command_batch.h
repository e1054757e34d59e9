#pragma once
/// One round trip to the device: uploads, then dispatches, then downloads, recorded into the
/// context's command buffer and submitted once; submit() waits and returns the timings.
///
/// The three phases come in this order (calling an earlier phase after a later one throws
/// std::logic_error): with UMA memory an upload is a memcpy into the buffer the device reads,
/// so it has to happen before anything that reads it is submitted, and a buffer may only be
/// reallocated before the descriptor sets that point at it are recorded.
///
/// Synchronisation is explicit and conservative — one global memory barrier between phases and
/// between consecutive dispatches (each kernel may read what the previous one wrote) — and is
/// checked by the validation layer's synchronisation validation in the GPU tests.
///
/// Large launches are split into chunks of at most Context::max_workgroups_per_dispatch()
/// workgroups; the DispatchRange at the head of the push block tells each chunk its items.
#include <vulkan/vulkan.h>

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace cutwork::vulkan {

class Context;
class StorageBuffer;
class ComputePipeline;
class DescriptorSet;

/// What one submit() did.
struct BatchReport {
  struct Dispatch {
    std::string kernel;               ///< GpuKernel::name
    uint32_t items = 0;               ///< invocations that did work
    uint32_t chunks = 0;              ///< vkCmdDispatch calls it took
    std::optional<double> device_ms;  ///< GPU time from timestamps (none without timestamps)
  };
  std::vector<Dispatch> dispatches;
  /// Per upload() call: the buffer's name and the bytes that changed and were transferred.
  std::vector<std::pair<std::string, size_t>> uploads;
  size_t upload_bytes = 0;  ///< sum of `uploads`
  size_t download_bytes = 0;
  double wall_ms = 0.0;  ///< submit() call, host clock (includes the wait)
};

class CommandBatch {
 public:
  /// Begins recording into ctx's command buffer. One CommandBatch per Context at a time.
  explicit CommandBatch(Context& ctx);
  /// Discards the recording if submit() was not called (e.g. after an exception).
  ~CommandBatch();
  CommandBatch(const CommandBatch&) = delete;
  CommandBatch& operator=(const CommandBatch&) = delete;

  // --- phase 1: uploads and output allocation -------------------------------------------
  /// Makes `buffer` hold exactly `bytes`, transferring only the blocks that changed since the
  /// buffer's last upload. Returns the bytes transferred.
  size_t upload(StorageBuffer& buffer, std::span<const std::byte> bytes);
  template <class T>
  size_t upload(StorageBuffer& buffer, std::span<const T> values) {
    return upload(buffer, std::as_bytes(values));
  }
  /// Sizes `buffer` to `bytes` for a kernel to write (contents undefined until it does).
  void allocate(StorageBuffer& buffer, size_t bytes);

  // --- phase 2: dispatches ---------------------------------------------------------------
  /// Runs `items` invocations of `pipeline` with `set` bound. `push` is the kernel's whole
  /// push block (GpuKernel::push_constant_bytes); its leading DispatchRange is overwritten per
  /// chunk. Items = 0 records nothing.
  void dispatch(const ComputePipeline& pipeline, DescriptorSet& set,
                std::span<const std::byte> push, uint32_t items);
  template <class Push>
  void dispatch(const ComputePipeline& pipeline, DescriptorSet& set, const Push& push,
                uint32_t items) {
    dispatch(pipeline, set, std::as_bytes(std::span<const Push>(&push, 1)), items);
  }

  // --- phase 3: downloads ----------------------------------------------------------------
  /// Copies bytes [offset, offset + dst.size()) of `buffer` into `dst` once submit() returns.
  /// `dst` must stay valid until then.
  void download(StorageBuffer& buffer, std::span<std::byte> dst, size_t offset = 0);
  template <class T>
  void download(StorageBuffer& buffer, std::span<T> dst, size_t offset_items = 0) {
    download(buffer, std::as_writable_bytes(dst), offset_items * sizeof(T));
  }

  /// Ends recording, submits, waits, performs the downloads. Throws DeviceError on failure.
  BatchReport submit();

 private:
  enum class Phase { Upload, Dispatch, Download, Done };
  void enter(Phase phase);
  void barrier(VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
               VkAccessFlags dst_access);

  struct PendingDownload {
    StorageBuffer* buffer;
    std::span<std::byte> dst;
    size_t offset;
  };

  Context& m_ctx;
  VkCommandBuffer m_cb;
  Phase m_phase = Phase::Upload;
  bool m_transfers_pending = false;  ///< staging copies recorded since the last barrier
  bool m_dispatched = false;
  std::vector<PendingDownload> m_downloads;
  BatchReport m_report;
  VkQueryPool m_queries = VK_NULL_HANDLE;
  uint32_t m_query_capacity = 0;
  uint32_t m_queries_used = 0;
  std::vector<int> m_dispatch_query;  ///< first query of dispatch i, −1 when untimed
};

}  // namespace cutwork::vulkan

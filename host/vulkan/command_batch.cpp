#include "host/vulkan/command_batch.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "host/vulkan/buffer.h"
#include "host/vulkan/context.h"
#include "host/vulkan/pipeline.h"
#include "host/vulkan/vk_check.h"
#include "kernels/common/gpu_kernel.h"

namespace cutwork::vulkan {
namespace {
constexpr uint32_t kMaxTimedDispatches = 32;  // two queries each
}

CommandBatch::CommandBatch(Context& ctx) : m_ctx(ctx), m_cb(ctx.command_buffer()) {
  check(vkResetCommandBuffer(m_cb, 0), "vkResetCommandBuffer");
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(m_cb, &begin), "vkBeginCommandBuffer");
  if (ctx.timestamps_supported()) {
    auto info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2 * kMaxTimedDispatches;
    check(vkCreateQueryPool(ctx.device(), &info, nullptr, &m_queries), "vkCreateQueryPool");
    m_query_capacity = info.queryCount;
    vkCmdResetQueryPool(m_cb, m_queries, 0, m_query_capacity);
  }
  // Earlier batches on this queue may have written buffers this one reads (a kernel's output
  // kept on the device for the next call); a barrier's first scope covers everything submitted
  // before it, so this one barrier orders them against all of this batch's work.
  barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
          VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
              VK_ACCESS_TRANSFER_WRITE_BIT);
}

CommandBatch::~CommandBatch() {
  if (m_phase != Phase::Done) vkResetCommandBuffer(m_cb, 0);
  if (m_queries != VK_NULL_HANDLE) vkDestroyQueryPool(m_ctx.device(), m_queries, nullptr);
}

void CommandBatch::barrier(VkPipelineStageFlags src, VkAccessFlags src_access,
                           VkPipelineStageFlags dst, VkAccessFlags dst_access) {
  auto b = vk_struct<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  b.srcAccessMask = src_access;
  b.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(m_cb, src, dst, 0, 1, &b, 0, nullptr, 0, nullptr);
}

void CommandBatch::enter(Phase phase) {
  if (phase < m_phase) {
    throw std::logic_error(
        "CommandBatch: uploads, dispatches and downloads must come in that order");
  }
  if (phase == m_phase) return;
  if (phase >= Phase::Dispatch && m_phase == Phase::Upload && m_transfers_pending) {
    barrier(VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    m_transfers_pending = false;
  }
  if (phase >= Phase::Download && m_phase < Phase::Download) {
    // Kernel (or upload) writes → the copies into the host mirrors, or → host reads (UMA).
    if (m_ctx.uses_staging()) {
      barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
              VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
              VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    } else {
      barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
              VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
              VK_ACCESS_HOST_READ_BIT);
    }
  }
  m_phase = phase;
}

size_t CommandBatch::upload(StorageBuffer& buffer, std::span<const std::byte> bytes) {
  enter(Phase::Upload);
  const std::vector<ByteRange> ranges = buffer.stage(bytes);
  size_t moved = 0;
  if (m_ctx.uses_staging() && !ranges.empty()) {
    std::vector<VkBufferCopy> regions;
    regions.reserve(ranges.size());
    for (const ByteRange& r : ranges) regions.push_back({r.offset, r.offset, r.size});
    vkCmdCopyBuffer(m_cb, buffer.mirror().handle(), buffer.device_buffer().handle(),
                    uint32_t(regions.size()), regions.data());
    m_transfers_pending = true;
  }
  for (const ByteRange& r : ranges) moved += r.size;
  m_report.uploads.emplace_back(buffer.name(), moved);
  m_report.upload_bytes += moved;
  return moved;
}

void CommandBatch::allocate(StorageBuffer& buffer, size_t bytes) {
  enter(Phase::Upload);
  buffer.mark_device_written(bytes);
}

void CommandBatch::dispatch(const ComputePipeline& pipeline, DescriptorSet& set,
                            std::span<const std::byte> push, uint32_t items) {
  enter(Phase::Dispatch);
  const kernels::GpuKernel& kernel = pipeline.kernel();
  if (push.size() != kernel.push_constant_bytes) {
    throw std::logic_error("CommandBatch::dispatch: push block of kernel '" +
                           std::string(kernel.name) + "' has the wrong size");
  }
  if (set.layout() != pipeline.set_layout()) {
    throw std::logic_error("CommandBatch::dispatch: descriptor set made for another pipeline");
  }
  BatchReport::Dispatch entry;
  entry.kernel = std::string(kernel.name);
  entry.items = items;
  if (items == 0) {
    m_report.dispatches.push_back(entry);
    m_dispatch_query.push_back(-1);
    return;
  }
  set.refresh();
  if (m_dispatched) {
    // The previous kernel's writes → this kernel's reads (and WAW/WAR on shared buffers).
    barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
            VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
  }
  m_dispatched = true;
  int query = -1;
  if (m_queries != VK_NULL_HANDLE && m_queries_used + 2 <= m_query_capacity) {
    query = int(m_queries_used);
    m_queries_used += 2;
    vkCmdWriteTimestamp(m_cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, m_queries, uint32_t(query));
  }
  vkCmdBindPipeline(m_cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
  const VkDescriptorSet handle = set.handle();
  vkCmdBindDescriptorSets(m_cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &handle, 0,
                          nullptr);
  std::vector<std::byte> block(push.begin(), push.end());
  const uint32_t wg = pipeline.workgroup_size();
  const uint64_t per_chunk = uint64_t(m_ctx.max_workgroups_per_dispatch()) * wg;
  for (uint64_t first = 0; first < items; first += per_chunk) {
    const uint32_t count = uint32_t(std::min<uint64_t>(per_chunk, items - first));
    if (entry.chunks > 0) {
      // Chunks touch disjoint items, but the validation layer tracks whole bound ranges;
      // a barrier keeps it (and any reader of the whole buffer) honest at negligible cost.
      barrier(VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
              VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
              VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
              VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    }
    const kernels::DispatchRange range{uint32_t(first), count};
    std::memcpy(block.data(), &range, sizeof range);
    vkCmdPushConstants(m_cb, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       uint32_t(block.size()), block.data());
    vkCmdDispatch(m_cb, (count + wg - 1) / wg, 1, 1);
    ++entry.chunks;
  }
  if (query >= 0) {
    vkCmdWriteTimestamp(m_cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, m_queries, uint32_t(query + 1));
  }
  m_report.dispatches.push_back(entry);
  m_dispatch_query.push_back(query);
}

void CommandBatch::download(StorageBuffer& buffer, std::span<std::byte> dst, size_t offset) {
  enter(Phase::Download);
  if (offset + dst.size() > buffer.size()) {
    throw std::logic_error("CommandBatch::download: range past the end of buffer '" +
                           buffer.name() + "'");
  }
  if (dst.empty()) return;
  if (m_ctx.uses_staging()) {
    const VkBufferCopy region{offset, offset, dst.size()};
    vkCmdCopyBuffer(m_cb, buffer.device_buffer().handle(), buffer.mirror().handle(), 1, &region);
  }
  m_downloads.push_back({&buffer, dst, offset});
  m_report.download_bytes += dst.size();
}

BatchReport CommandBatch::submit() {
  if (m_phase == Phase::Done) throw std::logic_error("CommandBatch::submit called twice");
  if (m_transfers_pending) {
    // Uploads without any dispatch: still make them visible to later batches' kernels.
    barrier(VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    m_transfers_pending = false;
  }
  if (m_ctx.uses_staging() && !m_downloads.empty()) {
    barrier(VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
  }
  check(vkEndCommandBuffer(m_cb), "vkEndCommandBuffer");
  m_phase = Phase::Done;
  const auto t0 = std::chrono::steady_clock::now();
  m_ctx.submit_and_wait();
  m_report.wall_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  if (m_queries_used > 0) {
    std::vector<uint64_t> ticks(m_queries_used);
    check(vkGetQueryPoolResults(m_ctx.device(), m_queries, 0, m_queries_used,
                                ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const uint32_t bits = m_ctx.timestamp_valid_bits();
    const uint64_t mask = bits >= 64 ? ~uint64_t(0) : ((uint64_t(1) << bits) - 1);
    for (size_t i = 0; i < m_report.dispatches.size(); ++i) {
      const int q = m_dispatch_query[i];
      if (q < 0) continue;
      const uint64_t delta = (ticks[size_t(q) + 1] - ticks[size_t(q)]) & mask;
      m_report.dispatches[i].device_ms = double(delta) * m_ctx.timestamp_period_ns() * 1e-6;
    }
  }
  for (const PendingDownload& d : m_downloads) {
    const Buffer& host = m_ctx.uses_staging() ? d.buffer->mirror() : d.buffer->device_buffer();
    host.invalidate(d.offset, d.dst.size());
    std::memcpy(d.dst.data(), d.buffer->host_view() + d.offset, d.dst.size());
  }
  return m_report;
}

}  // namespace cutwork::vulkan

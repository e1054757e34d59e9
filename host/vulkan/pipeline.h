#pragma once
/// Compute pipelines built from a kernel's GpuKernel description, and the descriptor sets that
/// point them at StorageBuffers.
///
/// The workgroup size is specialisation constant 0 (see kernels/common/gpu_kernel.h), so one
/// SPIR-V blob serves every device: the host picks the size (default: the kernel's own, clamped
/// to the device's limits) when it builds the pipeline. Kernels may declare further 32-bit
/// specialisation constants (e.g. clip's largest polygon size, which sizes private arrays).
#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/common/gpu_kernel.h"

namespace cutwork::vulkan {

class Context;
class StorageBuffer;

/// One 32-bit (int, uint or bool) specialisation constant.
struct SpecConstant {
  uint32_t id = 0;
  uint32_t value = 0;
};

class ComputePipeline {
 public:
  /// Builds the pipeline. `workgroup_size` 0 uses kernel.default_workgroup_size; the size is
  /// clamped to the device's maxComputeWorkGroupSize[0] and maxComputeWorkGroupInvocations.
  /// `extra` must not use id 0. Throws DeviceError when the device cannot run the kernel
  /// (no shaderFloat64 for a double-precision kernel, push block too large) or compilation fails.
  ComputePipeline(Context& ctx, const kernels::GpuKernel& kernel, uint32_t workgroup_size = 0,
                  std::span<const SpecConstant> extra = {});
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;

  const kernels::GpuKernel& kernel() const { return m_kernel; }
  uint32_t workgroup_size() const { return m_workgroup_size; }
  /// The specialisation constants beyond id 0, as given.
  const std::vector<SpecConstant>& constants() const { return m_constants; }
  VkPipeline handle() const { return m_pipeline; }
  VkPipelineLayout layout() const { return m_layout; }
  VkDescriptorSetLayout set_layout() const { return m_set_layout; }

 private:
  void release() noexcept;

  Context* m_ctx;
  kernels::GpuKernel m_kernel;
  uint32_t m_workgroup_size = 0;
  std::vector<SpecConstant> m_constants;
  VkShaderModule m_module = VK_NULL_HANDLE;
  VkDescriptorSetLayout m_set_layout = VK_NULL_HANDLE;
  VkPipelineLayout m_layout = VK_NULL_HANDLE;
  VkPipeline m_pipeline = VK_NULL_HANDLE;
};

/// Binds `buffers[i]` to binding i of set 0 for one pipeline layout. Owns its descriptor pool.
/// The buffers are referenced, not owned; they must outlive the set. refresh() re-points the
/// set when a buffer was reallocated (CommandBatch::dispatch calls it before recording).
class DescriptorSet {
 public:
  DescriptorSet(Context& ctx, const ComputePipeline& pipeline, std::vector<StorageBuffer*> buffers);
  ~DescriptorSet();
  DescriptorSet(const DescriptorSet&) = delete;
  DescriptorSet& operator=(const DescriptorSet&) = delete;

  /// Updates the descriptors whose buffer changed since the last update. Must not be called
  /// while a command buffer that uses this set is being recorded or executed after its first
  /// use in that recording (CommandBatch guarantees this by allocating before dispatching).
  void refresh();
  VkDescriptorSet handle() const { return m_set; }
  VkDescriptorSetLayout layout() const { return m_layout; }
  const std::vector<StorageBuffer*>& buffers() const { return m_buffers; }

 private:
  Context* m_ctx;
  VkDescriptorSetLayout m_layout;
  std::vector<StorageBuffer*> m_buffers;
  std::vector<uint64_t> m_generations;
  VkDescriptorPool m_pool = VK_NULL_HANDLE;
  VkDescriptorSet m_set = VK_NULL_HANDLE;
};

}  // namespace cutwork::vulkan

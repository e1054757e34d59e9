#include "host/vulkan/pipeline.h"

#include <algorithm>
#include <string>

#include "host/core/error.h"
#include "host/vulkan/buffer.h"
#include "host/vulkan/context.h"
#include "host/vulkan/vk_check.h"

namespace cutwork::vulkan {

ComputePipeline::ComputePipeline(Context& ctx, const kernels::GpuKernel& kernel,
                                 uint32_t workgroup_size, std::span<const SpecConstant> extra)
    : m_ctx(&ctx), m_kernel(kernel), m_constants(extra.begin(), extra.end()) {
  const std::string name(kernel.name);
  const VkPhysicalDeviceLimits& limits = ctx.limits();
  if (kernel.spirv.empty()) throw DeviceError("Vulkan kernel '" + name + "' has no SPIR-V");
  if (kernel.needs_float64 && !ctx.info().float64) {
    throw DeviceError("Vulkan device '" + ctx.info().name +
                      "' lacks shaderFloat64, which kernel '" + name +
                      "' needs (it computes in double precision); use --device cpu");
  }
  if (kernel.push_constant_bytes < sizeof(kernels::DispatchRange) ||
      kernel.push_constant_bytes % 4 != 0 ||
      kernel.push_constant_bytes > limits.maxPushConstantsSize) {
    throw DeviceError("Vulkan kernel '" + name + "': push block of " +
                      std::to_string(kernel.push_constant_bytes) +
                      " bytes is invalid or exceeds the device's " +
                      std::to_string(limits.maxPushConstantsSize));
  }
  for (const SpecConstant& c : m_constants) {
    if (c.id == 0)
      throw DeviceError("Vulkan kernel '" + name +
                        "': specialisation constant 0 is the workgroup size");
  }
  uint32_t wg = workgroup_size > 0 ? workgroup_size : kernel.default_workgroup_size;
  wg = std::max<uint32_t>(
      1, std::min({wg, limits.maxComputeWorkGroupSize[0], limits.maxComputeWorkGroupInvocations}));
  m_workgroup_size = wg;

  try {
    auto module_info =
        vk_struct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    module_info.codeSize = kernel.spirv.size() * sizeof(uint32_t);
    module_info.pCode = kernel.spirv.data();
    check(vkCreateShaderModule(ctx.device(), &module_info, nullptr, &m_module),
          "vkCreateShaderModule for kernel '" + name + "'");
    ctx.set_name(VK_OBJECT_TYPE_SHADER_MODULE, uint64_t(m_module), name);

    std::vector<VkDescriptorSetLayoutBinding> bindings(kernel.storage_buffers);
    for (uint32_t b = 0; b < kernel.storage_buffers; ++b) {
      bindings[b].binding = b;
      bindings[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      bindings[b].descriptorCount = 1;
      bindings[b].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    auto set_info = vk_struct<VkDescriptorSetLayoutCreateInfo>(
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    set_info.bindingCount = uint32_t(bindings.size());
    set_info.pBindings = bindings.data();
    check(vkCreateDescriptorSetLayout(ctx.device(), &set_info, nullptr, &m_set_layout),
          "vkCreateDescriptorSetLayout for kernel '" + name + "'");

    VkPushConstantRange push{};
    push.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    push.offset = 0;
    push.size = kernel.push_constant_bytes;
    auto layout_info =
        vk_struct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &m_set_layout;
    layout_info.pushConstantRangeCount = 1;
    layout_info.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(ctx.device(), &layout_info, nullptr, &m_layout),
          "vkCreatePipelineLayout for kernel '" + name + "'");

    std::vector<uint32_t> values;
    std::vector<VkSpecializationMapEntry> entries;
    values.push_back(wg);
    entries.push_back({0, 0, sizeof(uint32_t)});
    for (const SpecConstant& c : m_constants) {
      entries.push_back({c.id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
      values.push_back(c.value);
    }
    VkSpecializationInfo spec{};
    spec.mapEntryCount = uint32_t(entries.size());
    spec.pMapEntries = entries.data();
    spec.dataSize = values.size() * sizeof(uint32_t);
    spec.pData = values.data();

    auto info =
        vk_struct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    info.stage.module = m_module;
    info.stage.pName = "main";
    info.stage.pSpecializationInfo = &spec;
    info.layout = m_layout;
    check(vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &info, nullptr, &m_pipeline),
          "vkCreateComputePipelines for kernel '" + name + "'");
    ctx.set_name(VK_OBJECT_TYPE_PIPELINE, uint64_t(m_pipeline), name);
  } catch (...) {
    release();
    throw;
  }
}

ComputePipeline::~ComputePipeline() { release(); }

void ComputePipeline::release() noexcept {
  VkDevice d = m_ctx->device();
  if (m_pipeline != VK_NULL_HANDLE) vkDestroyPipeline(d, m_pipeline, nullptr);
  if (m_layout != VK_NULL_HANDLE) vkDestroyPipelineLayout(d, m_layout, nullptr);
  if (m_set_layout != VK_NULL_HANDLE) vkDestroyDescriptorSetLayout(d, m_set_layout, nullptr);
  if (m_module != VK_NULL_HANDLE) vkDestroyShaderModule(d, m_module, nullptr);
  m_pipeline = VK_NULL_HANDLE;
  m_layout = VK_NULL_HANDLE;
  m_set_layout = VK_NULL_HANDLE;
  m_module = VK_NULL_HANDLE;
}

DescriptorSet::DescriptorSet(Context& ctx, const ComputePipeline& pipeline,
                             std::vector<StorageBuffer*> buffers)
    : m_ctx(&ctx), m_layout(pipeline.set_layout()), m_buffers(std::move(buffers)) {
  const uint32_t n = pipeline.kernel().storage_buffers;
  if (m_buffers.size() != n) {
    throw DeviceError("Vulkan kernel '" + std::string(pipeline.kernel().name) + "' binds " +
                      std::to_string(n) + " buffers, got " + std::to_string(m_buffers.size()));
  }
  m_generations.assign(n, 0);  // generation 0 never names a live buffer: first refresh writes all
  VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, std::max<uint32_t>(n, 1)};
  auto pool_info =
      vk_struct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  check(vkCreateDescriptorPool(ctx.device(), &pool_info, nullptr, &m_pool),
        "vkCreateDescriptorPool");
  auto alloc =
      vk_struct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
  alloc.descriptorPool = m_pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &m_layout;
  const VkResult r = vkAllocateDescriptorSets(ctx.device(), &alloc, &m_set);
  if (r != VK_SUCCESS) {
    vkDestroyDescriptorPool(ctx.device(), m_pool, nullptr);
    check(r, "vkAllocateDescriptorSets");
  }
}

DescriptorSet::~DescriptorSet() {
  if (m_pool != VK_NULL_HANDLE) vkDestroyDescriptorPool(m_ctx->device(), m_pool, nullptr);
}

void DescriptorSet::refresh() {
  std::vector<VkDescriptorBufferInfo> infos(m_buffers.size());
  std::vector<VkWriteDescriptorSet> writes;
  for (size_t i = 0; i < m_buffers.size(); ++i) {
    StorageBuffer& b = *m_buffers[i];
    const VkBuffer handle = b.handle();  // allocates a minimal buffer on first use
    if (b.generation() == m_generations[i]) continue;
    infos[i].buffer = handle;
    infos[i].offset = 0;
    infos[i].range = VK_WHOLE_SIZE;
    auto w = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    w.dstSet = m_set;
    w.dstBinding = uint32_t(i);
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &infos[i];
    writes.push_back(w);
    m_generations[i] = b.generation();
  }
  if (!writes.empty()) {
    vkUpdateDescriptorSets(m_ctx->device(), uint32_t(writes.size()), writes.data(), 0, nullptr);
  }
}

}  // namespace cutwork::vulkan

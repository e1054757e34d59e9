#pragma once
/// What a GPU twin of a kernel hands to the host: a plain description of one compute shader.
///
/// Layering. kernels/ knows nothing above it, yet the Vulkan context (instance, device,
/// buffers, pipelines, dispatch) lives in host/vulkan. The bridge is this POD: each GPU twin
/// (kernels/<op>/<op>_vk.cpp) exposes its SPIR-V — compiled from <op>.comp by glslang at build
/// time and embedded as a uint32_t array — together with its binding and push-constant layout.
/// host/vulkan builds the pipeline from it and dispatches; kernels/ never includes a Vulkan or
/// host header, and host/vulkan never hard-codes a kernel's layout.
///
/// Conventions every cutwork compute shader follows (so that one host dispatcher serves all):
///  - descriptor set 0 holds `storage_buffers` storage buffers at bindings 0 … n−1, std430;
///  - specialisation constant 0 is the workgroup size along x
///    (`layout(local_size_x_id = 0) in;`); further constants are kernel-specific and listed
///    in the kernel's own header;
///  - the push-constant block begins with DispatchRange: the host splits a launch that
///    exceeds the device's workgroup-count limit into chunks and tells each chunk which items
///    it covers; the shader handles item `range.first + gl_GlobalInvocationID.x` when that is
///    below `range.first + range.count` (and must ignore the others);
///  - one invocation per item (pair, face, stencil …); no float atomics anywhere, so results do
///    not depend on scheduling.
#include <cstdint>
#include <span>
#include <string_view>

namespace cutwork::kernels {

/// Head of every push-constant block (std430: two uints, 8 bytes).
struct DispatchRange {
  uint32_t first = 0;  ///< first item this dispatch covers
  uint32_t count = 0;  ///< number of items this dispatch covers
};
static_assert(sizeof(DispatchRange) == 8);

/// One compute shader and its interface. Non-owning: `spirv` points at static storage.
struct GpuKernel {
  std::string_view name;                 ///< for messages and timestamps ("clip", "fill", …)
  std::span<const uint32_t> spirv;       ///< SPIR-V words, entry point "main"
  uint32_t storage_buffers = 0;          ///< bindings 0 … n−1 of set 0, all storage buffers
  uint32_t push_constant_bytes = 0;      ///< size of the push block (≥ sizeof(DispatchRange))
  uint32_t default_workgroup_size = 64;  ///< value of specialisation constant 0 unless overridden
  bool needs_float64 = false;            ///< the shader uses double (requires shaderFloat64)
};

}  // namespace cutwork::kernels

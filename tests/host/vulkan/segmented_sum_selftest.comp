#version 450
// Self-test kernel for host/vulkan (not part of the product): a scaled segmented sum in double,
// one invocation per segment, summed in index order — the same shape as the fill kernel, so it
// exercises storage buffers, the DispatchRange push-constant head, a double in the push block,
// the workgroup-size specialisation constant and shaderFloat64. CPU twin: vulkan_context_vk_test.cpp.
layout(local_size_x_id = 0) in;

layout(std430, set = 0, binding = 0) readonly buffer Offsets { int offsets[]; };
layout(std430, set = 0, binding = 1) readonly buffer Values { double values[]; };
layout(std430, set = 0, binding = 2) writeonly buffer Sums { double sums[]; };

layout(push_constant, std430) uniform Push {
  uint first;  // DispatchRange: this dispatch covers segments [first, first + count)
  uint count;
  double scale;
} pc;

void main() {
  const uint local_index = gl_GlobalInvocationID.x;
  if (local_index >= pc.count) return;
  const uint segment = pc.first + local_index;
  precise double sum = 0.0;
  for (int j = offsets[segment]; j < offsets[segment + 1]; ++j) sum += values[j];
  sums[segment] = pc.scale * sum;
}

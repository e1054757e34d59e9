// GPU twins of the fill kernel: the embedded SPIR-V of fill.comp / fill_pullback.comp.
#include "kernels/fill/fill_vk.h"

#include <cstddef>

#include "fill_pullback_spv.h"  // generated at build time (third_party/cmake/CutworkSpirv.cmake)
#include "fill_spv.h"

namespace cutwork::kernels {

static_assert(offsetof(FillPushVk, params) == 8 && offsetof(FillParams, derivatives) == 8);

GpuKernel fill_gpu_kernel() {
  GpuKernel k;
  k.name = "fill";
  k.spirv = std::span<const uint32_t>(fill_spv);
  k.storage_buffers = kFillBindingCount;
  k.push_constant_bytes = sizeof(FillPushVk);
  k.default_workgroup_size = 64;
  k.needs_float64 = true;
  return k;
}

GpuKernel fill_pullback_gpu_kernel() {
  GpuKernel k;
  k.name = "fill_pullback";
  k.spirv = std::span<const uint32_t>(fill_pullback_spv);
  k.storage_buffers = kPullbackBindingCount;
  k.push_constant_bytes = sizeof(FillPullbackPushVk);
  k.default_workgroup_size = 64;
  k.needs_float64 = true;
  return k;
}

}  // namespace cutwork::kernels

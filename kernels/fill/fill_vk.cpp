// GPU twins of the fill kernel: the embedded SPIR-V of fill.comp / fill_pullback.comp.
#include "kernels/fill/fill_vk.h"

#include <cstddef>

#include "fill_pullback_spv.h"  // generated at build time (third_party/cmake/CutworkSpirv.cmake)
#include "fill_spv.h"

namespace cutwork::kernels {

static_assert(offsetof(FillPushVk, params) == 8 && offsetof(FillParams, derivatives) == 8);

GpuKernel fill_gpu_kernel() {
  return {.name = "fill", .spirv = fill_spv, .storage_buffers = kFillBindingCount, .push_constant_bytes = sizeof(FillPushVk),
          .default_workgroup_size = 64, .needs_float64 = true};
}

GpuKernel fill_pullback_gpu_kernel() {
  return {.name = "fill_pullback", .spirv = fill_pullback_spv, .storage_buffers = kPullbackBindingCount, .push_constant_bytes = sizeof(FillPullbackPushVk),
          .default_workgroup_size = 64, .needs_float64 = true};
}

}  // namespace cutwork::kernels

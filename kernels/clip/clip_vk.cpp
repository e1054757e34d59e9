// GPU twin of the clip kernel: the embedded SPIR-V of clip.comp and its interface.
#include "kernels/clip/clip_vk.h"

#include <cstddef>

#include "clip_spv.h"  // generated from clip.comp at build time (third_party/cmake/CutworkSpirv.cmake)

namespace cutwork::kernels {

// The std430 layouts clip.comp declares; a change on either side must fail to compile here.
static_assert(offsetof(ClipShape, polygon_count) == 4 && offsetof(ClipShape, area) == 8 &&
              offsetof(ClipShape, inner_radius) == 16 && sizeof(ClipShape) == 24);
static_assert(offsetof(ClipStencil, axis_x) == 24 && offsetof(ClipStencil, axis_y) == 48 &&
              offsetof(ClipStencil, d_origin) == 72 && offsetof(ClipStencil, d_axis_x) == 144 &&
              offsetof(ClipStencil, d_axis_y) == 216 && offsetof(ClipStencil, scale) == 288 &&
              offsetof(ClipStencil, shape) == 296 && sizeof(ClipStencil) == 304);
static_assert(offsetof(ClipPair, face) == 4 && sizeof(ClipPair) == 8);
static_assert(offsetof(ClipResult, d_fraction) == 8 && offsetof(ClipResult, overlap_area) == 48 &&
              offsetof(ClipResult, triangle_area) == 56 && sizeof(ClipResult) == 64);
static_assert(offsetof(ClipPushVk, options) == 8 && sizeof(ClipOptions) == 8);

GpuKernel clip_gpu_kernel() {
  return {.name = "clip", .spirv = clip_spv, .storage_buffers = kClipBindingCount, .push_constant_bytes = sizeof(ClipPushVk),
          .default_workgroup_size = 64, .needs_float64 = true};
}

}  // namespace cutwork::kernels

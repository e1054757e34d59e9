#pragma once
/// GPU twin of the clip kernel: clip.comp, compiled to SPIR-V by glslang at build time and
/// embedded in the library, plus the interface host/vulkan needs to run it (bindings, push
/// block, specialisation constants). kernels/ does not dispatch anything itself: the host's
/// Vulkan layer builds the pipeline from clip_gpu_kernel() and records the dispatch (see
/// kernels/common/gpu_kernel.h for the split, host/vulkan/clip_fill_vk.h for the runner).
///
/// Buffers: exactly ClipInputs plus the results, one storage buffer each, std430, with the
/// byte layouts of clip.h's structs (static_asserted in clip_vk.cpp), so the host uploads the
/// CPU twin's arrays unchanged.
///
/// Memory: an invocation keeps O(1) state whatever the polygon size (clip.comp clips as a
/// stream), so the kernel handles every polygon the host accepts (kMaxStencilPolygonVertices)
/// with no size-dependent pipeline.
///
/// Precision: double, like the CPU twins (requires shaderFloat64; see
/// host/vulkan/clip_fill_vk.h for the decision and the parity tolerance).
#include <cstdint>

#include "kernels/clip/clip.h"
#include "kernels/common/gpu_kernel.h"

namespace cutwork::kernels {

/// Storage-buffer bindings of clip.comp, set 0.
enum ClipBinding : uint32_t {
  kClipVertices = 0,  ///< #V×3 double
  kClipFaces,         ///< #F×3 int32
  kClipShapes,        ///< #K ClipShape
  kClipPolygons,      ///< 2·Σn double
  kClipStencils,      ///< #S ClipStencil
  kClipPairs,         ///< #P ClipPair, sorted by face
  kClipResults,       ///< #P ClipResult (written)
  kClipBindingCount
};

/// clip.comp's push block. std430: {uint first; uint count; int derivatives; int early_exits;}.
struct ClipPushVk {
  DispatchRange range;
  ClipOptions options;
};
static_assert(sizeof(ClipPushVk) == 16);

/// clip.comp as a GpuKernel (7 storage buffers, 16-byte push block, needs shaderFloat64; no
/// specialisation constants beyond the workgroup size).
GpuKernel clip_gpu_kernel();

}  // namespace cutwork::kernels

#pragma once
/// GPU twins of the fill kernel and its pull-back: fill.comp and fill_pullback.comp, compiled
/// to SPIR-V by glslang at build time and embedded, plus their binding and push-block layouts
/// (see kernels/common/gpu_kernel.h for the split with host/vulkan, which dispatches them).
///
/// Both are deterministic segmented reductions — one invocation per face (fill) or per
/// stencil (pull-back), summing in list order, no float atomics — so they reproduce fill_ref /
/// fill_pullback_ref whatever the scheduling. Double precision, like the CPU twins.
#include <cstdint>

#include "kernels/common/gpu_kernel.h"
#include "kernels/fill/fill.h"

namespace cutwork::kernels {

/// Storage-buffer bindings of fill.comp, set 0.
enum FillBinding : uint32_t {
  kFillClip = 0,     ///< #P ClipResult (the clip kernel's output, sorted by face)
  kFillFaceOffsets,  ///< #F+1 int32
  kFillAlpha,        ///< #F double (written)
  kFillDAlpha,       ///< #P×5 double (written when derivatives are on)
  kFillBindingCount
};

/// fill.comp's push block. std430: {uint first; uint count; double min_fill; int derivatives;
/// int pad;}.
struct FillPushVk {
  DispatchRange range;
  FillParams params;
};
static_assert(sizeof(FillPushVk) == 24);

/// fill.comp as a GpuKernel (4 storage buffers, one invocation per face).
GpuKernel fill_gpu_kernel();

/// Storage-buffer bindings of fill_pullback.comp, set 0.
enum FillPullbackBinding : uint32_t {
  kPullbackPairs = 0,          ///< #P ClipPair
  kPullbackDAlpha,             ///< #P×5 double (fill's output)
  kPullbackStencilPairs,       ///< #P int32, pair indices grouped by stencil
  kPullbackStencilOffsets,     ///< #S+1 int32
  kPullbackDObjectiveDAlpha,   ///< #F double
  kPullbackDObjectiveDParams,  ///< #S×5 double (written)
  kPullbackBindingCount
};

/// fill_pullback.comp's push block: just the DispatchRange.
struct FillPullbackPushVk {
  DispatchRange range;
};
static_assert(sizeof(FillPullbackPushVk) == 8);

/// fill_pullback.comp as a GpuKernel (6 storage buffers, one invocation per stencil).
GpuKernel fill_pullback_gpu_kernel();

}  // namespace cutwork::kernels

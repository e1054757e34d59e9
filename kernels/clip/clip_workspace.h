#pragma once
/// Private to kernels/clip: the scratch buffers behind ClipWorkspace.
#include <tbb/enumerable_thread_specific.h>

#include <vector>

#include "kernels/clip/clip.h"

namespace cutwork::kernels {

struct ClipWorkspace::Impl {
  std::vector<ClipVertex> serial;                                  ///< clip_ref
  tbb::enumerable_thread_specific<std::vector<ClipVertex>> local;  ///< clip_tbb, one per thread
};

/// Grows `buf` to hold the two ping-pong buffers for polygons of up to `max_count` vertices.
inline ClipVertex* clip_scratch(std::vector<ClipVertex>& buf, int32_t max_count) {
  const size_t need = 2 * size_t(clip_scratch_capacity(max_count));
  if (buf.size() < need) buf.resize(need);
  return buf.data();
}

}  // namespace cutwork::kernels

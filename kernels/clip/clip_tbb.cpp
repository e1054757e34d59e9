// TBB twin of the clip kernel: a parallel loop over pairs, each computed by the same clip_pair
// as the reference twin, so results agree bit for bit whatever the scheduling.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "kernels/clip/clip.h"
#include "kernels/clip/clip_workspace.h"

namespace cutwork::kernels {

void clip_tbb(const ClipInputs& in, const ClipOptions& options, std::span<ClipResult> results,
              ClipWorkspace& workspace) {
  const int32_t max_count = max_polygon_count(in.shapes);
  auto& local = workspace.impl().local;
  const int32_t count = int32_t(in.pairs.size());
  // Grain: a pair costs from ~50 ns (early exit) to a few µs (large non-convex polygon).
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, count, 256),
                    [&](const tbb::blocked_range<int32_t>& range) {
                      ClipVertex* scratch = clip_scratch(local.local(), max_count);
                      for (int32_t i = range.begin(); i < range.end(); ++i) {
                        results[size_t(i)] = clip_pair(in, options, i, scratch);
                      }
                    });
}

}  // namespace cutwork::kernels

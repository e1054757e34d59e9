// TBB twin of the fill kernel: parallel over faces (fill) or stencils (pull-back); each work
// item runs the same body as the reference twin, so the results agree bit for bit.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "kernels/fill/fill.h"

namespace cutwork::kernels {

void fill_tbb(const FillInputs& in, const FillParams& params, const FillOutputs& out) {
  const int32_t faces = int32_t(in.face_offsets.size()) - 1;
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, faces, 1024),
                    [&](const tbb::blocked_range<int32_t>& range) {
                      for (int32_t f = range.begin(); f < range.end(); ++f) {
                        fill_face(in, params, out, f);
                      }
                    });
}

void fill_pullback_tbb(const FillPullbackInputs& in, std::span<const double> d_objective_d_alpha,
                       std::span<double> d_objective_d_params) {
  const int32_t stencils = int32_t(in.stencil_offsets.size()) - 1;
  tbb::parallel_for(tbb::blocked_range<int32_t>(0, stencils, 64),
                    [&](const tbb::blocked_range<int32_t>& range) {
                      for (int32_t s = range.begin(); s < range.end(); ++s) {
                        fill_pullback_stencil(in, d_objective_d_alpha, d_objective_d_params, s);
                      }
                    });
}

}  // namespace cutwork::kernels

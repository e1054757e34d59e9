#pragma once
/// The CPU/GPU parity contract of the clip and fill kernels (stated in
/// host/vulkan/clip_fill_vk.h), as test assertions:
///   |Δ fraction| ≤ 1e-12, |Δ α| ≤ 1e-12;
///   |Δ ∂/∂p_k| ≤ 1e-9 · (|value| + u_k) + 64 ε · (P/A) · u_k, u_k = 1/s for q and s, 1 for φ,
///     P/A the perimeter-to-area ratio of the triangle in stencil units (the round-off floor of
///     the quotient rule: a tiny triangle's derivatives are noise of that size in either twin);
///   areas (m²): |Δ| ≤ 1e-12 · |projected triangle area|.
/// Reports the first violations with their pair index, and how many results were bit-identical
/// (all of them on an IEEE double implementation such as lavapipe, except clipped pairs whose
/// summation order differs, see kernels/clip/clip.comp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <span>
#include <string>

#include "kernels/clip/clip.h"

namespace cutwork::test {

inline constexpr double kFractionTolerance = 1e-12;
inline constexpr double kDerivativeTolerance = 1e-9;
inline constexpr double kRoundOffFloor = 64 * 2.220446049250313e-16;

/// u_k of the contract for a stencil of scale s.
inline double derivative_unit(int k, double scale) { return k < 4 ? 1.0 / scale : 1.0; }

struct ParityStats {
  size_t compared = 0;
  size_t bit_identical = 0;
  size_t partial = 0;  ///< 0 < fraction < 1 (the clipped ones)
  double max_fraction_error = 0;
  double max_derivative_error = 0;  ///< largest |Δ| / tolerance (≤ 1 passes)
};

inline std::ostream& operator<<(std::ostream& os, const ParityStats& s) {
  return os << s.compared << " pairs (" << s.partial << " partial), " << s.bit_identical
            << " bit-identical, max |Δfraction| " << s.max_fraction_error << ", max |Δ∂|/tolerance "
            << s.max_derivative_error;
}

inline ParityStats expect_clip_parity(std::span<const kernels::ClipResult> cpu,
                                      std::span<const kernels::ClipResult> gpu,
                                      const kernels::ClipInputs& in) {
  ParityStats st;
  EXPECT_EQ(cpu.size(), gpu.size());
  if (cpu.size() != gpu.size()) return st;
  int reported = 0;
  auto report = [&](size_t i, const std::string& what, double c, double g) {
    if (reported++ < 8) {
      ADD_FAILURE() << "pair " << i << " (stencil " << in.pairs[i].stencil << ", face "
                    << in.pairs[i].face << "): " << what << " cpu " << c << " gpu " << g << " Δ "
                    << (g - c);
    }
  };
  for (size_t i = 0; i < cpu.size(); ++i) {
    const kernels::ClipResult& c = cpu[i];
    const kernels::ClipResult& g = gpu[i];
    ++st.compared;
    if (std::memcmp(&c, &g, sizeof c) == 0) ++st.bit_identical;
    if (c.fraction > 0 && c.fraction < 1) ++st.partial;
    const double df = std::abs(g.fraction - c.fraction);
    st.max_fraction_error = std::max(st.max_fraction_error, df);
    if (!(df <= kFractionTolerance)) report(i, "fraction", c.fraction, g.fraction);
    const double area_tol = 1e-12 * std::abs(c.triangle_area);
    if (!(std::abs(g.triangle_area - c.triangle_area) <= area_tol))
      report(i, "triangle_area", c.triangle_area, g.triangle_area);
    if (!(std::abs(g.overlap_area - c.overlap_area) <= area_tol))
      report(i, "overlap_area", c.overlap_area, g.overlap_area);
    const double scale = in.stencils[size_t(in.pairs[i].stencil)].scale;
    // Perimeter (3-D, m) over projected area (m²), in stencil units: P_ref / A_ref = P s / A.
    double perimeter = 0;
    for (int k = 0; k < 3; ++k) {
      const size_t f = 3 * size_t(in.pairs[i].face);
      const double* a = &in.vertices[3 * size_t(in.faces[f + size_t(k)])];
      const double* b = &in.vertices[3 * size_t(in.faces[f + size_t((k + 1) % 3)])];
      perimeter += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                             (a[2] - b[2]) * (a[2] - b[2]));
    }
    const double shape_ratio = c.triangle_area > 0 ? perimeter * scale / c.triangle_area : 0.0;
    for (int k = 0; k < kernels::kStencilDofs; ++k) {
      const double u = derivative_unit(k, scale);
      const double tol =
          kDerivativeTolerance * (std::abs(c.d_fraction[k]) + u) + kRoundOffFloor * shape_ratio * u;
      const double e = std::abs(g.d_fraction[k] - c.d_fraction[k]) / tol;
      st.max_derivative_error = std::max(st.max_derivative_error, e);
      if (!(e <= 1.0))
        report(i, "d_fraction[" + std::to_string(k) + "]", c.d_fraction[k], g.d_fraction[k]);
    }
  }
  if (reported > 8) ADD_FAILURE() << "… " << (reported - 8) << " more violations";
  std::cout << "[ parity ] " << st << "\n";
  return st;
}

}  // namespace cutwork::test

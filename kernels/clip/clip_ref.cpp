// Reference twin of the clip kernel, and the per-pair function both CPU twins share.
#include <algorithm>

#include "kernels/clip/clip.h"
#include "kernels/clip/clip_workspace.h"

namespace cutwork::kernels {

ClipWorkspace::ClipWorkspace() : m_impl(std::make_unique<Impl>()) {}
ClipWorkspace::~ClipWorkspace() = default;

int32_t max_polygon_count(std::span<const ClipShape> shapes) {
  int32_t n = 3;
  for (const ClipShape& s : shapes) n = std::max(n, s.polygon_count);
  return n;
}

ClipResult clip_pair(const ClipInputs& in, const ClipOptions& options, int32_t pair_index,
                     ClipVertex* scratch) {
  ClipResult r{};
  const ClipPair pair = in.pairs[size_t(pair_index)];
  const ClipStencil& st = in.stencils[size_t(pair.stencil)];
  const ClipShape& shape = in.shapes[size_t(st.shape)];
  const bool derivatives = options.derivatives != 0;

  // 1. Corners in the reference frame, with ∂w_k/∂p (2×5 each).
  double w[6];
  double jac[3][10];
  for (int k = 0; k < 3; ++k) {
    const int32_t v = in.faces[3 * size_t(pair.face) + size_t(k)];
    project_equidistant(&in.vertices[3 * size_t(v)], st.origin, st.axis_x, st.axis_y, st.scale,
                        st.d_origin, st.d_axis_x, st.d_axis_y, &w[2 * k],
                        derivatives ? jac[k] : nullptr);
  }

  // 2. Projected triangle; back-facing or edge-on triangles contribute nothing.
  const double s2 = st.scale * st.scale;
  const double twice_tri = orient2(w[0], w[1], w[2], w[3], w[4], w[5]);
  r.triangle_area = 0.5 * twice_tri * s2;
  double longest2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int k1 = k == 2 ? 0 : k + 1;
    const double ex = w[2 * k1] - w[2 * k], ey = w[2 * k1 + 1] - w[2 * k + 1];
    longest2 = std::max(longest2, ex * ex + ey * ey);
  }
  if (!(twice_tri > 2e-12 * longest2)) return r;

  // 3. Early exits.
  const int32_t n = shape.polygon_count;
  const double* poly = &in.polygons[2 * size_t(shape.polygon_offset)];
  double overlap = 0.0;
  double grad_overlap[6] = {0, 0, 0, 0, 0, 0};
  bool need_clip = true;
  if (options.early_exits != 0) {
    double edge_fn[3];  // twice the signed area of (w_k, w_k+1, origin)
    bool origin_inside = true;
    for (int k = 0; k < 3; ++k) {
      const int k1 = k == 2 ? 0 : k + 1;
      edge_fn[k] = orient2(w[2 * k], w[2 * k + 1], w[2 * k1], w[2 * k1 + 1], 0.0, 0.0);
      origin_inside = origin_inside && edge_fn[k] >= 0.0;
    }
    if (!origin_inside) {
      double d2 = origin_segment_distance2(w[0], w[1], w[2], w[3]);
      d2 = std::min(d2, origin_segment_distance2(w[2], w[3], w[4], w[5]));
      d2 = std::min(d2, origin_segment_distance2(w[4], w[5], w[0], w[1]));
      if (d2 >= 1.0) return r;  // disjoint from the bounding circle
    }
    const double inner2 = shape.inner_radius * shape.inner_radius;
    const double r0 = w[0] * w[0] + w[1] * w[1], r1 = w[2] * w[2] + w[3] * w[3],
                 r2 = w[4] * w[4] + w[5] * w[5];
    if (std::max(r0, std::max(r1, r2)) <= inner2) {  // triangle ⊂ inscribed disk ⊂ polygon
      r.fraction = 1.0;
      r.overlap_area = r.triangle_area;
      return r;
    }
    if (origin_inside) {
      // Distance from the origin to edge line k is edge_fn[k] / |edge k|.
      bool circle_inside = true;
      for (int k = 0; k < 3; ++k) {
        const int k1 = k == 2 ? 0 : k + 1;
        const double ex = w[2 * k1] - w[2 * k], ey = w[2 * k1 + 1] - w[2 * k + 1];
        circle_inside = circle_inside && edge_fn[k] * edge_fn[k] >= ex * ex + ey * ey;
      }
      if (circle_inside) {  // bounding circle ⊂ triangle: the whole polygon is covered
        overlap = shape.area;
        need_clip = false;
      }
    }
  }

  // 4. Clip.
  if (need_clip) {
    const int32_t cap = clip_scratch_capacity(n);
    overlap = polygon_triangle_overlap(poly, n, w, derivatives ? grad_overlap : nullptr,
                                       scratch, scratch + cap);
  }

  // 5. Fraction and its derivatives.
  const double tri = 0.5 * twice_tri;
  r.fraction = overlap / tri;
  r.overlap_area = overlap * s2;
  if (!derivatives) return r;
  double d_frac_dw[6];
  for (int k = 0; k < 3; ++k) {
    const int kn = k == 2 ? 0 : k + 1, kp = k == 0 ? 2 : k - 1;
    // ∂A_T/∂w_k = ½ (w_{k+1} − w_{k−1})^⊥ with (x, y)^⊥ = (y, −x).
    const double g_x = 0.5 * (w[2 * kn + 1] - w[2 * kp + 1]);
    const double g_y = -0.5 * (w[2 * kn] - w[2 * kp]);
    d_frac_dw[2 * k] = (grad_overlap[2 * k] - r.fraction * g_x) / tri;
    d_frac_dw[2 * k + 1] = (grad_overlap[2 * k + 1] - r.fraction * g_y) / tri;
  }
  for (int j = 0; j < kStencilDofs; ++j) {
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      sum += d_frac_dw[2 * k] * jac[k][j] + d_frac_dw[2 * k + 1] * jac[k][5 + j];
    }
    r.d_fraction[j] = sum;
  }
  return r;
}

void clip_ref(const ClipInputs& in, const ClipOptions& options, std::span<ClipResult> results,
              ClipWorkspace& workspace) {
  ClipVertex* scratch = clip_scratch(workspace.impl().serial, max_polygon_count(in.shapes));
  const int32_t count = int32_t(in.pairs.size());
  for (int32_t i = 0; i < count; ++i) results[size_t(i)] = clip_pair(in, options, i, scratch);
}

}  // namespace cutwork::kernels

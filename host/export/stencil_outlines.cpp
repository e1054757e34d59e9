#include "host/export/stencil_outlines.h"

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork {

std::vector<RowMatX3d> stencil_outlines(const FaceBvh& bvh, const StencilLibrary& shapes,
                                        const TangentField& field, std::span<const StencilParams> stencils) {
  std::vector<RowMatX3d> lines;
  lines.reserve(stencils.size());
  for (size_t i = 0; i < stencils.size(); ++i) {
    const StencilParams& p = stencils[i];
    if (p.type < 0 || p.type >= shapes.size())
      throw InputError(fmt::format("stencil {}: type {} is not among the {} shapes", i, p.type, shapes.size()));
    FrameJacobian jac;
    const Frame frame = compute_frame(bvh, field, p.position, &jac);
    const kernels::ClipStencil cs = make_clip_stencil(frame, jac, p.scale, p.angle, p.type);
    const Vec3 c(cs.origin[0], cs.origin[1], cs.origin[2]);
    const Vec3 ex(cs.axis_x[0], cs.axis_x[1], cs.axis_x[2]);
    const Vec3 ey(cs.axis_y[0], cs.axis_y[1], cs.axis_y[2]);
    const std::vector<Vec2>& polygon = shapes[p.type].polygon;
    RowMatX3d pts(Eigen::Index(polygon.size()), 3);
    for (size_t k = 0; k < polygon.size(); ++k) {
      const Vec3 in_plane = c + p.scale * (polygon[k].x() * ex + polygon[k].y() * ey);
      pts.row(Eigen::Index(k)) = bvh.closest_point(in_plane).point.transpose();
    }
    lines.push_back(std::move(pts));
  }
  return lines;
}

}  // namespace cutwork

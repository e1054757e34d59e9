#include "host/mesh/mirror.h"

#include <cmath>

namespace cutwork {

MirroredMesh mirror_across_plane(const RowMatX3d& vertices, const RowMatX3i& faces, int axis, double c,
                                 double tolerance) {
  MirroredMesh out;
  const Eigen::Index nv = vertices.rows();
  out.image.assign(std::size_t(nv), -1);
  Eigen::Index off = 0;
  for (Eigen::Index v = 0; v < nv; ++v) off += std::abs(vertices(v, axis) - c) > tolerance;
  out.vertices.resize(nv + off, 3);
  out.vertices.topRows(nv) = vertices;
  Eigen::Index next = nv;
  for (Eigen::Index v = 0; v < nv; ++v) {
    if (std::abs(vertices(v, axis) - c) <= tolerance) {
      out.vertices(v, axis) = c;
      out.image[std::size_t(v)] = int(v);
      continue;
    }
    out.vertices.row(next) = vertices.row(v);
    out.vertices(next, axis) = 2 * c - vertices(v, axis);
    out.image[std::size_t(v)] = int(next++);
  }
  out.faces.resize(2 * faces.rows(), 3);
  out.faces.topRows(faces.rows()) = faces;
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    out.faces.row(faces.rows() + f) << out.image[std::size_t(faces(f, 0))], out.image[std::size_t(faces(f, 2))],
        out.image[std::size_t(faces(f, 1))];
  return out;
}

}  // namespace cutwork

#include "host/pattern/pattern_surface.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace cutwork {

RowMatX3d layout_positions(const StencilLayout& layout) {
  RowMatX3d out(Eigen::Index(layout.size()), 3);
  for (size_t i = 0; i < layout.size(); ++i) out.row(Eigen::Index(i)) = layout[i].position.transpose();
  return out;
}

Eigen::VectorXd layout_scales(const StencilLayout& layout) {
  Eigen::VectorXd out(Eigen::Index(layout.size()));
  for (size_t i = 0; i < layout.size(); ++i) out[Eigen::Index(i)] = layout[i].scale;
  return out;
}

Eigen::VectorXi layout_types(const StencilLayout& layout) {
  Eigen::VectorXi out(Eigen::Index(layout.size()));
  for (size_t i = 0; i < layout.size(); ++i) out[Eigen::Index(i)] = layout[i].type;
  return out;
}

std::vector<StencilParams> layout_params(const StencilLayout& layout) {
  std::vector<StencilParams> out;
  out.reserve(layout.size());
  for (const auto& s : layout) out.push_back({s.position, s.scale, s.angle, s.type});
  return out;
}

PatternSurface::PatternSurface(const SurfaceMesh& mesh, const OrientationFieldOptions& field_options,
                               SizingField sizing, double boundary_cell, const Vec3& mirror_planes)
    : m_mesh(&mesh),
      m_bvh(mesh),
      m_field(mesh, m_bvh, field_options),
      m_sizing(std::move(sizing)),
      m_mirror(mirror_planes, mesh.vertices().colwise().mean().transpose()),
      m_boundary(mesh, boundary_cell, &m_mirror) {
  m_area_cdf.resize(size_t(mesh.num_faces()));
  double acc = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    acc += mesh.face_areas()[f];
    m_area_cdf[size_t(f)] = acc;
  }
  m_area = acc;
  // The whole's bounding box on symmetry planes: each plane's axis spans twice the model's reach
  // from the plane.
  Vec3 extent = mesh.bbox_max() - mesh.bbox_min();
  for (int a = 0; a < 3; ++a)
    if (m_mirror.has_plane(a))
      extent[a] = 2 * std::max(std::abs(mesh.bbox_max()[a] - m_mirror.planes()[a]),
                               std::abs(mesh.bbox_min()[a] - m_mirror.planes()[a]));
  m_length = extent.maxCoeff();
}

void PatternSurface::frame_at(const SurfacePoint& p, Vec3& normal, Vec3& tangent,
                              Vec3& bitangent) const {
  normal = phong_normal_and_jacobian(*m_mesh, p, nullptr);
  tangent = m_field.direction(p);
  bitangent = normal.cross(tangent);
}

double PatternSurface::boundary_distance(const Vec3& p, double max_distance) const {
  const auto bp = m_boundary.nearest(p, max_distance);
  return bp ? bp->signed_distance : INFINITY;
}

SurfacePoint PatternSurface::sample(PatternRng& rng) const {
  const double u = rng.uniform() * m_area;
  int f = int(std::upper_bound(m_area_cdf.begin(), m_area_cdf.end(), u) - m_area_cdf.begin());
  f = std::min(f, m_mesh->num_faces() - 1);
  double a = rng.uniform(), b = rng.uniform();
  if (a + b > 1) {  // fold the unit square onto the triangle
    a = 1 - a;
    b = 1 - b;
  }
  SurfacePoint p;
  p.face = f;
  p.bary = Vec3(1 - a - b, a, b);
  return p;
}

}  // namespace cutwork

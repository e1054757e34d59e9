#pragma once
/// What pattern synthesis needs to know about the surface the stencils live on (the base
/// mesh): closest-point projection, frames (Phong normal, orientation-field tangent), the
/// sizing field, the open boundary, and area-weighted sampling. Plus the stencil layout type
/// shared by the initialisations, the objectives and the pattern phase.
#include <limits>
#include <memory>
#include <vector>

#include "host/field/orientation_field.h"
#include "host/field/sizing_field.h"
#include "host/mesh/bvh.h"
#include "host/pattern/boundary_distance.h"
#include "host/pattern/random.h"
#include "host/stencil/frame.h"

namespace cutwork {

/// One stencil of a layout. `position` is on the surface (c = Π(q)); `where` locates it.
struct PlacedStencil {
  Vec3 position = Vec3::Zero();  ///< m
  SurfacePoint where;
  double scale = 0;              ///< bounding-circle radius (m)
  double angle = 0;              ///< rad, counter-clockwise about the normal from the field tangent
  int type = 0;                  ///< stencil shape index (StencilLibrary type id)
};
using StencilLayout = std::vector<PlacedStencil>;

/// #S×3 positions, #S scales, #S types of a layout.
RowMatX3d layout_positions(const StencilLayout& layout);
Eigen::VectorXd layout_scales(const StencilLayout& layout);
Eigen::VectorXi layout_types(const StencilLayout& layout);
/// The layout as stencil parameters (position on the surface, scale, angle, type), #S.
std::vector<StencilParams> layout_params(const StencilLayout& layout);

class PatternSurface {
 public:
  /// Builds the BVH, solves the orientation field and collects the boundary polylines of
  /// `mesh` (which must outlive this object). `boundary_cell` (m) buckets the boundary, best
  /// about the largest stencil reach. `mirror_planes` (LoadCase::symmetry_planes: x = .x(), …; NaN
  /// where none): the mesh is the half (quarter, eighth) of a whole on those planes, which are then
  /// no part of its open boundary and across which the pattern sees its mirror images
  /// (pattern_mirror.h).
  PatternSurface(const SurfaceMesh& mesh, const OrientationFieldOptions& field_options,
                 SizingField sizing, double boundary_cell,
                 const Vec3& mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));
  PatternSurface(const PatternSurface&) = delete;
  PatternSurface& operator=(const PatternSurface&) = delete;

  const SurfaceMesh& mesh() const { return *m_mesh; }
  const FaceBvh& bvh() const { return m_bvh; }
  const OrientationField& field() const { return m_field; }
  const SizingField& sizing() const { return m_sizing; }
  const BoundaryPolylines& boundary() const { return m_boundary; }
  /// The symmetry planes (none unless given).
  const PatternMirror& mirror() const { return m_mirror; }
  double area() const { return m_area; }
  /// The object's length: the longest side of its bounding box (m; of the whole on symmetry
  /// planes); ε is a fraction of it.
  double length() const { return m_length; }

  ClosestPoint project(const Vec3& q) const { return project_to_surface(m_bvh, q); }
  /// Sizing multiplier at a surface point.
  double sizing_at(const SurfacePoint& p) const { return m_sizing.value(*m_mesh, p); }
  /// Frame at a surface point: Phong normal, field tangent, bitangent n × t.
  void frame_at(const SurfacePoint& p, Vec3& normal, Vec3& tangent, Vec3& bitangent) const;
  /// Full frame of a stencil at (unprojected) position q with Jacobians w.r.t. q.
  Frame frame(const Vec3& q, FrameJacobian* jacobian) const {
    return compute_frame(m_bvh, m_field, q, jacobian);
  }
  /// Distance from a surface point to the open boundary, or +inf beyond `max_distance`.
  double boundary_distance(const Vec3& p, double max_distance) const;

  /// A uniformly distributed random surface point (face by area, then uniform barycentrics).
  SurfacePoint sample(PatternRng& rng) const;

 private:
  const SurfaceMesh* m_mesh;
  FaceBvh m_bvh;
  OrientationField m_field;
  SizingField m_sizing;
  PatternMirror m_mirror;
  BoundaryPolylines m_boundary;
  std::vector<double> m_area_cdf;
  double m_area = 0;
  double m_length = 0;
};

}  // namespace cutwork

#pragma once
/// Stencil parameters and frames (paper §4.1).
///
/// A stencil's degrees of freedom are p = (q, s, φ) (kStencilDofs = 5, in this order):
///   q ∈ R³  its position (m); the stencil sits at c = Π(q), the closest point of the surface
///           (kept on it by closest-point projection, so q may drift off the surface between
///           optimiser steps without harm);
///   s > 0   its scale: the radius of its bounding circle (m);
///   φ       its angle (rad), counter-clockwise about the normal from the tangent t.
/// The frame at c: normal n = Phong-interpolated vertex normal, tangent t from a TangentField
/// (the orientation field of the pattern-synthesis issue plugs in here), bitangent b = n × t.
/// Every quantity comes with its Jacobian w.r.t. q, so that derivatives of fill ratios are
/// exact for the full map p → α (closest point, Phong normal and tangent included).
#include <Eigen/Core>
#include <span>

#include "host/core/types.h"
#include "host/mesh/bvh.h"
#include "host/mesh/surface_mesh.h"
#include "kernels/clip/clip.h"

namespace cutwork {

using Mat3 = Eigen::Matrix3d;

/// The state of one stencil. See the file comment for the meaning of each field.
struct StencilParams {
  Vec3 position = Vec3::Zero();  ///< q (m)
  double scale = 0;              ///< s (m), bounding-circle radius
  double angle = 0;              ///< φ (rad)
  int type = 0;                  ///< shape type id (index in the StencilLibrary)
};

/// A stencil's frame at its surface point c = Π(q).
struct Frame {
  SurfacePoint where;            ///< face and barycentrics of c
  Vec3 origin = Vec3::Zero();    ///< c (m)
  Vec3 normal = Vec3::UnitZ();   ///< n, Phong normal
  Vec3 tangent = Vec3::UnitX();  ///< t, from the tangent field (φ = 0 direction)
  Vec3 bitangent = Vec3::UnitY();///< b = n × t
};

/// Jacobians of a Frame w.r.t. q (3×3 each: column j is ∂/∂q_j).
struct FrameJacobian {
  Mat3 d_origin = Mat3::Zero();
  Mat3 d_normal = Mat3::Zero();
  Mat3 d_tangent = Mat3::Zero();
  Mat3 d_bitangent = Mat3::Zero();
};

/// Source of the tangent direction t of stencil frames. Implementations must be smooth where
/// they are differentiated, return the exact Jacobian of what they return, and be safe to call
/// concurrently (the evaluator computes frames in parallel).
class TangentField {
 public:
  virtual ~TangentField() = default;
  /// Unit tangent t ⟂ normal at the surface point `where` (position `point`, Phong normal
  /// `normal`), and if `d_tangent` is not null its Jacobian ∂t/∂q, given the Jacobians of the
  /// point (∂c/∂q) and of the normal (∂n/∂q).
  virtual Vec3 tangent(const SurfaceMesh& mesh, const SurfacePoint& where, const Vec3& point,
                       const Vec3& normal, const Mat3& d_point, const Mat3& d_normal,
                       Mat3* d_tangent) const = 0;
};

/// The default smooth tangent field: a fixed global axis projected onto the tangent plane,
///   t = (a − (a·n) n) / |a − (a·n) n|.
/// It is smooth wherever n is not parallel to a; where |n·a| > switch_cos the field uses the
/// fallback axis instead (a jump in t there, unavoidable for any global field on a closed
/// surface — hairy ball). Defaults: a = x, fallback = y, switch at |n·a| > 0.95 (18°).
class AxisTangentField final : public TangentField {
 public:
  explicit AxisTangentField(const Vec3& axis = Vec3::UnitX(), const Vec3& fallback = Vec3::UnitY(),
                            double switch_cos = 0.95);
  Vec3 tangent(const SurfaceMesh& mesh, const SurfacePoint& where, const Vec3& point,
               const Vec3& normal, const Mat3& d_point, const Mat3& d_normal,
               Mat3* d_tangent) const override;

 private:
  Vec3 m_axis, m_fallback;
  double m_switch_cos;
};

/// Projects q onto the surface (closest point, ties to the lower face index).
/// Throws InputError for a non-finite q or an empty mesh.
ClosestPoint project_to_surface(const FaceBvh& bvh, const Vec3& q);
/// Moves every stencil's position onto the surface (what an optimiser does between steps to
/// keep q on it; the fill ratios do not change, since they only see Π(q)).
void snap_to_surface(const FaceBvh& bvh, std::span<StencilParams> stencils);

/// Phong normal at `where` and its Jacobian w.r.t. the position of the surface point moving in
/// its face's plane (∂n/∂c, 3×3; only its action on in-plane directions is meaningful).
Vec3 phong_normal_and_jacobian(const SurfaceMesh& mesh, const SurfacePoint& where,
                               Mat3* d_normal_d_point);

/// The frame of a stencil at position q, and (if `jacobian` is not null) its Jacobians w.r.t. q.
/// ∂c/∂q follows the closest-point region: inside the face (or q on the surface) the projector
/// I − n_f n_fᵀ onto the face plane; on an edge's region (q off the surface beyond a convex
/// edge) the projector onto the edge line; on a vertex's region zero. q exactly on an edge or
/// vertex of the surface is a kink of Π; the derivative returned is the one-sided derivative
/// within the face the BVH reports.
Frame compute_frame(const FaceBvh& bvh, const TangentField& field, const Vec3& q,
                    FrameJacobian* jacobian);

/// Packs a frame and the stencil's (s, φ, type) into the clip kernel's record: axes
/// e_x = cos φ t + sin φ b, e_y = −sin φ t + cos φ b and their Jacobians.
kernels::ClipStencil make_clip_stencil(const Frame& frame, const FrameJacobian& jacobian,
                                       double scale, double angle, int type);

}  // namespace cutwork

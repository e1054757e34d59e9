#include "host/stencil/frame.h"

#include <cmath>

#include "host/core/error.h"

namespace cutwork {
namespace {

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

void store(const Vec3& v, double* out) {
  for (int i = 0; i < 3; ++i) out[i] = v[i];
}

void store(const Mat3& m, double* out) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) out[3 * i + j] = m(i, j);
}

}  // namespace

AxisTangentField::AxisTangentField(const Vec3& axis, const Vec3& fallback, double switch_cos)
    : m_switch_cos(switch_cos) {
  if (!(axis.norm() > 0) || !(fallback.norm() > 0) || !axis.allFinite() || !fallback.allFinite())
    throw InputError("tangent field: the axes must be finite and non-zero");
  m_axis = axis.normalized();
  m_fallback = fallback.normalized();
  // Where |n·axis| > switch_cos the fallback is used; it must then be far from n.
  if (!(switch_cos > 0 && switch_cos < 1) ||
      std::abs(m_axis.dot(m_fallback)) > std::sqrt(1 - switch_cos * switch_cos) * 0.5)
    throw InputError("tangent field: the fallback axis must be (nearly) perpendicular to the "
                     "main axis and switch_cos in (0, 1)");
}

Vec3 AxisTangentField::tangent(const SurfaceMesh&, const SurfacePoint&, const Vec3&,
                               const Vec3& normal, const Mat3&, const Mat3& d_normal,
                               Mat3* d_tangent) const {
  const Vec3& a = std::abs(normal.dot(m_axis)) > m_switch_cos ? m_fallback : m_axis;
  const double an = a.dot(normal);
  const Vec3 raw = a - an * normal;
  const double len = raw.norm();
  const Vec3 t = raw / len;
  if (d_tangent != nullptr) {
    // ∂raw/∂q = −n (aᵀ ∂n/∂q) − (a·n) ∂n/∂q;  ∂t = (I − t tᵀ) ∂raw / |raw|.
    const Mat3 d_raw = -normal * (a.transpose() * d_normal) - an * d_normal;
    *d_tangent = (Mat3::Identity() - t * t.transpose()) * d_raw / len;
  }
  return t;
}

ClosestPoint project_to_surface(const FaceBvh& bvh, const Vec3& q) {
  if (bvh.mesh() == nullptr || bvh.mesh()->num_faces() == 0)
    throw InputError("stencil projection: the surface has no faces");
  if (!q.allFinite()) throw InputError("stencil projection: the position is not finite");
  return bvh.closest_point(q);
}

void snap_to_surface(const FaceBvh& bvh, std::span<StencilParams> stencils) {
  for (StencilParams& p : stencils) p.position = project_to_surface(bvh, p.position).point;
}

Vec3 phong_normal_and_jacobian(const SurfaceMesh& mesh, const SurfacePoint& where,
                               Mat3* d_normal_d_point) {
  const auto f = mesh.faces().row(where.face);
  const auto& V = mesh.vertices();
  const auto& N = mesh.vertex_normals();
  Vec3 raw = Vec3::Zero();
  for (int k = 0; k < 3; ++k) raw += where.bary[k] * N.row(f[k]).transpose();
  const double len = raw.norm();
  if (len < 1e-12) {  // as SurfaceMesh::phong_normal: opposite normals cancelled
    if (d_normal_d_point != nullptr) d_normal_d_point->setZero();
    return mesh.face_normals().row(where.face).transpose();
  }
  const Vec3 n = raw / len;
  if (d_normal_d_point != nullptr) {
    // ∇b_k = n_f × (P_{k+2} − P_{k+1}) / (2 A): barycentric gradients in the face plane.
    const Vec3 nf = mesh.face_normals().row(where.face).transpose();
    const double twice_area = 2 * mesh.face_areas()[where.face];
    Mat3 d_raw = Mat3::Zero();
    for (int k = 0; k < 3; ++k) {
      const Vec3 p1 = V.row(f[(k + 1) % 3]).transpose(), p2 = V.row(f[(k + 2) % 3]).transpose();
      const Vec3 grad_b = nf.cross(p2 - p1) / twice_area;
      d_raw += N.row(f[k]).transpose() * grad_b.transpose();
    }
    *d_normal_d_point = (Mat3::Identity() - n * n.transpose()) * d_raw / len;
  }
  return n;
}

Frame compute_frame(const FaceBvh& bvh, const TangentField& field, const Vec3& q,
                    FrameJacobian* jacobian) {
  const ClosestPoint cp = project_to_surface(bvh, q);
  const SurfaceMesh& mesh = *bvh.mesh();
  Frame fr;
  fr.where = cp.where;
  fr.origin = cp.point;
  Mat3 dn_dc;
  fr.normal = phong_normal_and_jacobian(mesh, cp.where, jacobian ? &dn_dc : nullptr);

  Mat3 C = Mat3::Zero();
  if (jacobian != nullptr) {
    const int face = cp.where.face;
    const Vec3 nf = mesh.face_normals().row(face).transpose();
    int zeros = 0;
    for (int k = 0; k < 3; ++k) zeros += cp.where.bary[k] == 0.0;
    const bool on_surface = cp.squared_distance <= 1e-24 * mesh.face_areas()[face];
    if (on_surface || zeros == 0) {
      C = Mat3::Identity() - nf * nf.transpose();
    } else if (zeros == 1) {
      int i = -1, j = -1;
      for (int k = 0; k < 3; ++k) {
        if (cp.where.bary[k] == 0.0) continue;
        (i < 0 ? i : j) = k;
      }
      const auto f = mesh.faces().row(face);
      const Vec3 e = (mesh.vertices().row(f[j]) - mesh.vertices().row(f[i])).transpose().normalized();
      C = e * e.transpose();
    }
    jacobian->d_origin = C;
    jacobian->d_normal = dn_dc * C;
  }
  fr.tangent = field.tangent(mesh, cp.where, fr.origin, fr.normal, C,
                             jacobian ? jacobian->d_normal : Mat3::Zero().eval(),
                             jacobian ? &jacobian->d_tangent : nullptr);
  fr.bitangent = fr.normal.cross(fr.tangent);
  if (jacobian != nullptr) {
    jacobian->d_bitangent =
        skew(fr.normal) * jacobian->d_tangent - skew(fr.tangent) * jacobian->d_normal;
  }
  return fr;
}

kernels::ClipStencil make_clip_stencil(const Frame& frame, const FrameJacobian& jacobian,
                                       double scale, double angle, int type) {
  const double c = std::cos(angle), s = std::sin(angle);
  kernels::ClipStencil st{};
  store(frame.origin, st.origin);
  store((c * frame.tangent + s * frame.bitangent).eval(), st.axis_x);
  store((-s * frame.tangent + c * frame.bitangent).eval(), st.axis_y);
  store(jacobian.d_origin, st.d_origin);
  store((c * jacobian.d_tangent + s * jacobian.d_bitangent).eval(), st.d_axis_x);
  store((-s * jacobian.d_tangent + c * jacobian.d_bitangent).eval(), st.d_axis_y);
  st.scale = scale;
  st.shape = type;
  return st;
}

}  // namespace cutwork

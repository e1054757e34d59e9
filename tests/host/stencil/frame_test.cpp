// Stencil frames: closest-point projection, Phong normal, tangent field, and their Jacobians
// w.r.t. q against central differences (error vs step printed on failure).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "host/core/error.h"
#include "host/surfaces/generators.h"
#include "host/stencil/frame.h"

namespace cutwork {
namespace {

Vec3 random_surface_point(const SurfaceMesh& mesh, std::mt19937& rng, double min_bary) {
  std::uniform_int_distribution<int> face(0, mesh.num_faces() - 1);
  std::uniform_real_distribution<double> u(0, 1);
  const int f = face(rng);
  Vec3 b;
  do {
    b = Vec3(u(rng), u(rng), 0);
    b.z() = 1 - b.x() - b.y();
  } while (b.minCoeff() < min_bary);
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 3; ++k) p += b[k] * mesh.vertices().row(mesh.faces()(f, k)).transpose();
  return p;
}

/// Compares the four Jacobians of compute_frame at q with central differences.
/// Returns false (and prints the error table) on a mismatch beyond 1e-6 relative.
bool frame_jacobian_matches(const FaceBvh& bvh, const TangentField& field, const Vec3& q,
                            double h, int* skipped) {
  FrameJacobian J;
  const Frame f0 = compute_frame(bvh, field, q, &J);
  auto column = [&](const Frame& fr, int which) -> Vec3 {
    switch (which) {
      case 0: return fr.origin;
      case 1: return fr.normal;
      case 2: return fr.tangent;
      default: return fr.bitangent;
    }
  };
  const Mat3* analytic[4] = {&J.d_origin, &J.d_normal, &J.d_tangent, &J.d_bitangent};
  bool ok = true;
  for (int j = 0; j < 3; ++j) {
    Vec3 qp = q, qm = q;
    qp[j] += h;
    qm[j] -= h;
    const Frame fp = compute_frame(bvh, field, qp, nullptr), fm = compute_frame(bvh, field, qm, nullptr);
    if (fp.where.face != f0.where.face || fm.where.face != f0.where.face) {
      ++*skipped;
      continue;
    }
    for (int which = 0; which < 4; ++which) {
      const Vec3 fd = (column(fp, which) - column(fm, which)) / (2 * h);
      const Vec3 an = analytic[which]->col(j);
      const double ref = std::max({fd.norm(), an.norm(), 1e-3});
      if ((fd - an).norm() > 1e-6 * ref) {
        ok = false;
        std::printf("quantity %d, d/dq_%d: analytic (%g %g %g)\n  step    error\n", which, j,
                    an.x(), an.y(), an.z());
        for (double s = 1e-2; s >= 1e-10; s /= 10) {
          Vec3 a = q, b = q;
          a[j] += s;
          b[j] -= s;
          const Vec3 f2 = (column(compute_frame(bvh, field, a, nullptr), which) -
                           column(compute_frame(bvh, field, b, nullptr), which)) /
                          (2 * s);
          std::printf("  %.0e  %.3e\n", s, (f2 - an).norm() / ref);
        }
      }
    }
  }
  return ok;
}

TEST(StencilFrame, OrthonormalPhongFrameOnTheSurface) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.012);
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  std::mt19937 rng(1);
  for (int i = 0; i < 50; ++i) {
    const Vec3 q = random_surface_point(mesh, rng, 0.0);
    const Frame fr = compute_frame(bvh, field, q, nullptr);
    EXPECT_LE((fr.origin - q).norm(), 1e-14);
    EXPECT_NEAR(fr.normal.norm(), 1, 1e-14);
    EXPECT_NEAR(fr.tangent.norm(), 1, 1e-14);
    EXPECT_NEAR(fr.normal.dot(fr.tangent), 0, 1e-14);
    EXPECT_LE((fr.bitangent - fr.normal.cross(fr.tangent)).norm(), 1e-15);
    EXPECT_LE((fr.normal - mesh.phong_normal(fr.where)).norm(), 1e-15);
  }
}

TEST(StencilFrame, JacobiansMatchCentralDifferencesOnTheBowl) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.012);
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  std::mt19937 rng(2);
  int skipped = 0, checked = 0;
  for (int i = 0; i < 40; ++i) {
    Vec3 q = random_surface_point(mesh, rng, 0.1);
    // Half of them off the surface, along the face normal (same region: the face interior).
    if (i % 2) {
      const Frame fr = compute_frame(bvh, field, q, nullptr);
      q += 0.002 * mesh.face_normals().row(fr.where.face).transpose();
    }
    // h ≈ ε^(1/3) · (bowl size 0.3 m): below it round-off, not truncation, dominates the central
    // difference of O(1) quantities (the printed table shows where).
    EXPECT_TRUE(frame_jacobian_matches(bvh, field, q, 1e-6, &skipped)) << "point " << i;
    ++checked;
  }
  EXPECT_LE(skipped, 6);
}

TEST(StencilFrame, JacobiansBeyondTheRimFollowTheClosestPointRegion) {
  // Points beyond the bowl's rim project onto a rim edge (or vertex): ∂c/∂q is the projector
  // onto the edge line (or zero).
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.012);
  const FaceBvh bvh(mesh);
  const AxisTangentField field;
  int skipped = 0, edge = 0;
  for (int i = 0; i < 24; ++i) {
    const double a = 0.37 + 2 * 3.14159265 * i / 24;
    const Vec3 q(0.17 * std::cos(a), 0.17 * std::sin(a), 0.09);
    FrameJacobian J;
    const Frame fr = compute_frame(bvh, field, q, &J);
    const double rank = J.d_origin.trace();  // a projector's trace is its rank
    EXPECT_TRUE(std::abs(rank - 1) < 1e-12 || std::abs(rank) < 1e-12) << rank;
    edge += std::abs(rank - 1) < 1e-12;
    // h ≈ ε^(1/3) · (bowl size 0.3 m): below it round-off, not truncation, dominates the central
    // difference of O(1) quantities (the printed table shows where).
    EXPECT_TRUE(frame_jacobian_matches(bvh, field, q, 1e-6, &skipped)) << "point " << i;
    (void)fr;
  }
  EXPECT_GT(edge, 12);
  EXPECT_LE(skipped, 6);
}

TEST(StencilFrame, AxisFieldFallsBackNearThePole) {
  // A plane whose normal is x-ish: the x axis cannot be projected, the fallback (y) is used.
  RowMatX3d v(3, 3);
  v << 0, 0, 0, 0, 1, 0, 0.1, 0, 1;
  RowMatX3i f(1, 3);
  f << 0, 1, 2;
  const SurfaceMesh mesh(v, f, "tilted");
  const FaceBvh bvh(mesh);
  const Frame fr = compute_frame(bvh, AxisTangentField(), Vec3(0.03, 0.3, 0.3), nullptr);
  EXPECT_GT(std::abs(fr.normal.x()), 0.95);
  const Vec3 expected = (Vec3::UnitY() - fr.normal.y() * fr.normal).normalized();
  EXPECT_LE((fr.tangent - expected).norm(), 1e-14);
  EXPECT_THROW(AxisTangentField(Vec3::UnitX(), Vec3::UnitX()), InputError);
  EXPECT_THROW(AxisTangentField(Vec3::Zero()), InputError);
}

TEST(StencilFrame, ClipStencilRecordRotatesTheAxes) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.012);
  const FaceBvh bvh(mesh);
  FrameJacobian J;
  const Frame fr = compute_frame(bvh, AxisTangentField(), Vec3(0.02, 0.01, 0.0), &J);
  const double phi = 0.7;
  const kernels::ClipStencil st = make_clip_stencil(fr, J, 0.03, phi, 2);
  const Vec3 ex(st.axis_x[0], st.axis_x[1], st.axis_x[2]);
  const Vec3 ey(st.axis_y[0], st.axis_y[1], st.axis_y[2]);
  EXPECT_NEAR(ex.dot(fr.tangent), std::cos(phi), 1e-15);
  EXPECT_NEAR(ex.dot(fr.bitangent), std::sin(phi), 1e-15);
  EXPECT_LE((ex.cross(ey) - fr.normal).norm(), 1e-15);
  EXPECT_EQ(st.scale, 0.03);
  EXPECT_EQ(st.shape, 2);
  EXPECT_EQ(st.d_origin[3 * 1 + 2], J.d_origin(1, 2));  // row-major
}

}  // namespace
}  // namespace cutwork

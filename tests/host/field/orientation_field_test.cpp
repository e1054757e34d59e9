// The orientation field: constant on a flat plate without strokes, smooth on curved shapes,
// aligned to sketch strokes (within 5° near a stroke), exact tangent Jacobian, and the
// symmetry helpers.
#include <complex>
#include <numbers>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "host/core/error.h"
#include "host/field/orientation_field.h"
#include "host/mesh/mirror.h"
#include "host/pattern/random.h"
#include "host/surfaces/generators.h"
#include "host/stencil/stencil_shape.h"
#include "../pattern/pattern_test_util.h"

namespace cutwork {
namespace {

/// Smallest angle between two directions modulo 2π/N (radians, in [0, π/N]).
double angle_mod(const Vec3& a, const Vec3& b, const Vec3& n, int N) {
  const double th = std::atan2(n.dot(a.cross(b)), a.dot(b));
  const double period = 2 * std::numbers::pi / N;
  double r = std::fmod(std::abs(th), period);
  return std::min(r, period - r);
}

SurfaceMesh shape(const char* name) {
  return generate_shape(name, {}, find_shape(name)->base_edge_length);
}

TEST(OrientationField, ConstantAlongTheLongestAxisOnAFlatPlate) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.01);
  const FaceBvh bvh(mesh);
  for (int N : {1, 2, 4, 5}) {
    OrientationFieldOptions o;
    o.symmetry = N;
    const OrientationField field(mesh, bvh, o);
    PatternRng rng(1);
    for (int k = 0; k < 200; ++k) {
      SurfacePoint p{rng.below(mesh.num_faces()), Vec3::Zero()};
      const double a = rng.uniform(), b = rng.uniform() * (1 - a);
      p.bary = Vec3(1 - a - b, a, b);
      const Vec3 t = field.direction(p);
      EXPECT_NEAR(t.norm(), 1.0, 1e-12);
      EXPECT_LT(angle_mod(t, Vec3::UnitX(), Vec3::UnitZ(), N), 1e-9) << "N = " << N;
    }
  }
}

TEST(OrientationField, SmoothOnCurvedShapes) {
  // Across every interior edge the two faces' directions (transported by unfolding, measured
  // modulo 2π/N) differ little: the bowl and the vault are disks/annuli with no forced
  // singularity, so a smooth field exists and the solver must find one.
  for (const char* name : {"bowl", "pavilion"}) {
    const SurfaceMesh mesh = shape(name);
    const FaceBvh bvh(mesh);
    OrientationFieldOptions o;
    o.symmetry = 4;
    const OrientationField field(mesh, bvh, o);
    double worst = 0, mean = 0;
    int count = 0;
    for (int e = 0; e < mesh.num_edges(); ++e) {
      const int f = mesh.edge_faces()(e, 0), g = mesh.edge_faces()(e, 1);
      if (g < 0) continue;
      const Vec3 edge = (mesh.vertices().row(mesh.edges()(e, 1)) - mesh.vertices().row(mesh.edges()(e, 0)))
                            .transpose()
                            .normalized();
      Vec3 e1f, e2f, e1g, e2g;
      field.face_basis(f, e1f, e2f);
      field.face_basis(g, e1g, e2g);
      // Angles relative to the shared edge are comparable across the hinge.
      const double af = field.face_angles()[f] - std::atan2(edge.dot(e2f), edge.dot(e1f));
      const double ag = field.face_angles()[g] - std::atan2(edge.dot(e2g), edge.dot(e1g));
      const double period = 2 * std::numbers::pi / 4;
      double d = std::fmod(std::abs(af - ag), period);
      d = std::min(d, period - d);
      worst = std::max(worst, d);
      mean += d;
      ++count;
    }
    mean /= count;
    EXPECT_LT(mean * 180 / std::numbers::pi, 1.0) << name;
    EXPECT_LT(worst * 180 / std::numbers::pi, 10.0) << name;
  }
}

TEST(OrientationField, SketchStrokeAlignmentWithin5Degrees) {
  // One straight stroke across the plate at 30° to the x axis (the direction the field takes
  // without strokes). Within one stencil radius of the stroke the field must be within 5° of
  // it (modulo 2π/N); without the stroke it is 30° off there, so the test can fail.
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.005);
  const FaceBvh bvh(mesh);
  const Vec3 a(0.03, 0.02, 0), b = a + 0.15 * Vec3(std::cos(std::numbers::pi / 6), std::sin(std::numbers::pi / 6), 0);
  const double stencil_radius = 0.008;
  for (int N : {1, 2, 4}) {
    OrientationFieldOptions with;
    with.symmetry = N;
    with.strokes = {SketchStroke{{a, a + 0.5 * (b - a), b}}};
    OrientationFieldOptions without = with;
    without.strokes.clear();
    const OrientationField fs(mesh, bvh, with), f0(mesh, bvh, without);
    EXPECT_FALSE(fs.stroke_faces().empty());
    const Vec3 dir = (b - a).normalized();
    double worst = 0, worst0 = 0;
    int near = 0;
    PatternRng rng(2);
    for (int k = 0; k < 4000; ++k) {
      SurfacePoint p{rng.below(mesh.num_faces()), Vec3::Zero()};
      const double u = rng.uniform(), v = rng.uniform() * (1 - u);
      p.bary = Vec3(1 - u - v, u, v);
      const Vec3 x = mesh.point(p);
      const double t = std::clamp((x - a).dot(dir), 0.0, (b - a).norm());
      if ((x - (a + t * dir)).norm() > stencil_radius) continue;
      ++near;
      worst = std::max(worst, angle_mod(fs.direction(p), dir, Vec3::UnitZ(), N));
      worst0 = std::max(worst0, angle_mod(f0.direction(p), dir, Vec3::UnitZ(), N));
    }
    ASSERT_GT(near, 100);
    EXPECT_LT(worst * 180 / std::numbers::pi, 5.0) << "N = " << N;
    EXPECT_GT(worst0 * 180 / std::numbers::pi, 5.0) << "N = " << N << ": the stroke test would pass without a stroke";
  }
}

TEST(OrientationField, AHalfOnASymmetryPlaneHasItsWholesField) {
  // A curved surface symmetric about y = 0 and a stroke on its half y ≥ 0: the whole (the half and
  // its mirror image, the stroke and its image) has a symmetric field, which the half solved with its
  // plane must reproduce face by face; with the plane a free boundary it does not.
  const SurfaceMesh flat = test::flat_plate(0.2, 0.08, 0.006);
  RowMatX3d v = flat.vertices();
  for (int i = 0; i < v.rows(); ++i) {
    const double x = v(i, 0) - 0.1, y = v(i, 1);
    v(i, 2) = 1.5 * x * x - 4.0 * y * y + 0.8 * x * y * y;  // even in y
  }
  const SurfaceMesh half(v, flat.faces(), "half");
  const MirroredMesh m = mirror_across_plane(v, flat.faces(), 1, 0.0, 1e-12);
  const SurfaceMesh whole(m.vertices, m.faces, "whole");
  const FaceBvh half_bvh(half), whole_bvh(whole);
  auto on = [&](double x, double y) { return Vec3(x, y, 1.5 * (x - 0.1) * (x - 0.1) - 4.0 * y * y + 0.8 * (x - 0.1) * y * y); };
  std::vector<Vec3> stroke;
  for (int k = 0; k <= 8; ++k) stroke.push_back(on(0.03 + 0.018 * k, 0.02 + 0.04 * std::sin(0.3 * k)));
  std::vector<Vec3> image = stroke;
  for (Vec3& p : image) p.y() = -p.y();
  for (int N : {1, 4, 5}) {
    OrientationFieldOptions o;
    o.symmetry = N;
    o.strokes = {SketchStroke{stroke}};
    OrientationFieldOptions ow = o;
    ow.strokes.push_back(SketchStroke{image});
    OrientationFieldOptions oh = o;
    oh.mirror_planes = Vec3(NAN, 0.0, NAN);
    const OrientationField fw(whole, whole_bvh, ow), fh(half, half_bvh, oh), free_half(half, half_bvh, o);
    double worst = 0, worst_free = 0;
    for (int f = 0; f < half.num_faces(); ++f) {
      const std::complex<double> uw = std::polar(1.0, N * fw.face_angles()[f]);
      worst = std::max(worst, std::abs(std::polar(1.0, N * fh.face_angles()[f]) - uw));
      worst_free = std::max(worst_free, std::abs(std::polar(1.0, N * free_half.face_angles()[f]) - uw));
    }
    EXPECT_LT(worst, 1e-8) << "N = " << N;
    EXPECT_GT(worst_free, 1e-3) << "N = " << N << ": the free half would pass";
  }
}

TEST(OrientationField, TheHalfOfASquarePlateKeepsTheWholesAxis) {
  // The half of a 0.2 m square plate is 0.2 (y) × 0.1 (x): alone its field runs along y; as the half
  // on the plane x = 0 it runs along x, as the whole's does.
  SurfaceMesh half = test::flat_plate(0.1, 0.2, 0.01);
  const FaceBvh bvh(half);
  OrientationFieldOptions o;
  o.symmetry = 2;
  const OrientationField alone(half, bvh, o);
  o.mirror_planes = Vec3(0.0, NAN, NAN);
  const OrientationField as_half(half, bvh, o);
  const SurfacePoint p{0, Vec3::Constant(1.0 / 3)};
  EXPECT_LT(angle_mod(alone.direction(p), Vec3::UnitY(), Vec3::UnitZ(), 2), 1e-9);
  EXPECT_LT(angle_mod(as_half.direction(p), Vec3::UnitX(), Vec3::UnitZ(), 2), 1e-9);
}

TEST(OrientationField, StrokeFarFromTheSurfaceIsAnError) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.01);
  const FaceBvh bvh(mesh);
  OrientationFieldOptions o;
  o.strokes = {SketchStroke{{Vec3(0.05, 0.05, 0), Vec3(0.1, 0.05, 0.5)}}};
  try {
    OrientationField f(mesh, bvh, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pattern.strokes[0] point 1"), std::string::npos) << e.what();
  }
}

TEST(OrientationField, TangentJacobianMatchesFiniteDifferences) {
  // d t / d x inside faces of the bowl and the chair, and through the TangentField interface
  // (compute_frame: ∂t/∂q including the closest-point projection).
  for (const char* name : {"bowl", "chair"}) {
    const SurfaceMesh mesh = shape(name);
    const FaceBvh bvh(mesh);
    OrientationFieldOptions o;
    o.symmetry = 1;
    o.strokes = {};
    const OrientationField field(mesh, bvh, o);
    PatternRng rng(3);
    for (int k = 0; k < 50; ++k) {
      const int f = rng.below(mesh.num_faces());
      const double u = rng.uniform(0.1, 0.8), v = rng.uniform(0.05, 0.9 - u);
      const SurfacePoint p{f, Vec3(1 - u - v, u, v)};
      const Vec3 x0 = mesh.point(p);
      const Vec3 n = mesh.face_normals().row(f).transpose();
      // t is a unit vector varying over about an edge length: derivatives ~ 1/edge. Steps of
      // 1e-4 edge keep central differences accurate to ~1e-8 of that scale.
      const double edge = mesh.mean_edge_length();
      const double h = 1e-4 * edge;
      auto fq = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) -> double {
        // Scalar probe: w · t(x) for a fixed w, so the gradient is (∂t/∂x)ᵀ w.
        const Vec3 w(0.3, -0.7, 0.5);
        Eigen::Matrix3d J;
        SurfacePoint sp = bvh.closest_point(Vec3(x)).where;
        const Vec3 t = field.direction(sp, &J);
        if (g) *g = (Eigen::Matrix3d::Identity() - n * n.transpose()) * J.transpose() * w;
        return w.dot(t);
      };
      // Directional derivatives within the face plane only (the map ignores normal motion).
      auto fq_plane = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g) -> double {
        Vec3 e1, e2;
        field.face_basis(f, e1, e2);
        const Vec3 x = x0 + y[0] * e1 + y[1] * e2;
        Eigen::VectorXd g3;
        const double val = fq(x, g ? &g3 : nullptr);
        if (g) {
          g->resize(2);
          (*g)[0] = g3.dot(e1);
          (*g)[1] = g3.dot(e2);
        }
        return val;
      };
      EXPECT_TRUE(test::gradient_matches(fq_plane, Eigen::Vector2d::Zero(), h, 1e-6,
                                         std::string("dt/dx on ") + name, 1e-2 / edge));
      // Through compute_frame: rows of ∂t/∂q against differences of t(q).
      const Vec3 q = x0 + 0.1 * mesh.mean_edge_length() * n;
      FrameJacobian fj;
      compute_frame(bvh, field, q, &fj);
      for (int c = 0; c < 3; ++c) {
        auto tc = [&](const Eigen::VectorXd& y, Eigen::VectorXd* g) -> double {
          FrameJacobian j2;
          const Frame fr = compute_frame(bvh, field, Vec3(y), g ? &j2 : nullptr);
          if (g) *g = j2.d_tangent.row(c).transpose();
          return fr.tangent[c];
        };
        EXPECT_TRUE(test::gradient_matches(tc, Eigen::VectorXd(q), h, 1e-6,
                                           std::string("compute_frame dt/dq on ") + name, 1e-2 / edge));
      }
    }
  }
}

TEST(OrientationField, SymmetryOrders) {
  EXPECT_EQ(polygon_symmetry_order(make_builtin_stencil("circle", {}, "c").polygon) > 12, true);
  EXPECT_EQ(polygon_symmetry_order(make_builtin_stencil("square", {}, "s").polygon), 4);
  EXPECT_EQ(polygon_symmetry_order(make_builtin_stencil("star", {{"points", 5}}, "s").polygon), 5);
  EXPECT_EQ(polygon_symmetry_order(make_builtin_stencil("apple", {}, "a").polygon), 1);
  EXPECT_EQ(polygon_symmetry_order({Vec2(1, 0), Vec2(0, 1), Vec2(-1, 0), Vec2(0, -0.5)}), 1);
  // gcd rule, circles (order > 12) free, cap at divisors ≤ 6, exemplar symmetry.
  EXPECT_EQ(field_symmetry_for({64}, 0), 4);
  EXPECT_EQ(field_symmetry_for({64}, 2), 2);
  EXPECT_EQ(field_symmetry_for({5, 64}, 0), 5);
  EXPECT_EQ(field_symmetry_for({5}, 2), 1);
  EXPECT_EQ(field_symmetry_for({8}, 0), 4);
  EXPECT_EQ(field_symmetry_for({12}, 0), 6);
  EXPECT_EQ(field_symmetry_for({4, 6}, 0), 2);
  EXPECT_EQ(field_symmetry_for({1}, 4), 1);
}

}  // namespace
}  // namespace cutwork

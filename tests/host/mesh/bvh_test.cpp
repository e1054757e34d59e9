#include "host/mesh/bvh.h"

#include <gtest/gtest.h>

#include <random>

#include "tests/host/mesh/mesh_fixtures.h"

namespace cutwork {
namespace {

/// Independent reference for the closest point on a triangle: the plane projection when it
/// falls inside, otherwise the best of the three edge segments (different arithmetic from
/// Ericson's region test).
double reference_squared_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 q = p - n * (p - a).dot(n) / n.squaredNorm();
  const double area = n.norm();
  const double u = (b - q).cross(c - q).dot(n) / (area * area), v = (c - q).cross(a - q).dot(n) / (area * area);
  const double w = 1 - u - v;
  if (u >= 0 && v >= 0 && w >= 0) return (p - q).squaredNorm();
  auto segment = [&](const Vec3& s, const Vec3& e) {
    const double t = std::clamp((p - s).dot(e - s) / (e - s).squaredNorm(), 0.0, 1.0);
    return (p - (s + t * (e - s))).squaredNorm();
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

TEST(ClosestPointOnTriangle, EveryVoronoiRegion) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  struct Case {
    Vec3 p, expected_bary;
  };
  const Case cases[] = {
      {{-1, -1, 3}, {1, 0, 0}},     // vertex a
      {{3, -0.5, -1}, {0, 1, 0}},   // vertex b
      {{-0.5, 3, 2}, {0, 0, 1}},    // vertex c
      {{0.5, -1, 1}, {0.75, 0.25, 0}},  // edge ab
      {{-1, 1.5, 0}, {0.25, 0, 0.75}},  // edge ca
      {{2, 2, 5}, {0, 0.5, 0.5}},       // edge bc
      {{0.5, 0.5, -4}, {0.5, 0.25, 0.25}},  // face interior
  };
  for (const Case& t : cases) {
    const ClosestPoint r = closest_point_on_triangle(t.p, a, b, c);
    EXPECT_NEAR((r.where.bary - t.expected_bary).norm(), 0, 1e-15) << t.p.transpose();
    const Vec3 q = t.expected_bary[0] * a + t.expected_bary[1] * b + t.expected_bary[2] * c;
    EXPECT_NEAR((r.point - q).norm(), 0, 1e-15);
    EXPECT_NEAR(r.squared_distance, (t.p - q).squaredNorm(), 1e-14);
  }
}

TEST(ClosestPointOnTriangle, MatchesReferenceOnRandomTriangles) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0, 1);
  auto rand3 = [&] { return Vec3(g(rng), g(rng), g(rng)); };
  for (int i = 0; i < 20000; ++i) {
    const Vec3 a = rand3(), b = rand3(), c = rand3(), p = 2 * rand3();
    const ClosestPoint r = closest_point_on_triangle(p, a, b, c);
    const double expected = reference_squared_distance(p, a, b, c);
    ASSERT_NEAR(r.squared_distance, expected, 1e-11 * (1 + expected)) << "case " << i;
    ASSERT_NEAR(r.where.bary.sum(), 1, 1e-14);
    ASSERT_GE(r.where.bary.minCoeff(), -1e-15);
    ASSERT_NEAR((r.point - (r.where.bary[0] * a + r.where.bary[1] * b + r.where.bary[2] * c)).norm(), 0, 1e-14);
  }
}

TEST(ClosestPointOnTriangle, DegenerateTriangleFallsBackToEdges) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(2, 0, 0);  // collinear
  const ClosestPoint r = closest_point_on_triangle(Vec3(1.5, 1, 0), a, b, c);
  EXPECT_NEAR(r.squared_distance, 1.0, 1e-15);
  EXPECT_NEAR((r.point - Vec3(1.5, 0, 0)).norm(), 0, 1e-15);
  EXPECT_TRUE(r.where.bary.allFinite());
}

class BvhVsBruteForce : public ::testing::TestWithParam<int> {};

TEST_P(BvhVsBruteForce, ClosestPointAndBallQueries) {
  const SurfaceMesh mesh = GetParam() == 0 ? test::make(test::bumpy_grid(40)) : test::make(test::icosphere(4));
  const FaceBvh bvh(mesh);
  EXPECT_EQ(bvh.mesh(), &mesh);
  std::mt19937 rng(2024 + GetParam());
  const Vec3 lo = mesh.bbox_min() - Vec3::Constant(0.3), hi = mesh.bbox_max() + Vec3::Constant(0.3);
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<int> any_face(0, mesh.num_faces() - 1);
  std::vector<int> fast, slow;
  for (int q = 0; q < 1000; ++q) {
    Vec3 p;
    if (q % 2 == 0) {  // anywhere around the surface
      p = lo + (hi - lo).cwiseProduct(Vec3(unit(rng), unit(rng), unit(rng)));
    } else {  // just off the surface, where neighbouring faces compete
      const int f = any_face(rng);
      Vec3 bary(unit(rng), unit(rng), unit(rng));
      bary /= bary.sum();
      p = mesh.point({f, bary}) + (unit(rng) - 0.5) * 0.02 * mesh.face_normals().row(f).transpose();
    }
    const ClosestPoint a = bvh.closest_point(p), b = closest_point_brute_force(mesh, p);
    ASSERT_EQ(a.where.face, b.where.face) << "query " << q;
    ASSERT_EQ(a.squared_distance, b.squared_distance) << "query " << q;
    ASSERT_EQ(a.where.bary, b.where.bary);
    ASSERT_NEAR((mesh.point(a.where) - a.point).norm(), 0, 1e-14);

    const double radius = 0.2 * unit(rng);
    bvh.faces_in_ball(p, radius, fast);
    faces_in_ball_brute_force(mesh, p, radius, slow);
    ASSERT_EQ(fast, slow) << "query " << q << " radius " << radius;
    ASSERT_TRUE(std::is_sorted(fast.begin(), fast.end()));
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, BvhVsBruteForce, ::testing::Values(0, 1));

TEST(FaceBvh, TiesGoToTheLowerFaceIndex) {
  // The centre vertex of a flat grid is shared by 6 faces: all are at exactly the same
  // distance from a point straight above it.
  auto arrays = test::bumpy_grid(4);
  arrays.vertices.col(2).setZero();
  const SurfaceMesh mesh = test::make(arrays);
  const FaceBvh bvh(mesh);
  const int centre = 2 * 5 + 2;
  const Vec3 p = mesh.vertices().row(centre).transpose() + Vec3(0, 0, 0.5);
  int lowest = mesh.num_faces();
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.faces()(f, k) == centre) lowest = std::min(lowest, f);
  const ClosestPoint brute = closest_point_brute_force(mesh, p);
  EXPECT_EQ(bvh.closest_point(p).where.face, brute.where.face);
  EXPECT_EQ(brute.where.face, lowest);
  EXPECT_EQ(brute.squared_distance, 0.25);
}

TEST(FaceBvh, SingleTriangleAndEmptyBall) {
  const auto arrays = test::from_lists({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}});
  const SurfaceMesh mesh = test::make(arrays);
  const FaceBvh bvh(mesh);
  const ClosestPoint r = bvh.closest_point(Vec3(0.25, 0.25, 2));
  EXPECT_EQ(r.where.face, 0);
  EXPECT_DOUBLE_EQ(r.squared_distance, 4);
  std::vector<int> out = {42};
  bvh.faces_in_ball(Vec3(0.25, 0.25, 2), 1.999, out);
  EXPECT_TRUE(out.empty());
  bvh.faces_in_ball(Vec3(0.25, 0.25, 2), 2.0, out);
  EXPECT_EQ(out, std::vector<int>{0});
  bvh.faces_in_ball(Vec3(0.25, 0.25, 0), -1.0, out);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace cutwork

#include "host/mesh/mesh_mapping.h"

#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/mesh/bvh.h"
#include "tests/host/mesh/mesh_fixtures.h"

namespace cutwork {
namespace {

TEST(MapMeshes, IdenticalMeshesMapToThemselves) {
  const SurfaceMesh a = test::make(test::bumpy_grid(6));
  const SurfaceMesh b = test::make(test::bumpy_grid(6));  // equal arrays, another object
  for (const SurfaceMesh* sim : {&a, &b}) {
    const MeshMapping map = map_meshes(a, *sim);
    EXPECT_EQ(map.max_distance, 0.0);
    ASSERT_EQ(int(map.face_to_sim_face.size()), a.num_faces());
    for (int f = 0; f < a.num_faces(); ++f) EXPECT_EQ(map.face_to_sim_face[f], f);
    ASSERT_EQ(int(map.vertex_on_sim.size()), a.num_vertices());
    for (int v = 0; v < a.num_vertices(); ++v) {
      const SurfacePoint& p = map.vertex_on_sim[v];
      ASSERT_GE(p.face, 0);
      EXPECT_EQ(sim->point(p), a.vertices().row(v).transpose());
      EXPECT_EQ(p.bary.maxCoeff(), 1.0);
    }
  }
}

TEST(MapMeshes, FineMeshOntoCoarseMeshMatchesBruteForce) {
  // A fine sphere mapped onto a coarse one: every image is the brute-force closest point.
  const SurfaceMesh fine = test::make(test::icosphere(3));
  const SurfaceMesh coarse = test::make(test::icosphere(1));
  const MeshMapping map = map_meshes(fine, coarse);
  double max_distance = 0;
  for (int v = 0; v < fine.num_vertices(); ++v) {
    const ClosestPoint c = closest_point_brute_force(coarse, fine.vertices().row(v).transpose());
    ASSERT_EQ(map.vertex_on_sim[v].face, c.where.face);
    ASSERT_EQ(map.vertex_on_sim[v].bary, c.where.bary);
    max_distance = std::max(max_distance, std::sqrt(c.squared_distance));
  }
  EXPECT_EQ(map.max_distance, max_distance);
  EXPECT_GT(map.max_distance, 0.01);  // the coarse sphere is visibly inscribed
  EXPECT_LT(map.max_distance, 0.1);
  for (int f = 0; f < fine.num_faces(); ++f) {
    const Vec3 centroid = (fine.vertices().row(fine.faces()(f, 0)) + fine.vertices().row(fine.faces()(f, 1)) +
                           fine.vertices().row(fine.faces()(f, 2))).transpose() / 3;
    ASSERT_EQ(map.face_to_sim_face[f], closest_point_brute_force(coarse, centroid).where.face);
  }
}

TEST(InterpolateVertexField, AffineFieldsAtSurfacePointsAndTheBruteForceClosestPoint) {
  // A field affine in position is interpolated exactly at points on a flat mesh; on a sphere each
  // value is the brute-force closest point's barycentric mix of its face's vertex values.
  const SurfaceMesh grid = test::make(test::annulus(24, 4));
  const FaceBvh grid_bvh(grid);
  Eigen::Matrix3d A;
  A << 1, 2, -3, 0.5, -1, 4, 2, 0, 1;
  const Vec3 b(0.1, -0.2, 0.3);
  auto affine = [&](const RowMatX3d& P) {
    RowMatX3d out = P * A.transpose();
    out.rowwise() += b.transpose();
    return out;
  };
  const SurfaceMesh fine_grid = test::make(test::annulus(57, 9));
  const RowMatX3d at = interpolate_vertex_field(grid_bvh, affine(grid.vertices()), fine_grid.vertices());
  // Points off the coarse annulus (its polygonal rims cut the fine one's round ones) project onto
  // its border; only those on it are compared.
  int compared = 0;
  for (int v = 0; v < fine_grid.num_vertices(); ++v) {
    const Vec3 p = fine_grid.vertices().row(v).transpose();
    if (closest_point_brute_force(grid, p).squared_distance > 1e-24) continue;
    ++compared;
    EXPECT_LT((at.row(v) - affine(p.transpose())).norm(), 1e-12) << "vertex " << v;
  }
  EXPECT_GT(compared, fine_grid.num_vertices() / 2);

  const SurfaceMesh coarse = test::make(test::icosphere(1));
  const SurfaceMesh fine = test::make(test::icosphere(3));
  RowMatX3d field(coarse.num_vertices(), 3);
  for (int v = 0; v < coarse.num_vertices(); ++v) field.row(v) << v, v * v, -2.0 * v;
  const RowMatX3d on_fine = interpolate_vertex_field(FaceBvh(coarse), field, fine.vertices());
  for (int v = 0; v < fine.num_vertices(); ++v) {
    const SurfacePoint w = closest_point_brute_force(coarse, fine.vertices().row(v).transpose()).where;
    Vec3 expected = Vec3::Zero();
    for (int k = 0; k < 3; ++k) expected += w.bary[k] * field.row(coarse.faces()(w.face, k)).transpose();
    ASSERT_LT((on_fine.row(v).transpose() - expected).norm(), 1e-12) << "vertex " << v;
  }
  EXPECT_THROW(interpolate_vertex_field(FaceBvh(coarse), RowMatX3d::Zero(2, 3), fine.vertices()), InternalError);
}

TEST(SimToBaseFaces, PullsValuesThroughTheFaceMap) {
  MeshMapping map;
  map.face_to_sim_face = {2, 0, 2, 1};
  Eigen::VectorXd sim(3);
  sim << 10, 20, 30;
  Eigen::VectorXd expected(4);
  expected << 30, 10, 30, 20;
  EXPECT_EQ(sim_to_base_faces(map, sim), expected);
  EXPECT_THROW(sim_to_base_faces(map, Eigen::VectorXd::Zero(2)), InputError);
}

}  // namespace
}  // namespace cutwork

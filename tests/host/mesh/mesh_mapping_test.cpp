#include "host/mesh/mesh_mapping.h"

#include <gtest/gtest.h>

#include "host/core/error.h"
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

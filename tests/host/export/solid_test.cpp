// The printable solid: closed, manifold, outward, volume = area × thickness; its STL and 3MF.
#include "host/export/solid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/bvh.h"
#include "host/surfaces/generators.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;

constexpr double kThickness = 0.003;

TEST(Solid, UncutPlateIsAClosedManifoldBoxOfAreaTimesThickness) {
  const SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.01);
  const Solid s = thicken_surface(plate.vertices(), plate.faces(), kThickness);
  EXPECT_EQ(s.vertices.rows(), 2 * plate.num_vertices());
  const SolidCheck c = check_solid(s);
  EXPECT_TRUE(c.valid()) << c.problem;
  EXPECT_TRUE(c.manifold);
  EXPECT_TRUE(c.closed);
  EXPECT_FALSE(c.self_intersecting);
  EXPECT_TRUE(c.outward);
  EXPECT_TRUE(c.bounds_volume);
  const double area = plate.face_areas().sum();
  EXPECT_NEAR(c.volume, area * kThickness, 0.01 * area * kThickness);
  EXPECT_NEAR(area, 0.02, 1e-12);
  // Two faces and the walls: 2 × 0.02 m² + perimeter 0.6 m × thickness.
  EXPECT_NEAR(c.area, 2 * area + 0.6 * kThickness, 1e-9);
}

TEST(Solid, CutPlateAndCurvedBowlStayValidWithVolumeAreaTimesThickness) {
  const SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.005);
  const FaceBvh bvh(plate);
  StencilLibrary shapes;
  shapes.add(make_builtin_stencil("circle", {}, "circle"));
  const AxisTangentField field;
  std::vector<StencilParams> stencils;
  for (int i = 0; i < 3; ++i) {
    StencilParams p;
    p.position = Vec3(-0.06 + 0.06 * i, 0.005 * i, 0);
    p.scale = 0.02;
    stencils.push_back(p);
  }
  const CutSurface cut = cut_stencils(bvh, shapes, field, stencils);
  const SolidCheck c = check_solid(thicken_surface(cut.vertices, cut.faces, kThickness));
  EXPECT_TRUE(c.valid()) << c.problem;
  EXPECT_NEAR(c.volume, cut.area * kThickness, 1e-9 * cut.area * kThickness);

  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.01);
  const SolidCheck b = check_solid(thicken_surface(bowl.vertices(), bowl.faces(), kThickness));
  EXPECT_TRUE(b.valid()) << b.problem;
  const double area = bowl.face_areas().sum();
  EXPECT_NEAR(b.volume, area * kThickness, 0.01 * area * kThickness);

  // A cut bowl offset along the bowl's Phong normals (what a design does).
  const FaceBvh bowl_bvh(bowl);
  std::vector<StencilParams> on_bowl;
  for (int i = 0; i < 6; ++i) {
    StencilParams p;
    p.position = bowl_bvh.closest_point(Vec3(0.06 * std::cos(i), 0.06 * std::sin(i), 0.05)).point;
    p.scale = 0.015;
    on_bowl.push_back(p);
  }
  const CutSurface cut_bowl = cut_stencils(bowl_bvh, shapes, field, on_bowl);
  const RowMatX3d normals = surface_normals_at(bowl_bvh, cut_bowl.vertices);
  const SolidCheck cb = check_solid(thicken_surface(cut_bowl.vertices, cut_bowl.faces, kThickness, &normals));
  EXPECT_TRUE(cb.valid()) << cb.problem;
  EXPECT_LT(cut_bowl.area, 0.99 * area) << "the stencils cut something";
  EXPECT_NEAR(cb.volume, cut_bowl.area * kThickness, 0.01 * cut_bowl.area * kThickness);
  EXPECT_THROW(thicken_surface(cut_bowl.vertices, cut_bowl.faces, kThickness, &bowl.vertices()), InternalError);
}

TEST(Solid, ThickerThanTheCurvatureAllowsIsFoundSelfIntersecting) {
  // A bowl thickened by more than its radius folds the inner offset through itself.
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.01);
  const SolidCheck c = check_solid(thicken_surface(bowl.vertices(), bowl.faces(), 1.0));
  EXPECT_FALSE(c.valid());
  EXPECT_TRUE(c.self_intersecting) << c.problem;
}

TEST(Solid, BadInputsAreRejected) {
  const SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.05);
  EXPECT_THROW(thicken_surface(plate.vertices(), plate.faces(), 0.0), InputError);
  EXPECT_THROW(thicken_surface(plate.vertices(), plate.faces(), -1.0), InputError);
  EXPECT_THROW(thicken_surface(plate.vertices(), RowMatX3i(0, 3), 0.01), InputError);
  RowMatX3i twice(2, 3);
  twice << 0, 1, 2, 0, 1, 3;  // edge 0→1 used twice in the same direction
  EXPECT_THROW(thicken_surface(RowMatX3d::Random(4, 3), twice, 0.01), InputError);
}

TEST(Solid, StlAnd3mfHoldTheSolidInMillimetres) {
  const SurfaceMesh plate = generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.02);
  const Solid s = thicken_surface(plate.vertices(), plate.faces(), kThickness);
  const fs::path dir = test::temp_dir("solid_files");
  write_stl(dir / "cut_solid.stl", s);
  EXPECT_EQ(fs::file_size(dir / "cut_solid.stl"), 84u + 50u * size_t(s.faces.rows()));
  std::ifstream stl(dir / "cut_solid.stl", std::ios::binary);
  char header[84];
  stl.read(header, 84);
  uint32_t count = 0;
  std::memcpy(&count, header + 80, 4);
  EXPECT_EQ(count, uint32_t(s.faces.rows()));
  float first[12];
  stl.read(reinterpret_cast<char*>(first), sizeof first);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(first[3 + k], 1e3 * s.vertices(s.faces(0, 0), k), 1e-3);

  write_3mf(dir / "cut_solid.3mf", s, "plate");
  const ThreeMfMesh m = read_3mf(dir / "cut_solid.3mf");
  EXPECT_EQ(m.unit, "millimeter");
  ASSERT_EQ(m.vertices.rows(), s.vertices.rows());
  EXPECT_EQ(m.faces, s.faces);
  EXPECT_LT((m.vertices - 1e3 * s.vertices).cwiseAbs().maxCoeff(), 1e-4);  // float precision in mm
}

}  // namespace
}  // namespace cutwork

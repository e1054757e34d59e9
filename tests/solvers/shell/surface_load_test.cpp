// Loads spread over the surface are carried by the material (LoadCase::surface_loads,
// ShellModel::external_forces): each face's share in proportion to α_t a_t, each load's total
// unchanged — the distribution a mesh with the holes cut gives the same load (resolve_load_case's
// match_totals). Checked against a face-by-face twin, against the load case at α ≡ 1, and its
// derivative against central differences.
#include <gtest/gtest.h>

#include <random>

#include "host/core/error.h"
#include "host/scene/scene.h"
#include "solvers/shell/fill_ratio_partials.h"
#include "solvers/shell/shell_model.h"
#include "tests/solvers/support/finite_difference.h"

namespace cutwork::solvers {
namespace {

/// The unit sheet pinned round its boundary under an area load over part of it, a pressure disc,
/// a point load's patch and an edge load (the edge load stays where it is: it is not spread over
/// the surface).
Scene loaded_sheet(double edge_length) {
  nlohmann::json doc = nlohmann::json::parse(R"({
    "mesh": {"generator": "sheet"},
    "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
    "loads": [
      {"type": "area", "force": [0, 0, -1500], "select": {"entity": "faces", "x": {"above": -0.137}, "y": {"above": 0.0731, "below": 0.4137}}},
      {"type": "point", "force": [3, 0, -20], "select": {"near": {"point": [0.0123, -0.171, 0.01], "radius": 0.0777}}},
      {"type": "pressure", "pressure": 250, "select": {"entity": "faces", "near": {"point": [-0.2, -0.2, 0], "radius": 0.13}}},
      {"type": "edge", "force": [0, 40, 0], "select": {"entity": "boundary_edges", "x": {"above": 0.2113}}}
    ]})");
  doc["mesh"]["edge_length"] = edge_length;
  return parse_scene(doc, "test:surface-loads");
}

Eigen::VectorXd random_fill_ratios(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> a(0.2, 1.0);
  Eigen::VectorXd alpha(n);
  for (int t = 0; t < n; ++t) alpha[t] = a(rng);
  return alpha;
}

TEST(SurfaceLoads, AreCarriedByTheMaterialWithTheirTotals) {
  const Scene scene = loaded_sheet(0.05);
  const SurfaceMesh mesh = build_scene_meshes(scene).sim;
  const LoadCase lc = resolve_load_case(scene, mesh);
  ASSERT_EQ(lc.surface_loads.size(), 3u) << "area, point patch and pressure; not the edge load";
  const ShellModel model(mesh, Material{}, lc);
  const RowMatX3i& F = mesh.faces();

  // Without holes the loads are where the load case has them.
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_faces());
  EXPECT_EQ((model.external_forces(ones) - lc.forces).cwiseAbs().maxCoeff(), 0.0);

  // The face-by-face twin: the edge load's forces, plus each surface load's faces' shares
  // (Σ a / Σ α a) α_t F_t.
  const Eigen::VectorXd alpha = random_fill_ratios(mesh.num_faces(), 7);
  RowMatX3d twin = lc.forces;
  for (const SurfaceLoad& sl : lc.surface_loads) {
    double area = 0, material = 0;
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      area += sl.areas[i];
      material += alpha[sl.faces[i]] * sl.areas[i];
      for (int k = 0; k < 3; ++k) twin.row(F(sl.faces[i], k)) -= sl.nodal[i][std::size_t(k)].transpose();
    }
    for (std::size_t i = 0; i < sl.faces.size(); ++i)
      for (int k = 0; k < 3; ++k)
        twin.row(F(sl.faces[i], k)) += (area / material * alpha[sl.faces[i]]) * sl.nodal[i][std::size_t(k)].transpose();
  }
  const RowMatX3d f = model.external_forces(alpha);
  const double scale = lc.forces.cwiseAbs().maxCoeff();
  EXPECT_LE((f - twin).cwiseAbs().maxCoeff(), 1e-12 * scale);
  // Totals unchanged (every traction here has one direction), the distribution changed.
  const Vec3 total = f.colwise().sum().transpose(), total_uncut = lc.forces.colwise().sum().transpose();
  EXPECT_NEAR((total - total_uncut).norm(), 0, 1e-12 * total_uncut.norm());
  EXPECT_GT((f - lc.forces).cwiseAbs().maxCoeff(), 0.1 * scale);
  // The edge load's rows (on the boundary, beyond the surface loads' regions) are untouched.
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (lc.forces(v, 1) != 0) {
      EXPECT_EQ(f(v, 1), lc.forces(v, 1)) << "vertex " << v;
    }
  }

  // A face with half the material carries half the load per area of one with all of it: the
  // area load over the whole sheet, α = 1 left of x = 0 and 0.25 right of it, moves its centre of
  // load left by the twin's amount, computed from the faces' areas and centroids.
  nlohmann::json doc = nlohmann::json::parse(R"({
    "mesh": {"generator": "sheet", "edge_length": 0.1},
    "supports": [{"type": "pinned", "select": {"entity": "boundary_vertices"}}],
    "loads": [{"type": "area", "force": [0, 0, -1500], "select": {"entity": "faces"}}]})");
  const Scene whole = parse_scene(doc, "test:surface-loads");
  const SurfaceMesh sheet = build_scene_meshes(whole).sim;
  const LoadCase whole_lc = resolve_load_case(whole, sheet);
  const ShellModel whole_model(sheet, Material{}, whole_lc);
  Eigen::VectorXd halves(sheet.num_faces());
  double area = 0, material = 0, moment = 0;
  for (int t = 0; t < sheet.num_faces(); ++t) {
    const Vec3 c = (sheet.vertices().row(sheet.faces()(t, 0)) + sheet.vertices().row(sheet.faces()(t, 1)) +
                    sheet.vertices().row(sheet.faces()(t, 2))).transpose() / 3.0;
    halves[t] = c.x() < 0 ? 1.0 : 0.25;
    area += sheet.face_areas()[t];
    material += halves[t] * sheet.face_areas()[t];
    moment += halves[t] * sheet.face_areas()[t] * c.x();
  }
  const RowMatX3d g = whole_model.external_forces(halves);
  double got = 0;
  for (int v = 0; v < sheet.num_vertices(); ++v) got += g(v, 2) * sheet.vertices()(v, 0);
  const double expected = -1500 * area / material * moment;  // Σ f_z x
  EXPECT_NEAR(got, expected, 1e-12 * std::abs(expected));
  EXPECT_NEAR(g.col(2).sum(), -1500 * area, 1e-12 * 1500 * area);
  // Closed form, for faces split exactly at x = 0: 2400 N/m² on the left half, 600 on the right,
  // Σ f_z x = 2400 · 0.125 − 600 · 0.125 = 225 N m (the faces' centroids split it within O(h)).
  EXPECT_NEAR(expected, 225, 0.05 * 225);
}

// "mechanics.loads": "area" (the paper's model) leaves every load where the load case has it.
TEST(SurfaceLoads, TheAreaRuleLeavesThemSpreadByArea) {
  Scene scene = loaded_sheet(0.05);
  scene.mechanics.loads = LoadSpread::Area;
  const SurfaceMesh mesh = build_scene_meshes(scene).sim;
  const LoadCase lc = resolve_load_case(scene, mesh);
  EXPECT_TRUE(lc.surface_loads.empty());
  const ShellModel model(mesh, Material{}, lc);
  EXPECT_EQ((model.external_forces(random_fill_ratios(mesh.num_faces(), 3)) - lc.forces).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SurfaceLoads, TheirDerivativeMatchesCentralDifferences) {
  const Scene scene = loaded_sheet(0.12);
  const SurfaceMesh mesh = build_scene_meshes(scene).sim;
  const LoadCase lc = resolve_load_case(scene, mesh);
  const ShellModel model(mesh, Material{}, lc);
  const Eigen::VectorXd a0 = random_fill_ratios(mesh.num_faces(), 11);
  const RowMatX3d x = mesh.vertices();
  // At rest the elastic force is zero: ∂f/∂α is the loads' alone.
  auto force = [&](const Eigen::VectorXd& a) -> Eigen::VectorXd { return model.gather_free(model.external_forces(a)); };
  const Eigen::MatrixXd J = force_alpha_jacobian(model, x, a0);
  const auto check = test::check_jacobian(force, a0, J, 0.1);
  EXPECT_LE(check.best, 1e-7) << check.table();
  EXPECT_GT(J.cwiseAbs().maxCoeff(), 0.0);
  // v · ∂f/∂α without the matrix, for v zero on the fixed rows.
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  Eigen::VectorXd lambda(model.num_dofs());
  for (int i = 0; i < lambda.size(); ++i) lambda[i] = n(rng);
  RowMatX3d v = RowMatX3d::Zero(mesh.num_vertices(), 3);
  model.scatter_free(lambda, v);
  Eigen::VectorXd product = Eigen::VectorXd::Zero(mesh.num_faces());
  model.add_load_alpha_product(v, a0, product);
  // (Round-off: each column of J sums a load's whole rank-one term, with cancellation; measured
  // 4.6e-11 relative.)
  EXPECT_LE((product - J.transpose() * lambda).norm(), 1e-9 * product.norm());
}

TEST(SurfaceLoads, AMalformedOneIsRefused) {
  const Scene scene = loaded_sheet(0.12);
  const SurfaceMesh mesh = build_scene_meshes(scene).sim;
  LoadCase lc = resolve_load_case(scene, mesh);
  LoadCase bad_face = lc;
  bad_face.surface_loads[0].faces[0] = mesh.num_faces();
  EXPECT_THROW(ShellModel(mesh, Material{}, bad_face), InputError);
  LoadCase bad_area = lc;
  bad_area.surface_loads[0].areas[0] = 0;
  EXPECT_THROW(ShellModel(mesh, Material{}, bad_area), InputError);
  LoadCase bad_size = lc;
  bad_size.surface_loads[0].nodal.pop_back();
  EXPECT_THROW(ShellModel(mesh, Material{}, bad_size), InputError);
  // No material under a load (fill ratios are positive in a run; a hand-made α may not be).
  const ShellModel model(mesh, Material{}, lc);
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(mesh.num_faces());
  for (int t : lc.surface_loads[0].faces) alpha[t] = 0;
  EXPECT_THROW(model.external_forces(alpha), SolveError);
}

}  // namespace
}  // namespace cutwork::solvers

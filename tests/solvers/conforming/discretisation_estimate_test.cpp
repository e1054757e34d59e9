// The discretisation estimate (solvers/conforming/discretisation_estimate.h): the refined meshes,
// Richardson's rule on known sequences, and the verdict on a converged and an unconverged scene.
#include <gtest/gtest.h>

#include <cmath>

#include "host/scene/scene.h"
#include "solvers/conforming/discretisation_estimate.h"
#include "solvers/conforming/richardson.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"

namespace cutwork::solvers {
namespace {

Eigen::VectorXd solid(const SurfaceMesh& m) { return Eigen::VectorXd::Ones(m.num_faces()); }

/// The uncut shell of `scene` at its simulation mesh, and the estimate of its discretisation error.
DiscretisationEstimate uncut_estimate(const Scene& scene, const DiscretisationOptions& options = {}) {
  const SceneMeshes meshes = build_scene_meshes(scene);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  const MechanicsSettings mechanics = scene_mechanics(scene);
  const ShellModel model(meshes.sim, scene.material, lc, mechanics);
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = solid(meshes.sim);
  solver.solve(alpha);
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha);
  return estimate_discretisation(scene, refine_simulation_mesh(scene, meshes, options), solid, mechanics, s,
                                 simulation_edge_length(scene, meshes), meshes.sim, options);
}

TEST(Richardson, KnownSequences) {
  for (double p : {1.0, 2.0, 3.0}) {
    const double q[3] = {5 + 2 * 1.0, 5 + 2 * std::pow(0.5, p), 5 + 2 * std::pow(0.25, p)};
    const Richardson r = richardson_extrapolate(q);
    EXPECT_TRUE(r.asymptotic);
    EXPECT_NEAR(r.order, p, 1e-12);
    EXPECT_NEAR(r.extrapolated, 5, 1e-12);
  }
  const double growing[3] = {1.0, 1.1, 1.4};
  const Richardson g = richardson_extrapolate(growing);
  EXPECT_FALSE(g.asymptotic);
  EXPECT_EQ(g.extrapolated, 1.4);
  EXPECT_NEAR(g.error_bar, 0.3, 1e-15);
  EXPECT_TRUE(std::isnan(richardson_extrapolate(std::span<const double>(growing, 1)).error_bar));
}

TEST(DiscretisationEstimate, TheSheetIsConverged) {
  // The unit sheet under self-weight, pinned round its boundary, at its default 0.05 m: compliance
  // 0.04571, 0.04579, 0.04581 J at h, h/2, h/4 (measured): well inside 2%.
  const DiscretisationEstimate e = uncut_estimate(load_scene("sheet"));
  ASSERT_EQ(e.levels.size(), 3u);
  EXPECT_EQ(e.method, "regenerated");
  EXPECT_NEAR(e.levels[1].edge_length, 0.025, 1e-15);
  EXPECT_NEAR(e.levels[2].edge_length, 0.0125, 1e-15);
  EXPECT_GT(e.levels[2].faces, 12 * e.levels[0].faces);
  EXPECT_TRUE(e.converged) << discretisation_line(e);
  EXPECT_LT(e.estimated_error, 0.01);
  // The estimate bounds the distance to the finest level.
  EXPECT_GE(e.estimated_error * std::abs(e.compliance.extrapolated),
            std::abs(e.levels[0].quantities.compliance - e.levels[2].quantities.compliance) * 0.999);
}

TEST(DiscretisationEstimate, SupportsThatGrowUnderRefinementAreCaughtAndNamed) {
  // The pavilion's feet are strips of the rim on z = 0; past each foot's end the rim rises out of
  // z = 0 tangentially (z ≈ 1.2 (π t / 2)²), so "z below 0.01" also fixes up to 0.11 m of rim on
  // each side once the mesh is fine enough: 3.199 m of clamped line at 0.35 m, 3.888 m at 0.0875 m.
  // The levels are then different structures (compliance 1.685, 1.751, 1.188 J), and the estimate
  // must not judge the mesh by them.
  Scene scene = load_scene("pavilion");
  ASSERT_EQ(scene.supports.size(), 1u);
  scene.supports[0].select.below[2] = 0.01;
  const DiscretisationEstimate e = uncut_estimate(scene);
  ASSERT_EQ(e.levels.size(), 3u);
  EXPECT_NEAR(e.levels[0].clamped.length, 3.2, 0.01);
  EXPECT_GT(e.levels[2].clamped.length, 3.5);
  EXPECT_GT(e.support_change, 0.1);
  EXPECT_FALSE(e.supports_consistent);
  EXPECT_FALSE(e.converged);
  EXPECT_NE(discretisation_line(e).find("the supports hold a different region"), std::string::npos)
      << discretisation_line(e);
  EXPECT_EQ(discretisation_json(e)["supports_consistent"], false);
}

TEST(DiscretisationEstimate, TheDefaultPavilionHoldsItsFeetOnEveryLevel) {
  // Selected exactly ("z below 1e-6"), the feet are the same 4 × 0.8 m on every mesh (chords of
  // the rim: within 3e-4), and the compliance no longer falls under refinement: 1.685, 1.751,
  // 1.694 J at 0.35, 0.175, 0.0875 m, and 1.689 J at 0.05 m (1.688 J at 0.02 m, measured). The
  // levels do not converge monotonically (the hexagonal rings meet the arches differently), so
  // the estimate is the conservative "not asymptotic" one, and it must bracket the finer answer.
  const Scene scene = load_scene("pavilion");
  const DiscretisationEstimate e = uncut_estimate(scene);
  ASSERT_EQ(e.levels.size(), 3u);
  EXPECT_TRUE(e.supports_consistent) << discretisation_line(e);
  EXPECT_LT(e.support_change, 1e-3);
  for (const DiscretisationLevel& l : e.levels) {
    EXPECT_NEAR(l.clamped.length, 3.2, 2e-3);
    EXPECT_EQ(l.clamped.area, 0.0);
    EXPECT_EQ(l.clamped.points, 0);
  }
  // A finer run, the generator at 0.05 m.
  Scene fine = scene;
  fine.mesh.sim_edge_length = 0.05;
  const SceneMeshes meshes = build_scene_meshes(fine);
  const LoadCase lc = resolve_load_case(fine, meshes.sim);
  const ShellModel model(meshes.sim, fine.material, lc, scene_mechanics(fine));
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = solid(meshes.sim);
  solver.solve(alpha);
  const double c_fine = summarize_equilibrium(model, solver.positions(), alpha).compliance;
  const double c_h = e.levels[0].quantities.compliance;
  EXPECT_LE(std::abs(c_h - c_fine), e.estimated_error * c_fine) << discretisation_line(e);
  // Within 2% of it: the 35% "discretisation error" the old selection showed was the supports.
  EXPECT_LT(std::abs(c_h - c_fine) / c_fine, 0.02);
}

TEST(DiscretisationEstimate, TheBuiltinDefaultsAreWithinTwoPercent) {
  // Issue 21 item 1: the uncut default simulation meshes within 2% of converged, the supports the
  // same region on every level. Measured (h, h/2, h/4): plate 6.350, 6.324, 6.309 mJ (1.0%); bowl
  // 1.264, 1.278, 1.283 mJ (1.7%); table 2.909, 2.900, 2.888 J (1.1%, converged about 2.881 J);
  // chair 10.471, 10.434, 10.356 J (1.9%, about 10.31 J). Before the fillet rows and the exact
  // runner the table's was 3.0% (at 0.04 m) and the chair's 12.9% (at 0.043 m). The pavilion's
  // own test is above; the sheet's is TheSheetIsConverged.
  for (const char* name : {"plate", "bowl", "table", "chair"}) {
    SCOPED_TRACE(name);
    const DiscretisationEstimate e = uncut_estimate(load_scene(name));
    ASSERT_EQ(e.levels.size(), 3u);
    EXPECT_TRUE(e.supports_consistent) << discretisation_line(e);
    EXPECT_TRUE(e.converged) << discretisation_line(e);
    EXPECT_LE(e.estimated_error, 0.02) << discretisation_line(e);
  }
}

TEST(DiscretisationEstimate, MeshFilesAreSubdividedAndTheBudgetIsKept) {
  Scene scene = load_scene("sheet");
  // A mesh file stands in: the generator's own mesh without its generator.
  const SceneMeshes meshes = build_scene_meshes(scene);
  scene.mesh.generator.clear();
  DiscretisationOptions o;
  o.max_faces = 8 * meshes.sim.num_faces();  // h/2 (4×) fits, h/4 (16×) does not
  const std::vector<RefinedSimulationMesh> r = refine_simulation_mesh(scene, meshes, o);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].method, "subdivided");
  EXPECT_EQ(r[0].mesh.num_faces(), 4 * meshes.sim.num_faces());
  EXPECT_NEAR(r[0].mesh.face_areas().sum(), meshes.sim.face_areas().sum(), 1e-12);
  o.max_faces = 1'000'000;
  EXPECT_EQ(refine_simulation_mesh(scene, meshes, o).size(), 2u);
}

}  // namespace
}  // namespace cutwork::solvers

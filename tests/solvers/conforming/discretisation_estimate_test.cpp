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
                                 simulation_edge_length(scene, meshes), meshes.sim.num_faces(), options);
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

TEST(DiscretisationEstimate, TheDefaultPavilionIsNotConvergedAndSaysSo) {
  // The vault's faceted coarse mesh is far softer than the fine one (1.69 J at 0.35 m against
  // about 1.17 J from 0.06 m on): the estimate must not call that converged.
  const DiscretisationEstimate e = uncut_estimate(load_scene("pavilion"));
  ASSERT_EQ(e.levels.size(), 3u);
  EXPECT_FALSE(e.converged) << discretisation_line(e);
  EXPECT_GT(e.estimated_error, 0.25) << discretisation_line(e);
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

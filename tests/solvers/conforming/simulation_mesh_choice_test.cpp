// A file's simulation mesh, "auto" (solvers/conforming/simulation_mesh_choice.h): the coarsest
// midpoint subdivision of the file's mesh on which the uncut shell is within the tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "host/mesh/mesh_io.h"
#include "host/scene/scene.h"
#include "solvers/conforming/simulation_mesh_choice.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/shell/shell_model.h"
#include "tests/solvers/support/test_meshes.h"
#include "tests/support/test_support.h"

namespace cutwork::solvers {
namespace {

namespace fs = std::filesystem;

/// `mesh` written to a file and loaded as a plain mesh (its default supports and self-weight).
Scene plain_mesh_scene(const SurfaceMesh& mesh, const fs::path& dir, const std::string& name) {
  write_obj(dir / (name + ".obj"), mesh.vertices(), mesh.faces());
  return load_scene((dir / (name + ".obj")).string());
}

/// The uncut shell's compliance on `mesh` (the scene's supports, loads and mechanics).
double uncut_compliance(const Scene& scene, const SurfaceMesh& mesh) {
  const LoadCase lc = resolve_load_case(scene, mesh);
  const ShellModel model(mesh, scene.material, lc, scene_mechanics(scene));
  EquilibriumSolver solver(model);
  const Eigen::VectorXd solid = Eigen::VectorXd::Ones(mesh.num_faces());
  solver.solve(solid);
  return summarize_equilibrium(model, solver.positions(), solid).compliance;
}

// A dome of 612 flat facets on its rim, under its weight: 11.7% from converged on the file's mesh,
// 3.2% divided once, 1.4% twice. The choice is the first within 2%, and the run then simulates on it.
TEST(SimulationMeshChoice, TheCoarsestSubdivisionWithinTheToleranceIsChosen) {
  const fs::path dir = test::temp_dir("sim-mesh-choice");
  const Scene scene = plain_mesh_scene(test::spherical_cap(9, 36), dir, "dome");
  SceneMeshes meshes = build_scene_meshes(scene);
  ASSERT_TRUE(meshes.sim_choice_pending);
  const double file_compliance = uncut_compliance(scene, meshes.sim);
  const std::string note = choose_simulation_mesh(scene, meshes);
  EXPECT_FALSE(meshes.sim_choice_pending);
  const nlohmann::json& c = meshes.sim_choice;
  ASSERT_TRUE(c.is_object());
  const int k = c.at("subdivisions");
  EXPECT_TRUE(c.at("converged").get<bool>()) << note;
  EXPECT_TRUE(c.at("supports_consistent").get<bool>());
  ASSERT_GE(c.at("levels").size(), 3u);
  EXPECT_NEAR(c["levels"][0]["compliance"].get<double>(), file_compliance, 1e-12 * file_compliance)
      << "the study's first level is the run's uncut shell";
  // The first level within the tolerance, and none before it.
  for (int j = 0; j < k; ++j) EXPECT_GT(c["levels"][j]["error"].get<double>(), c.at("tolerance").get<double>());
  EXPECT_LE(c["levels"][k]["error"].get<double>(), c.at("tolerance").get<double>());
  EXPECT_EQ(k, 2) << note;
  EXPECT_EQ(meshes.sim_subdivisions, k);
  EXPECT_EQ(meshes.sim.num_faces(), meshes.base.num_faces() << (2 * k));
  EXPECT_FALSE(meshes.sim_is_base);
  EXPECT_NEAR(uncut_compliance(scene, meshes.sim), c["levels"][k]["compliance"].get<double>(),
              1e-9 * file_compliance);
  EXPECT_NE(note.find("divided 2 times (9792 triangles): its uncut compliance is within 1.4%"), std::string::npos)
      << note;
  // Resolved once: a second call changes nothing.
  EXPECT_EQ(choose_simulation_mesh(scene, meshes), "");
  EXPECT_EQ(meshes.sim.num_faces(), meshes.base.num_faces() << (2 * k));
  fs::remove_all(dir);
}

// Where no subdivision within the budget is converged the finest is taken and the note says how far
// it is; where the supports hold a different region on each level nothing can be judged and the
// file's mesh stays.
TEST(SimulationMeshChoice, WhatCannotBeConvergedOrJudgedIsSaid) {
  const fs::path dir = test::temp_dir("sim-mesh-choice-not");
  {
    // 264 facets: within 2% divided three times (16896 triangles, 1.3% by five levels). With a face
    // budget of 20,000 the finest that may be chosen is divided twice, 10% off by four levels.
    const Scene scene = plain_mesh_scene(test::spherical_cap(6, 24), dir, "coarse");
    SceneMeshes meshes = build_scene_meshes(scene);
    DiscretisationOptions budget;
    budget.max_faces = 20'000;
    const std::string note = choose_simulation_mesh(scene, meshes, budget);
    EXPECT_FALSE(meshes.sim_choice.at("converged").get<bool>());
    EXPECT_EQ(meshes.sim_choice.at("subdivisions"), 2);
    EXPECT_EQ(meshes.sim_choice.at("levels").size(), 4u);
    EXPECT_NE(note.find("divided 2 times (4224 triangles), the finest whose own estimate fits 20000 triangles: NOT "
                        "converged"),
              std::string::npos)
        << note;
  }
  {
    // Upside down, resting on its apex: the default band of 1% takes more of each finer mesh.
    const Scene scene = plain_mesh_scene(test::spherical_cap(6, 24, true), dir, "bowl");
    SceneMeshes meshes = build_scene_meshes(scene);
    const std::string note = choose_simulation_mesh(scene, meshes);
    EXPECT_FALSE(meshes.sim_choice.at("supports_consistent").get<bool>());
    EXPECT_EQ(meshes.sim_choice.at("subdivisions"), 0);
    EXPECT_TRUE(meshes.sim_is_base);
    EXPECT_NE(note.find("the supports hold a different region on each subdivision"), std::string::npos) << note;
  }
  {
    // An explicit count is taken as it is: nothing to choose.
    Scene scene = plain_mesh_scene(test::spherical_cap(6, 24), dir, "explicit");
    scene.mesh.sim_subdivisions = 1;
    SceneMeshes meshes = build_scene_meshes(scene);
    EXPECT_EQ(choose_simulation_mesh(scene, meshes), "");
    EXPECT_EQ(meshes.sim.num_faces(), 4 * meshes.base.num_faces());
    EXPECT_TRUE(meshes.sim_choice.is_null());
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork::solvers

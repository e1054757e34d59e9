// max_displacement and W_max of an equilibrium measure the material, not the α = 1e-4 filler of a
// hole (issue 11 item 5): a strip pinned at both ends under self-weight with a hole in the middle,
// whose filler sags below the material around it.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/structural_quantities.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

struct HoledStrip {
  SurfaceMesh mesh = test::equilateral_rectangle(0.6, 0.2, 24);
  LoadCase lc;
  std::unique_ptr<ShellModel> model;
  Eigen::VectorXd alpha;

  HoledStrip() {
    const int nv = mesh.num_vertices();
    lc.fixed.assign(nv, false);
    lc.clamped.assign(nv, false);
    for (int v = 0; v < nv; ++v) {
      const double x = mesh.vertices()(v, 0);
      if (x < 1e-9 || x > 0.6 - 1e-9) lc.fixed[v] = true;
    }
    lc.gravity = Vec3(0, 0, -9.81);
    model = std::make_unique<ShellModel>(mesh, test::pa12(), lc);
    // A round hole of radius 0.07 m at the centre: filler inside, a ring of partly cut faces.
    alpha = Eigen::VectorXd::Ones(mesh.num_faces());
    const RowMatX3i& F = mesh.faces();
    for (int f = 0; f < mesh.num_faces(); ++f) {
      int inside = 0;
      for (int k = 0; k < 3; ++k)
        inside += (mesh.vertices().row(F(f, k)) - Eigen::RowVector3d(0.3, 0.1, 0)).norm() < 0.07;
      alpha[f] = inside == 3 ? 1e-4 : inside == 2 ? 0.03 : inside == 1 ? 0.5 : 1.0;
    }
  }
};

TEST(StructuralQuantities, MaxDisplacementAndWMaxIgnoreTheFillerOfAHole) {
  HoledStrip s;
  EquilibriumSolver solver(*s.model);
  ASSERT_TRUE(solver.solve(s.alpha).converged);
  const EquilibriumSummary q = summarize_equilibrium(*s.model, solver.positions(), s.alpha);
  const RowMatX3i& F = s.mesh.faces();

  // Brute force over the material: faces with α > 0.05 and their vertices.
  const Eigen::VectorXd un = solver.displacements().rowwise().norm();
  double u_material = 0, u_all = un.maxCoeff(), W_material = 0;
  std::vector<bool> vertex(size_t(s.mesh.num_vertices()), false);
  for (int f = 0; f < s.mesh.num_faces(); ++f)
    if (s.alpha[f] > 0.05) {
      W_material = std::max(W_material, q.energy_density[f]);
      for (int k = 0; k < 3; ++k) vertex[size_t(F(f, k))] = true;
    }
  for (int v = 0; v < s.mesh.num_vertices(); ++v)
    if (vertex[size_t(v)]) u_material = std::max(u_material, un[v]);
  // The case this is for: the filler sags further than any material, and its W exceeds the material's.
  ASSERT_GT(u_all, 1.01 * u_material);
  ASSERT_GT(q.energy_density.maxCoeff(), W_material);

  EXPECT_EQ(q.max_displacement, u_material);
  EXPECT_TRUE(vertex[size_t(q.max_displacement_vertex)]);
  EXPECT_EQ(q.max_displacement, un[q.max_displacement_vertex]);
  EXPECT_EQ(q.W_max, W_material);
  EXPECT_GT(s.alpha[q.W_max_face], kMaterialFillRatio);
  EXPECT_EQ(q.W_max, q.energy_density[q.W_max_face]);
}

TEST(StructuralQuantities, WithoutStencilsEveryVertexAndFaceCounts) {
  HoledStrip s;
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(s.mesh.num_faces());
  EquilibriumSolver solver(*s.model);
  ASSERT_TRUE(solver.solve(ones).converged);
  const EquilibriumSummary q = summarize_equilibrium(*s.model, solver.positions(), ones);
  EXPECT_EQ(q.max_displacement, solver.displacements().rowwise().norm().maxCoeff());
  EXPECT_EQ(q.W_max, q.energy_density.maxCoeff());
}

TEST(StructuralQuantities, MaterialFacesAndVertices) {
  Eigen::VectorXd alpha(3);
  alpha << 1e-4, 0.05, 0.0501;
  EXPECT_EQ(material_faces(alpha), (std::vector<bool>{false, false, true}));
  // Nothing is material: every face counts (the maxima stay defined).
  alpha << 1e-4, 1e-4, 0.01;
  EXPECT_EQ(material_faces(alpha), (std::vector<bool>{true, true, true}));
  RowMatX3i F(2, 3);
  F << 0, 1, 2, 2, 1, 3;
  EXPECT_EQ(material_vertices(F, 5, {false, true}), (std::vector<bool>{false, true, true, true, false}));
}

}  // namespace
}  // namespace cutwork::solvers

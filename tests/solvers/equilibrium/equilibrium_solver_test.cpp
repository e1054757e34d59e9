// Newton equilibrium: fill-ratio scaling of the stiffness, warm starts, the factor kept for the
// adjoint, and every bad input ending in a clear error with the last valid state kept.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/mesh/bvh.h"
#include "host/mesh/mesh_mapping.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

Material pa12() {
  Material m;  // laser-sintered PA12, 3 mm
  m.youngs_modulus = 1.7e9;
  m.poisson_ratio = 0.4;
  m.thickness = 0.003;
  m.density = 1010;
  return m;
}

/// A 0.4 m square plate of `rows` triangle rows, boundary pinned, with a point load at the vertex
/// nearest the centre.
struct PointLoadedPlate {
  SurfaceMesh mesh;
  LoadCase lc;
  int centre = 0;
  PointLoadedPlate(double load, bool clamp, int rows = 16) : mesh(test::equilateral_rectangle(0.4, 0.4, rows)) {
    const int nv = mesh.num_vertices();
    lc.fixed = mesh.is_boundary_vertex();
    lc.clamped.assign(nv, false);
    if (clamp) lc.clamped = lc.fixed;
    lc.forces = RowMatX3d::Zero(nv, 3);
    double best = INFINITY;
    for (int v = 0; v < nv; ++v) {
      const double d = (mesh.vertices().row(v) - Eigen::RowVector3d(0.2, 0.2, 0)).norm();
      if (d < best) best = d, centre = v;
    }
    lc.forces(centre, 2) = -load;
  }
};

TEST(Equilibrium, HalfFillRatioDoublesSmallLoadDeflection) {
  // (9) and (10) scale membrane and bending energy by α and √(α·α) = α: at α = 0.5 the shell is half
  // as stiff, and in the linear regime (w ≈ 1e-3 h) the deflection doubles.
  PointLoadedPlate plate(1e-3, false);
  const ShellModel model(plate.mesh, pa12(), plate.lc);
  EquilibriumSolver solver(model);
  const Eigen::VectorXd full = Eigen::VectorXd::Ones(model.num_faces());
  solver.solve(full);
  const double w1 = -solver.displacements()(plate.centre, 2);
  solver.solve(0.5 * full);
  const double w05 = -solver.displacements()(plate.centre, 2);
  EXPECT_GT(w1, 0);
  EXPECT_LT(w1, 1e-2 * pa12().thickness);
  EXPECT_NEAR(w05 / w1, 2.0, 0.02) << "w(alpha=1) = " << w1 << " m, w(alpha=0.5) = " << w05 << " m";
}

TEST(Equilibrium, ConvergesQuadraticallyAndWarmStarts) {
  // A large deflection (≈ 3 h) where membrane stretching matters: several Newton steps.
  PointLoadedPlate plate(300.0, true);
  const ShellModel model(plate.mesh, pa12(), plate.lc);
  EquilibriumSolver solver(model);
  const Eigen::VectorXd full = Eigen::VectorXd::Ones(model.num_faces());
  const EquilibriumStats cold = solver.solve(full);
  EXPECT_TRUE(cold.converged);
  EXPECT_FALSE(cold.warm_started);
  EXPECT_LE(cold.residual, solver.settings().residual_tolerance);
  EXPECT_EQ(cold.stop, "residual");
  EXPECT_GE(cold.newton_iterations, 2);
  EXPECT_LE(cold.newton_iterations, 15);
  const double w = -solver.displacements()(plate.centre, 2);
  EXPECT_GT(w, 1.0 * pa12().thickness);

  // A small change of the fill ratios from the previous equilibrium takes fewer steps.
  Eigen::VectorXd alpha = full;
  alpha.head(10).setConstant(0.9);
  const EquilibriumStats warm = solver.solve(alpha);
  EXPECT_TRUE(warm.warm_started);
  EXPECT_LT(warm.newton_iterations, cold.newton_iterations);

  // Same α again: converged at the first check, one factorisation (for the adjoint), by the same
  // test that stopped the warm solve (a residual within tolerance, or a negligible Newton step).
  const EquilibriumStats again = solver.solve(alpha);
  EXPECT_TRUE(again.converged);
  EXPECT_EQ(again.newton_iterations, 0);
  EXPECT_EQ(again.stop, warm.stop);
  EXPECT_LE(again.residual, 1e-8);
  EXPECT_EQ(again.factorizations, 1);
  EXPECT_TRUE(solver.linear_solver().has_factor());
}

TEST(Equilibrium, StartsFromACoarserMeshsSolution) {
  // The same clamped plate and load on a mesh of 8 and of 16 triangle rows: the coarse solution
  // carried onto the fine mesh (what verify's levels and the discretisation estimate do) is a guess
  // Newton converges from in fewer steps than from rest, onto the same equilibrium.
  const PointLoadedPlate coarse_plate(300.0, true, 8), fine_plate(300.0, true, 16);
  const SurfaceMesh& coarse_mesh = coarse_plate.mesh;
  const ShellModel coarse(coarse_mesh, pa12(), coarse_plate.lc);
  EquilibriumSolver coarse_solver(coarse);
  coarse_solver.solve(Eigen::VectorXd::Ones(coarse.num_faces()));

  const ShellModel fine(fine_plate.mesh, pa12(), fine_plate.lc);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(fine.num_faces());
  EquilibriumSolver cold_solver(fine);
  const EquilibriumStats cold = cold_solver.solve(ones);
  const RowMatX3d& X = fine.rest_positions();
  const RowMatX3d carried = X + interpolate_vertex_field(FaceBvh(coarse_mesh), coarse_solver.displacements(), X);

  EquilibriumSolver warm_solver(fine);
  warm_solver.start_from(carried);
  EXPECT_FALSE(warm_solver.has_solution()) << "a guess is not an equilibrium";
  const EquilibriumStats warm = warm_solver.solve(ones);
  EXPECT_TRUE(warm.converged);
  EXPECT_TRUE(warm.warm_started);
  EXPECT_FALSE(warm.cold_restarted);
  EXPECT_LT(warm.newton_iterations, cold.newton_iterations)
      << "from the coarse solution " << warm.newton_iterations << ", from rest " << cold.newton_iterations;
  const double w = cold_solver.max_displacement();
  EXPECT_LT((warm_solver.positions() - cold_solver.positions()).cwiseAbs().maxCoeff(), 1e-8 * w);

  // Fixed vertices of a guess are put back at rest; a guess far off (the plate lifted by its own
  // size) falls back to rest and still finds the equilibrium.
  RowMatX3d far = X;
  far.col(2).array() += 0.4;
  EquilibriumSolver far_solver(fine);
  far_solver.start_from(far);
  const EquilibriumStats restarted = far_solver.solve(ones);
  EXPECT_TRUE(restarted.converged);
  EXPECT_LT((far_solver.positions() - cold_solver.positions()).cwiseAbs().maxCoeff(), 1e-8 * w);
  for (int v = 0; v < fine.num_vertices(); ++v) {
    if (fine_plate.lc.fixed[size_t(v)]) {
      EXPECT_EQ(far_solver.positions().row(v), X.row(v)) << "vertex " << v;
    }
  }

  EXPECT_THROW(warm_solver.start_from(RowMatX3d::Zero(3, 3)), InternalError);
}

/// Runs `f`, expecting a SolveError whose message contains `fragment`.
template <typename F>
void expect_solve_error(F&& f, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no SolveError; expected one mentioning \"" << fragment << "\"";
  } catch (const SolveError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(EquilibriumBadInput, UnsupportedModelsAreRejected) {
  const SurfaceMesh mesh = test::equilateral_rectangle(0.4, 0.4, 8);
  const int nv = mesh.num_vertices();
  LoadCase lc;
  lc.forces = RowMatX3d::Zero(nv, 3);
  lc.forces(nv / 2, 2) = -1;
  lc.fixed.assign(nv, false);
  expect_solve_error([&] { ShellModel(mesh, pa12(), lc); }, "no fixed vertices");

  lc.fixed[0] = true;  // a single pin: free to rotate about it
  expect_solve_error([&] { ShellModel(mesh, pa12(), lc); }, "single point");

  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.y() < 1e-9; })) lc.fixed[v] = true;
  expect_solve_error([&] { ShellModel(mesh, pa12(), lc); }, "lie on one line");

  lc.clamped = lc.fixed;  // a clamped edge holds the rotation about it: a valid cantilever
  EXPECT_NO_THROW(ShellModel(mesh, pa12(), lc));

  // Two separate parts, only one supported.
  RowMatX3d V(mesh.num_vertices() * 2, 3);
  RowMatX3i F(mesh.num_faces() * 2, 3);
  V << mesh.vertices(), mesh.vertices().rowwise() + Eigen::RowVector3d(1, 0, 0);
  F << mesh.faces(), mesh.faces().array() + nv;
  const SurfaceMesh two(V, F, "two plates");
  LoadCase lc2;
  lc2.fixed.assign(2 * nv, false);
  for (int v = 0; v < nv; ++v) lc2.fixed[v] = mesh.is_boundary_vertex()[v];
  lc2.forces = RowMatX3d::Zero(2 * nv, 3);
  lc2.forces(nv / 2, 2) = -1;
  expect_solve_error([&] { ShellModel(two, pa12(), lc2); }, "has no fixed vertices");
}

TEST(EquilibriumBadInput, ZeroAndNonFiniteLoadsAreRejected) {
  PointLoadedPlate plate(1.0, false);
  LoadCase lc = plate.lc;
  lc.forces.setZero();
  expect_solve_error([&] { ShellModel(plate.mesh, pa12(), lc); }, "no load");

  // Loads on supported vertices only do no work: still no load on the shell.
  const int boundary = int(std::find(lc.fixed.begin(), lc.fixed.end(), true) - lc.fixed.begin());
  lc.forces(boundary, 2) = -5;
  expect_solve_error([&] { ShellModel(plate.mesh, pa12(), lc); }, "no load");

  lc = plate.lc;
  lc.forces(plate.centre, 1) = std::nan("");
  expect_solve_error([&] { ShellModel(plate.mesh, pa12(), lc); }, "not finite");
  lc = plate.lc;
  lc.forces(plate.centre, 0) = INFINITY;
  expect_solve_error([&] { ShellModel(plate.mesh, pa12(), lc); }, "not finite");
  lc = plate.lc;
  lc.gravity = Vec3(0, 0, std::nan(""));
  expect_solve_error([&] { ShellModel(plate.mesh, pa12(), lc); }, "not finite");

  // Bad fill ratios are input errors.
  const ShellModel model(plate.mesh, pa12(), plate.lc);
  EquilibriumSolver solver(model);
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
  alpha[3] = std::nan("");
  EXPECT_THROW(solver.solve(alpha), InputError);
  EXPECT_THROW(solver.solve(Eigen::VectorXd::Ones(2)), InputError);

  // Finite loads whose norm overflows double precision cannot be solved for; say so rather than
  // report a NaN residual.
  lc = plate.lc;
  lc.forces(plate.centre, 2) = -1e300;
  const ShellModel huge(plate.mesh, pa12(), lc);
  EquilibriumSolver huge_solver(huge);
  expect_solve_error([&] { huge_solver.solve(Eigen::VectorXd::Ones(huge.num_faces())); }, "too large");
}

TEST(EquilibriumBadInput, LoadBeyondCapacityKeepsTheLastValidState) {
  // A cantilever strip (clamped at x = 0): a modest tip load, then one a million times larger.
  const SurfaceMesh mesh = test::equilateral_rectangle(0.5, 0.0866, 20, 4);
  const int nv = mesh.num_vertices();
  LoadCase lc;
  lc.clamped.assign(nv, false);
  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() < 1e-9; })) lc.clamped[v] = true;
  lc.fixed = lc.clamped;
  const auto tip = test::select_vertices(mesh, [](const Vec3& p) { return p.x() > 0.5 - 1e-9; });
  auto with_tip_load = [&](double P) {
    LoadCase l = lc;
    l.forces = RowMatX3d::Zero(nv, 3);
    for (int v : tip) l.forces(v, 2) = -P / tip.size();
    return l;
  };
  const Eigen::VectorXd full = Eigen::VectorXd::Ones(mesh.num_faces());

  const ShellModel small(mesh, pa12(), with_tip_load(0.05));
  EquilibriumSolver solver(small);
  solver.solve(full);
  const RowMatX3d good = solver.positions();

  // The same solver object cannot change loads, so the overload is a model of its own; check the
  // error there, and that a failed solve (beyond capacity via tiny α) keeps the good state here.
  const ShellModel huge(mesh, pa12(), with_tip_load(5e4));
  EquilibriumSolver overloaded(huge);
  expect_solve_error([&] { overloaded.solve(full); }, "can carry");
  EXPECT_FALSE(overloaded.has_solution());
  EXPECT_TRUE(overloaded.positions() == huge.rest_positions());

  expect_solve_error([&] { solver.solve(Eigen::VectorXd::Constant(mesh.num_faces(), 1e-4)); }, "can carry");
  EXPECT_TRUE(solver.has_solution());
  EXPECT_TRUE(solver.positions() == good);
  EXPECT_TRUE(solver.alpha() == full);
  // The kept state is usable: its factor is back in place for the adjoint.
  EXPECT_NO_THROW(solver.solve_adjoint(Eigen::VectorXd::Ones(small.num_dofs())));
}

}  // namespace
}  // namespace cutwork::solvers

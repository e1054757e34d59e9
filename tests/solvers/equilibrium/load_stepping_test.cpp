// Large deflections: adaptive load stepping when Newton cannot reach the full load, the same
// equilibrium as plain Newton where both converge, and an error naming the load fraction carried
// when the structure cannot carry its load.
#include <cmath>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "host/core/error.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

Material pa12(double thickness) {
  Material m;  // laser-sintered PA12
  m.youngs_modulus = 1.7e9;
  m.poisson_ratio = 0.4;
  m.thickness = thickness;
  m.density = 1010;
  return m;
}

/// A 1.7 m canopy given as a plain mesh: a shallow barrel, 1.7 m long in x and 1 m wide, rising
/// 2 cm at its middle line, clamped along x = 0 and carrying its own weight. With Kirchhoff bending
/// (the default shape operator, ν = 0.4) 10 mm PA12 sags beyond a quarter of the model size (the
/// hinge model, stiffer here, carried it at 0.43 m); 12 mm carries it (kThickCanopy); in 3 mm the
/// curved section snaps through at a fraction of its weight and the flattened strip cannot carry
/// the rest.
constexpr double kThickCanopy = 0.012;

struct Canopy {
  SurfaceMesh mesh = make_mesh();
  LoadCase lc;
  Canopy() {
    const int nv = mesh.num_vertices();
    lc.clamped.assign(nv, false);
    for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() < 1e-9; })) lc.clamped[v] = true;
    lc.fixed = lc.clamped;
    lc.forces = RowMatX3d::Zero(nv, 3);
    lc.gravity = Vec3(0, 0, -9.81);
  }
  static SurfaceMesh make_mesh() {
    const SurfaceMesh flat = test::equilateral_rectangle(1.7, 1.0, 17);
    RowMatX3d V = flat.vertices();
    for (int v = 0; v < V.rows(); ++v) {
      const double s = 2 * V(v, 1) / 1.0 - 1;
      V(v, 2) = 0.02 * (1 - s * s);
    }
    return SurfaceMesh(V, flat.faces(), "canopy");
  }
};

TEST(LoadStepping, CanopyTwelveMillimetresConverges) {
  const Canopy canopy;
  const ShellModel model(canopy.mesh, pa12(kThickCanopy), canopy.lc);
  EquilibriumSolver solver(model);
  const EquilibriumStats& stats = solver.solve(Eigen::VectorXd::Ones(model.num_faces()));
  EXPECT_TRUE(stats.converged);
  const double sag = solver.max_displacement();
  EXPECT_GT(sag, 0.2) << "a large deflection";
  EXPECT_LT(sag, solver.settings().max_displacement_ratio * model.model_size());
}

TEST(LoadStepping, CanopyThreeMillimetresNamesTheLoadFractionCarried) {
  const Canopy canopy;
  const ShellModel model(canopy.mesh, pa12(0.003), canopy.lc);
  EquilibriumSolver solver(model);
  std::string message;
  try {
    solver.solve(Eigen::VectorXd::Ones(model.num_faces()));
  } catch (const SolveError& e) {
    message = e.what();
  }
  ASSERT_FALSE(message.empty()) << "the 3 mm canopy cannot carry its own weight";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(message, m, std::regex(R"(can carry only ([0-9.]+)% of the load)"))) << message;
  const double percent = std::stod(m[1]);
  EXPECT_GT(percent, 0.0) << message;
  EXPECT_LT(percent, 100.0) << message;
  ASSERT_TRUE(std::regex_search(message, m, std::regex(R"(\(([0-9.]+)% of the model size)"))) << message;
  EXPECT_GT(std::stod(m[1]), 0.0) << message;
  EXPECT_LE(std::stod(m[1]), 100 * solver.settings().max_displacement_ratio) << message;
  EXPECT_GT(solver.stats().failed_load_steps, 0);
  // Nothing partial is kept.
  EXPECT_FALSE(solver.has_solution());
  EXPECT_TRUE(solver.positions() == model.rest_positions());
}

TEST(LoadStepping, ReachesTheSameEquilibriumAsPlainNewton) {
  // The 12 mm canopy and a clamped plate under a large point load (≈ 3 h deflection): plain Newton
  // converges at the full load; load steps from a quarter of it reach the same equilibrium.
  const Canopy canopy;
  const SurfaceMesh plate = test::equilateral_rectangle(0.4, 0.4, 16);
  LoadCase plate_lc;
  plate_lc.fixed = plate.is_boundary_vertex();
  plate_lc.clamped = plate_lc.fixed;
  plate_lc.forces = RowMatX3d::Zero(plate.num_vertices(), 3);
  plate_lc.forces(test::select_vertices(plate, [](const Vec3& p) {
                    return (p - Vec3(0.2, 0.2, 0)).norm() < 0.013;
                  }).at(0),
                  2) = -300.0;
  const ShellModel models[] = {ShellModel(canopy.mesh, pa12(kThickCanopy), canopy.lc),
                               ShellModel(plate, pa12(0.003), plate_lc)};
  for (const ShellModel& model : models) {
    const Eigen::VectorXd full = Eigen::VectorXd::Ones(model.num_faces());
    NewtonSettings plain_settings;
    plain_settings.load_stepping = false;
    EquilibriumSolver plain(model, plain_settings);
    const EquilibriumStats plain_stats = plain.solve(full);
    EXPECT_EQ(plain_stats.load_steps, 0);

    NewtonSettings stepped_settings;
    stepped_settings.first_load_step = 0.25;
    EquilibriumSolver stepped(model, stepped_settings);
    const EquilibriumStats stepped_stats = stepped.solve(full);
    EXPECT_GE(stepped_stats.load_steps, 3);
    EXPECT_TRUE(stepped_stats.converged);

    const double u = plain.max_displacement();
    const double difference = (stepped.positions() - plain.positions()).rowwise().norm().maxCoeff();
    EXPECT_LE(difference, 1e-6 * u) << "largest displacement " << u << " m";
    // The stepped equilibrium's factor serves the adjoint like plain Newton's.
    const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(model.num_dofs());
    EXPECT_LE((stepped.solve_adjoint(rhs) - plain.solve_adjoint(rhs)).norm(),
              1e-6 * plain.solve_adjoint(rhs).norm());
  }
}

}  // namespace
}  // namespace cutwork::solvers

// Sensitivities with respect to the fill ratios: the partials ∂Ŵ/∂α and ∂f/∂α against central
// differences at fixed positions, and the adjoint total derivative dS/dα against
// central differences of the whole equilibrium solve along random directions (one thread).
#include <random>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/energy_density.h"
#include "solvers/objective/structural_quantities.h"
#include "solvers/sensitivity/adjoint.h"
#include "solvers/shell/fill_ratio_partials.h"
#include "solvers/shell/shell_energy.h"
#include "tests/solvers/support/finite_difference.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

/// Every bending model under both fill stiffness rules.
struct ModelVariant {
  BendingModel bending;
  FillStiffness stiffness;
  bool square = false;  ///< the homogenised rule on a square lattice (its anisotropic parts)
  bool roller = false;  ///< one edge held along two axes only (CapFixture's roller)
  bool mirror = false;  ///< one edge on a symmetry plane (CapFixture's mirror)
  std::string name() const {
    return std::string(bending == BendingModel::Hinge ? "hinge" : "shape operator") +
           (stiffness == FillStiffness::Homogenised ? ", homogenised stiffness" : "") +
           (square ? ", square lattice" : "") + (roller ? ", on a roller" : "") + (mirror ? ", on a symmetry plane" : "");
  }
};
const ModelVariant kVariants[] = {{BendingModel::ShapeOperator, FillStiffness::Linear},
                                  {BendingModel::Hinge, FillStiffness::Linear},
                                  {BendingModel::ShapeOperator, FillStiffness::Homogenised},
                                  {BendingModel::Hinge, FillStiffness::Homogenised},
                                  {BendingModel::ShapeOperator, FillStiffness::Homogenised, true},
                                  {BendingModel::Hinge, FillStiffness::Homogenised, true},
                                  {BendingModel::ShapeOperator, FillStiffness::Homogenised, false, true},
                                  {BendingModel::ShapeOperator, FillStiffness::Homogenised, false, false, true}};

TEST(FillRatioPartials, MatchCentralDifferencesAtFixedPositions) {
 for (const ModelVariant& variant : kVariants) {
  SCOPED_TRACE(variant.name());
  test::CapFixture fx(31, variant.bending, variant.stiffness, variant.square, variant.roller, variant.mirror);
  const ShellModel& model = *fx.model;
  const RowMatX3d x = fx.perturbed(32);
  const Eigen::VectorXd& a0 = fx.alpha;

  // ∂Ŵ/∂α
  auto energy = [&](const Eigen::VectorXd& a) { return shell_energy(model, x, a); };
  const auto ce = test::check_gradient(energy, a0, energy_alpha_gradient(model, x, a0), 0.1);
  EXPECT_LE(ce.best, 1e-6) << ce.table();

  // ∂f/∂α with f = −∂Ŵ/∂x + f_ext(α)
  auto force = [&](const Eigen::VectorXd& a) -> Eigen::VectorXd {
    ShellAssembly s;
    assemble_shell(model, x, a, false, s);
    Eigen::VectorXd f = model.gather_free(model.external_forces(a)) - s.gradient;
    model.zero_held(f);  // the supports' reactions there
    return f;
  };
  const Eigen::MatrixXd J = force_alpha_jacobian(model, x, a0);
  const auto cf = test::check_jacobian(force, a0, J, 0.1);
  EXPECT_LE(cf.best, 1e-6) << cf.table();

  // λᵀ ∂f/∂α without forming the matrix.
  std::mt19937 rng(33);
  std::normal_distribution<double> n;
  Eigen::VectorXd lambda(model.num_dofs());
  for (int i = 0; i < lambda.size(); ++i) lambda[i] = n(rng);
  const Eigen::VectorXd product = force_alpha_product(model, x, a0, lambda);
  EXPECT_LE((product - J.transpose() * lambda).norm(), 1e-12 * product.norm());
 }
}

/// Objectives of the kinds the optimiser uses, each with its exact partials.
std::vector<std::pair<std::string, StructuralObjectiveFn>> objectives() {
  std::vector<std::pair<std::string, StructuralObjectiveFn>> list;
  list.emplace_back("compliance", [](const ShellModel& m, const RowMatX3d& x, const Eigen::VectorXd& a) {
    return compliance_terms(m, x, a);
  });
  list.emplace_back("strain energy", [](const ShellModel& m, const RowMatX3d& x, const Eigen::VectorXd& a) {
    return strain_energy_terms(m, x, a);
  });
  // A smooth energy-density objective: S = Σ_i A_i W_i² / 2 (like (17) without the threshold).
  list.emplace_back("energy density", [](const ShellModel& m, const RowMatX3d& x, const Eigen::VectorXd& a) {
    const Eigen::VectorXd W = energy_density(m, x, a);
    const Eigen::VectorXd& A = m.mesh().face_areas();
    ObjectiveTerms t;
    t.value = 0.5 * A.dot(W.cwiseProduct(W));
    energy_density_vjp(m, x, a, A.cwiseProduct(W), &t.d_positions, &t.d_alpha);
    return t;
  });
  // Explicit in both x and α: S = Σ_v u_v,z² + Σ_t α_t² A_t.
  list.emplace_back("mixed", [](const ShellModel& m, const RowMatX3d& x, const Eigen::VectorXd& a) {
    const RowMatX3d u = x - m.rest_positions();
    ObjectiveTerms t;
    t.value = u.col(2).squaredNorm() + a.cwiseProduct(a).dot(m.mesh().face_areas());
    t.d_positions = RowMatX3d::Zero(x.rows(), 3);
    t.d_positions.col(2) = 2 * u.col(2);
    t.d_alpha = 2 * a.cwiseProduct(m.mesh().face_areas());
    return t;
  });
  return list;
}

TEST(AdjointSensitivity, MatchesCentralDifferencesOfTheEquilibrium) {
  // Threading fixed: everything runs in a one-thread arena.
  tbb::task_arena(1).execute([] {
 for (const ModelVariant& variant : kVariants) {
  SCOPED_TRACE(variant.name());
  test::CapFixture fx(39, variant.bending, variant.stiffness, variant.square, variant.roller, variant.mirror);
  const ShellModel& model = *fx.model;
  NewtonSettings settings;
  settings.residual_tolerance = 1e-12;
  EquilibriumSolver solver(model, settings);
  const EquilibriumStats& stats = solver.solve(fx.alpha);
  ASSERT_TRUE(stats.stable);
  const double umax = solver.max_displacement();
  std::cout << variant.name() << " adjoint fixture: max displacement " << umax << " m (" << umax / test::pa12().thickness
            << " h), " << stats.newton_iterations << " Newton iterations\n";
  EXPECT_GT(umax, 0.3 * test::pa12().thickness);  // geometrically nonlinear on purpose
  // A roller's held axes stay exactly at rest through the nonlinear solve.
  for (std::size_t v = 0; v < fx.lc.held_axes.size(); ++v)
    for (int a = 0; a < 3; ++a)
      if (fx.lc.held_axes[v] & (1u << a)) {
        EXPECT_EQ(solver.positions()(Eigen::Index(v), a), model.rest_positions()(Eigen::Index(v), a));
      }

  // A fresh solver per evaluation, started cold: the finite differences must not depend on warm
  // starts.
  auto solve_at = [&](const Eigen::VectorXd& a) {
    EquilibriumSolver s(model, settings);
    s.solve(a);
    return s.positions();
  };

  std::mt19937 rng(40);
  std::normal_distribution<double> n;
  for (const auto& [name, objective] : objectives()) {
    const Sensitivity sens = fill_ratio_sensitivity(solver, objective);
    for (int trial = 0; trial < 2; ++trial) {
      Eigen::VectorXd dir(model.num_faces());
      for (int i = 0; i < dir.size(); ++i) dir[i] = n(rng);
      dir.normalize();
      const double analytic = sens.gradient.dot(dir);
      auto along = [&](const Eigen::VectorXd& t) {
        const Eigen::VectorXd a = fx.alpha + t[0] * dir;
        return objective(model, solve_at(a), a).value;
      };
      const auto c = test::check_gradient(along, Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, analytic),
                                          0.5);
      std::cout << "  " << name << ", direction " << trial << ": relative error " << c.best << "\n";
      EXPECT_LE(c.best, 1e-6) << name << ", direction " << trial << ": dS/dalpha.d = " << analytic << "\n"
                              << c.table();
    }
  }
 }
  });
}

}  // namespace
}  // namespace cutwork::solvers

// The shell's partials with respect to the fill ratios at fixed positions, ∂Ŵ/∂α and ∂f/∂α (and the
// product λᵀ ∂f/∂α the adjoint uses), against central differences.
#include <random>

#include <gtest/gtest.h>

#include "solvers/shell/fill_ratio_partials.h"
#include "solvers/shell/shell_energy.h"
#include "tests/solvers/support/finite_difference.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

const BendingModel kBendingModels[] = {BendingModel::ShapeOperator, BendingModel::Hinge};
const char* bending_name(BendingModel b) { return b == BendingModel::Hinge ? "hinge" : "shape operator"; }

TEST(FillRatioPartials, MatchCentralDifferencesAtFixedPositions) {
 for (BendingModel bending : kBendingModels) {
  SCOPED_TRACE(bending_name(bending));
  test::CapFixture fx(31, bending);
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
    return model.gather_free(model.external_forces(a)) - s.gradient;
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

}  // namespace
}  // namespace cutwork::solvers

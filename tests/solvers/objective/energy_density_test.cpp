// The energy density W (16): its vector-Jacobian products against central differences in x and α,
// and its meaning as a density of the remaining material. The partials of the strain energy and
// compliance objectives against central differences.
#include <random>

#include <gtest/gtest.h>

#include "solvers/objective/energy_density.h"
#include "solvers/objective/structural_quantities.h"
#include "tests/solvers/support/finite_difference.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

TEST(EnergyDensity, VectorJacobianProductsMatchCentralDifferences) {
 for (FillStiffness stiffness : {FillStiffness::Linear, FillStiffness::Homogenised})
 for (bool square : {false, true})
 for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
  if (square && stiffness == FillStiffness::Linear) continue;
  SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
  SCOPED_TRACE(stiffness == FillStiffness::Homogenised ? "homogenised" : "linear");
  SCOPED_TRACE(square ? "square lattice" : "");
  test::CapFixture fx(34, bending, stiffness, square);
  const ShellModel& model = *fx.model;
  const RowMatX3d x = fx.perturbed(35);
  std::mt19937 rng(36);
  std::normal_distribution<double> n;
  Eigen::VectorXd c(model.num_faces());
  for (int i = 0; i < c.size(); ++i) c[i] = n(rng);

  RowMatX3d dx;
  Eigen::VectorXd da;
  energy_density_vjp(model, x, fx.alpha, c, &dx, &da);

  auto of_alpha = [&](const Eigen::VectorXd& a) { return c.dot(energy_density(model, x, a)); };
  if (bending == BendingModel::Hinge || stiffness == FillStiffness::Homogenised) {
    EXPECT_GT(da.norm(), 0.0);
    const auto ca = test::check_gradient(of_alpha, fx.alpha, da, 0.1);
    EXPECT_LE(ca.best, 1e-6) << ca.table();
  } else {
    // W is the energy per remaining area at the local strain: no α dependence at fixed positions.
    EXPECT_EQ(da.norm(), 0.0);
    const double scale = c.cwiseAbs().dot(energy_density(model, x, fx.alpha));
    const auto ca = test::check_gradient(of_alpha, fx.alpha, da, 0.1, scale);
    EXPECT_LE(ca.best, 1e-12) << ca.table();
  }

  auto of_positions = [&](const Eigen::VectorXd& xf) {
    RowMatX3d y = x;
    model.scatter_free(xf, y);
    return c.dot(energy_density(model, y, fx.alpha));
  };
  const auto cx = test::check_gradient(of_positions, model.gather_free(x), model.gather_free(dx), 0.01);
  EXPECT_LE(cx.best, 1e-6) << cx.table();
  for (int v = 0; v < model.num_vertices(); ++v)
    if (model.fixed()[v]) {
      EXPECT_EQ(dx.row(v).squaredNorm(), 0.0);
    }
 }
}

TEST(EnergyDensity, MembraneDensityIsPsiAndIndependentOfUniformAlpha) {
  test::CapFixture fx(37);
  const ShellModel& model = *fx.model;
  const RowMatX3d x = fx.perturbed(38);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(model.num_faces());
  // W is a density of the remaining material: independent of α with the shape operator, and
  // dependent only through the hinge shares (which a uniform α leaves unchanged) with hinges.
  const Eigen::VectorXd W1 = energy_density(model, x, ones);
  const Eigen::VectorXd W03 = energy_density(model, x, 0.3 * ones);
  EXPECT_LE((W1 - W03).norm(), 1e-12 * W1.norm());
  EXPECT_GT(W1.minCoeff(), 0.0);
}

TEST(StructuralQuantities, ObjectivePartialsMatchCentralDifferences) {
  test::CapFixture fx(41);
  const ShellModel& model = *fx.model;
  const RowMatX3d x = fx.perturbed(42);
  for (const auto& [name, terms] :
       {std::pair{"strain energy", &strain_energy_terms}, std::pair{"compliance", &compliance_terms}}) {
    const ObjectiveTerms t = terms(model, x, fx.alpha);
    auto of_alpha = [&](const Eigen::VectorXd& a) { return terms(model, x, a).value; };
    const auto ca = test::check_gradient(of_alpha, fx.alpha, t.d_alpha, 0.1);
    EXPECT_LE(ca.best, 1e-6) << name << "\n" << ca.table();
    auto of_positions = [&](const Eigen::VectorXd& xf) {
      RowMatX3d y = x;
      model.scatter_free(xf, y);
      return terms(model, y, fx.alpha).value;
    };
    const auto cx = test::check_gradient(of_positions, model.gather_free(x), model.gather_free(t.d_positions), 0.01);
    EXPECT_LE(cx.best, 1e-6) << name << "\n" << cx.table();
  }
  // The summary agrees with the objectives.
  const EquilibriumSummary s = summarize_equilibrium(model, x, fx.alpha);
  EXPECT_DOUBLE_EQ(s.strain_energy, strain_energy_terms(model, x, fx.alpha).value);
  EXPECT_DOUBLE_EQ(s.compliance, compliance_terms(model, x, fx.alpha).value);
  EXPECT_DOUBLE_EQ(s.W_max, s.energy_density.maxCoeff());
}

}  // namespace
}  // namespace cutwork::solvers

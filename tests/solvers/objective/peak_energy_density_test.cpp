// The peak energy density W_peak of solvers/objective/peak_energy_density.h: with K = 1 it is the
// mean W; a pure membrane state scales by K_m(α) face by face; an uncut face (α = 1) keeps its W.
// Its vector–Jacobian products (the structure.measure "peak" objective) against central
// differences; the ramp of K to 1 near α = 1 is C¹. summarize_equilibrium's W_peak_max.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "host/core/error.h"
#include "solvers/objective/energy_density.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/objective/structural_objective.h"
#include "solvers/objective/structural_quantities.h"
#include "tests/solvers/support/finite_difference.h"
#include "tests/solvers/support/shell_fixtures.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

FillStiffnessCurve with_concentration(FillStiffnessCurve c, std::vector<double> km, std::vector<double> kb) {
  c.membrane_concentration = std::move(km);
  c.bending_concentration = std::move(kb);
  return c;
}

/// The fixture's shell with concentration samples (K_b ≠ K_m, so that mixing them up shows).
ShellModel concentrated(const test::CapFixture& fx) {
  MechanicsSettings mech = fx.model->mechanics();
  mech.stiffness_curve = with_concentration(mech.stiffness_curve, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0},
                                            {1.9, 1.8, 1.7, 1.6, 1.5, 1.45});
  return ShellModel(fx.mesh, test::pa12(), fx.lc, mech);
}

TEST(PeakEnergyDensity, UnitConcentrationGivesTheMeanDensity) {
  for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
    SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
    test::CapFixture fx(51, bending, FillStiffness::Homogenised);
    const ShellModel& model = *fx.model;
    const RowMatX3d x = fx.perturbed(52);
    const std::vector<double> ones(test::test_stiffness_curve().alpha.size(), 1.0);
    const ConcentrationMap K(with_concentration(model.mechanics().stiffness_curve, ones, ones));
    ASSERT_FALSE(K.empty());
    const Eigen::VectorXd W = energy_density(model, x, fx.alpha);
    const Eigen::VectorXd P = peak_energy_density(model, x, fx.alpha, K);
    ASSERT_EQ(P.size(), W.size());
    // W_peak = r_m U/A + (r_b/r_b)(W − r_m U/A): W up to the round-off of one subtraction.
    for (int t = 0; t < W.size(); ++t) EXPECT_NEAR(P[t], W[t], 1e-14 * W.maxCoeff()) << "face " << t;
  }
}

TEST(PeakEnergyDensity, UnitConcentrationAndUnitRatiosGiveTheMeanDensityUnderTheLinearRule) {
  test::CapFixture fx(53);  // linear fill stiffness
  const ShellModel& model = *fx.model;
  const RowMatX3d x = fx.perturbed(54);
  const std::vector<double> a{0.3, 0.6, 1.0}, ones(3, 1.0);
  FillStiffnessCurve unit;
  unit.alpha = a, unit.membrane = ones, unit.bending = ones;
  const ConcentrationMap K(with_concentration(unit, ones, ones));
  const Eigen::VectorXd W = energy_density(model, x, fx.alpha);
  const Eigen::VectorXd P = peak_energy_density(model, x, fx.alpha, K);
  for (int t = 0; t < W.size(); ++t) EXPECT_NEAR(P[t], W[t], 1e-14 * W.maxCoeff()) << "face " << t;
}

// A flat plate stretched uniformly in its plane stores membrane energy only: W_peak_t = K_m(α_t) W_t.
// Faces take sample fill ratios, where the interpolated K_m is the sample itself; K_b differs from
// K_m so that mixing them up shows.
TEST(PeakEnergyDensity, UniformMembraneStateScalesByTheMembraneConcentration) {
  const SurfaceMesh mesh = test::grid_rectangle(0.4, 0.3, 6, 5);
  LoadCase lc;
  lc.fixed.assign(mesh.num_vertices(), false);
  lc.clamped.assign(mesh.num_vertices(), false);
  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() < 1e-9; })) lc.fixed[v] = lc.clamped[v] = true;
  lc.forces = RowMatX3d::Zero(mesh.num_vertices(), 3);
  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() > 0.4 - 1e-9; })) lc.forces(v, 0) = 1;
  MechanicsSettings mech;
  mech.stiffness = FillStiffness::Homogenised;
  const FillStiffnessCurve base = test::test_stiffness_curve();  // α = 0.3 0.45 0.6 0.75 0.9 1
  const std::vector<double> km{3.1, 2.7, 2.4, 2.2, 2.05, 2.0}, kb{1.9, 1.8, 1.7, 1.6, 1.5, 1.45};
  mech.stiffness_curve = with_concentration(base, km, kb);
  const ShellModel model(mesh, test::pa12(), lc, mech);
  const ConcentrationMap K(model.mechanics().stiffness_curve);

  // Uniform strain: ε_xx = 1e-3, ε_yy = −0.4e-3, γ_xy = 0.6e-3 (displacement gradient, small).
  RowMatX3d x = mesh.vertices();
  for (int v = 0; v < x.rows(); ++v) {
    const double X = x(v, 0), Y = x(v, 1);
    x(v, 0) += 1e-3 * X + 0.3e-3 * Y;
    x(v, 1) += 0.3e-3 * X - 0.4e-3 * Y;
  }
  Eigen::VectorXd alpha(mesh.num_faces());
  const std::vector<int> pick{0, 1, 2, 3, 4, 5};  // every sample, the uncut α = 1 included
  for (int t = 0; t < alpha.size(); ++t) alpha[t] = base.alpha[size_t(pick[size_t(t % 6)])];
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  const Eigen::VectorXd P = peak_energy_density(model, x, alpha, K);
  ASSERT_GT(W.minCoeff(), 0.0);
  for (int t = 0; t < W.size(); ++t) {
    const size_t s = size_t(t % 6);
    // α = 1 is uncut: K = 1 there, not the dilute limit the last sample holds.
    const double expected = s == 5 ? 1.0 : km[s];
    EXPECT_NEAR(P[t] / W[t], expected, 1e-12) << "face " << t << " α " << alpha[t];
    EXPECT_NEAR(K.membrane(alpha[t]), expected, 1e-15);
  }
  // Weighted (the cell filter's blend): w = 0 where a face resolves its stencils gives W itself,
  // w = ½ the factor halfway to 1, w = 1 the unweighted value.
  Eigen::VectorXd w(alpha.size());
  for (int t = 0; t < w.size(); ++t) w[t] = (t / 6) % 3 * 0.5;
  const Eigen::VectorXd Pw = peak_energy_density(model, x, alpha, K, &w);
  for (int t = 0; t < W.size(); ++t) {
    const size_t s = size_t(t % 6);
    const double k = s == 5 ? 1.0 : km[s];
    EXPECT_NEAR(Pw[t] / W[t], 1 + w[t] * (k - 1), 1e-12) << "face " << t << " weight " << w[t];
  }
  // Between samples K_m interpolates without overshoot.
  for (double a : {0.35, 0.5, 0.7, 0.95}) {
    EXPECT_LT(K.membrane(a), 3.1);
    EXPECT_GT(K.membrane(a), 2.0);
  }
}

// summarize_equilibrium reports W_peak_max over the material faces when the mechanics carries
// concentration samples, and NaN (face −1, no field) when it does not.
TEST(PeakEnergyDensity, EquilibriumSummaryCarriesWPeakMaxOnlyWithConcentrationSamples) {
  test::CapFixture fx(55, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  const RowMatX3d x = fx.perturbed(56);
  Eigen::VectorXd alpha = fx.alpha;
  alpha.head(5).setConstant(1e-4);  // filler: not material
  {
    const EquilibriumSummary s = summarize_equilibrium(*fx.model, x, alpha);
    EXPECT_TRUE(std::isnan(s.W_peak_max));
    EXPECT_EQ(s.W_peak_max_face, -1);
    EXPECT_EQ(s.peak_energy_density.size(), 0);
  }
  MechanicsSettings mech = fx.model->mechanics();
  mech.stiffness_curve = with_concentration(mech.stiffness_curve, {3.0, 2.6, 2.3, 2.1, 2.0, 1.9},
                                            {1.8, 1.7, 1.6, 1.5, 1.45, 1.4});
  const ShellModel model(fx.mesh, test::pa12(), fx.lc, mech);
  const EquilibriumSummary s = summarize_equilibrium(model, x, alpha);
  const Eigen::VectorXd P = peak_energy_density(model, x, alpha, ConcentrationMap(mech.stiffness_curve));
  ASSERT_EQ(s.peak_energy_density.size(), P.size());
  EXPECT_EQ((s.peak_energy_density - P).norm(), 0.0);
  double expected = 0;
  int face = -1;
  for (int t = 0; t < P.size(); ++t)
    if (alpha[t] > kMaterialFillRatio && P[t] > expected) expected = P[t], face = t;
  EXPECT_EQ(s.W_peak_max, expected);
  EXPECT_EQ(s.W_peak_max_face, face);
  EXPECT_GT(s.W_peak_max, s.W_max);  // every K exceeds 1
}

// K ramps from its dilute sample to 1 over [1 − δ, 1]: continuous at both ends, its slope the
// derivative of the value (central differences), and 1 at α = 1 exactly.
TEST(PeakEnergyDensity, ConcentrationRampsToOneNearTheUncutFaceWithAContinuousSlope) {
  const FillStiffnessCurve base = test::test_stiffness_curve();  // α = 0.3 0.45 0.6 0.75 0.9 1
  const ConcentrationMap K(with_concentration(base, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0}, {1.9, 1.8, 1.7, 1.6, 1.5, 1.45}));
  const double d = kConcentrationRamp;
  for (auto k : {&ConcentrationMap::membrane, &ConcentrationMap::bending}) {
    auto value = [&](double a) { return (K.*k)(a, nullptr); };
    EXPECT_NEAR(value(1 - 1e-12), 1.0, 1e-9);
    EXPECT_EQ(value(1.0), 1.0);
    EXPECT_NEAR(value(1 - d - 1e-10), value(1 - d + 1e-10), 1e-8);  // value continuous at 1 − δ
    for (double a : {0.5, 0.92, 1 - d - 1e-4, 1 - d + 1e-4, 0.97, 0.99, 0.999}) {
      double slope = 0;
      (K.*k)(a, &slope);
      const double h = 1e-6;
      EXPECT_NEAR(slope, (value(a + h) - value(a - h)) / (2 * h), 1e-5 * std::max(1.0, std::abs(slope))) << "α " << a;
    }
    // The slope is continuous across 1 − δ (C¹): both sides agree.
    double below = 0, above = 0;
    (K.*k)(1 - d - 1e-9, &below);
    (K.*k)(1 - d + 1e-9, &above);
    EXPECT_NEAR(below, above, 1e-5 * std::max(1.0, std::abs(below)));
  }
  // Midway through the ramp: 1 + (K − 1)·s(½) = 1 + (K − 1)/2.
  double k_mid = 0;
  {
    // K's own value at the midpoint, continued past 1 − δ without the ramp, is not exposed: use
    // a curve flat near 1 (the last two samples equal) where it is the sample itself.
    const ConcentrationMap flat(with_concentration(base, {3, 3, 3, 3, 2.0, 2.0}, {2, 2, 2, 2, 1.5, 1.5}));
    k_mid = flat.membrane(1 - d / 2);
    EXPECT_NEAR(k_mid, 1.5, 1e-12);
    EXPECT_NEAR(flat.bending(1 - d / 2), 1.25, 1e-12);
  }
}

// Σ c_t W_peak_t: its gradients in x and α (at fixed blend weights) against central differences,
// with fill ratios across the samples, between them and in the ramp, for both bending models.
TEST(PeakEnergyDensity, VectorJacobianProductsMatchCentralDifferences) {
  for (bool square : {false, true})
  for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
    SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
    SCOPED_TRACE(square ? "square lattice" : "hexagonal lattice");
    test::CapFixture fx(61, bending, FillStiffness::Homogenised, square);
    const ShellModel model = concentrated(fx);
    const ConcentrationMap K(model.mechanics().stiffness_curve);
    const RowMatX3d x = fx.perturbed(62);
    Eigen::VectorXd alpha = fx.alpha;
    const double ramp[] = {0.955, 0.97, 0.985, 0.994};
    for (int t = 0; t < alpha.size(); t += 5) alpha[t] = ramp[(t / 5) % 4];
    std::mt19937 rng(63);
    std::normal_distribution<double> n;
    std::uniform_real_distribution<double> u(0, 1);
    Eigen::VectorXd c(model.num_faces()), w(model.num_faces());
    for (int i = 0; i < c.size(); ++i) c[i] = n(rng), w[i] = i % 7 == 0 ? 0.0 : u(rng);

    const Eigen::VectorXd* no_weight = nullptr;
    const Eigen::VectorXd* with_weight = &w;
    for (const Eigen::VectorXd* weight : {no_weight, with_weight}) {
      SCOPED_TRACE(weight ? "blend weights" : "no weights");
      RowMatX3d dx;
      Eigen::VectorXd da;
      peak_energy_density_vjp(model, x, alpha, K, weight, c, &dx, &da);
      auto of_alpha = [&](const Eigen::VectorXd& a) { return c.dot(peak_energy_density(model, x, a, K, weight)); };
      EXPECT_GT(da.norm(), 0.0);
      const auto ca = test::check_gradient(of_alpha, alpha, da, 0.01);
      EXPECT_LE(ca.best, 1e-6) << ca.table();
      auto of_positions = [&](const Eigen::VectorXd& xf) {
        RowMatX3d y = x;
        model.scatter_free(xf, y);
        return c.dot(peak_energy_density(model, y, alpha, K, weight));
      };
      const auto cx = test::check_gradient(of_positions, model.gather_free(x), model.gather_free(dx), 0.01);
      EXPECT_LE(cx.best, 1e-6) << cx.table();
      for (int v = 0; v < model.num_vertices(); ++v)
        if (model.fixed()[v]) {
          EXPECT_EQ(dx.row(v).squaredNorm(), 0.0);
        }
      // Either output alone gives the same numbers.
      RowMatX3d dx_only;
      Eigen::VectorXd da_only;
      peak_energy_density_vjp(model, x, alpha, K, weight, c, &dx_only, nullptr);
      peak_energy_density_vjp(model, x, alpha, K, weight, c, nullptr, &da_only);
      EXPECT_EQ((dx_only - dx).norm(), 0.0);
      EXPECT_EQ((da_only - da).norm(), 0.0);
    }
  }
}

// The peak objective S = (1/m) Σ ½ ((W_peak − β)₊/W_ref)²: its value is built on W_peak (above β
// where W is not), and its partials match central differences.
TEST(PeakEnergyDensity, PeakObjectiveThresholdsWPeakAndItsPartialsMatchCentralDifferences) {
  test::CapFixture fx(64, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  const ShellModel model = concentrated(fx);
  const ConcentrationMap K(model.mechanics().stiffness_curve);
  const RowMatX3d x = fx.perturbed(65);
  const Eigen::VectorXd W = energy_density(model, x, fx.alpha);
  const Eigen::VectorXd P = peak_energy_density(model, x, fx.alpha, K);
  // β between the two maxima: the mean measure is below it everywhere, the peak is not.
  const double beta = W.maxCoeff() * 1.01, w_ref = W.maxCoeff();
  ASSERT_GT(P.maxCoeff(), beta);
  const PeakMeasure peak{&K, nullptr};
  Eigen::VectorXd measured;
  EXPECT_EQ(energy_density_objective(model, x, fx.alpha, beta, w_ref).value, 0.0);
  const ObjectiveTerms t = energy_density_objective(model, x, fx.alpha, beta, w_ref, &measured, &peak);
  EXPECT_EQ((measured - P).norm(), 0.0);
  double expected = 0;
  for (int i = 0; i < P.size(); ++i) expected += 0.5 * std::pow(std::max(0.0, P[i] - beta) / w_ref, 2);
  EXPECT_NEAR(t.value, expected / P.size(), 1e-14 * expected);
  auto of_alpha = [&](const Eigen::VectorXd& a) { return energy_density_objective(model, x, a, beta, w_ref, nullptr, &peak).value; };
  const auto ca = test::check_gradient(of_alpha, fx.alpha, t.d_alpha, 0.01);
  EXPECT_LE(ca.best, 1e-5) << ca.table();
  auto of_positions = [&](const Eigen::VectorXd& xf) {
    RowMatX3d y = x;
    model.scatter_free(xf, y);
    return energy_density_objective(model, y, fx.alpha, beta, w_ref, nullptr, &peak).value;
  };
  const auto cx = test::check_gradient(of_positions, model.gather_free(x), model.gather_free(t.d_positions), 0.01);
  EXPECT_LE(cx.best, 1e-5) << cx.table();
}

TEST(PeakEnergyDensity, RejectsMalformedConcentrationSamples) {
  const FillStiffnessCurve base = test::test_stiffness_curve();
  const std::vector<double> ok(base.alpha.size(), 1.5);
  std::vector<double> low = ok;
  low[2] = 0.9;
  EXPECT_THROW(ConcentrationMap(with_concentration(base, low, ok)), InputError);
  EXPECT_THROW(ConcentrationMap(with_concentration(base, ok, {1.5, 1.5})), InputError);
  EXPECT_TRUE(ConcentrationMap(base).empty());
  EXPECT_EQ(ConcentrationMap().membrane(0.4), 1.0);
}

}  // namespace
}  // namespace cutwork::solvers

// The peak energy density W_peak of solvers/objective/peak_energy_density.h: with K = 1 it is the
// mean W; a pure membrane state scales by K_m(α) face by face; an uncut face (α = 1) keeps its W.
// Its vector–Jacobian products (the structure.measure "peak" objective) against central
// differences; the ramp of K to 1 near α = 1 is C¹. summarize_equilibrium's W_peak_max.
#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>
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

/// A flat plate of length 0.4 m along x clamped at x = 0, a unit force along axis `axis` at each
/// vertex of its far end.
LoadCase cantilever(const SurfaceMesh& mesh, int axis) {
  LoadCase lc;
  lc.fixed.assign(mesh.num_vertices(), false);
  lc.clamped.assign(mesh.num_vertices(), false);
  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() < 1e-9; })) lc.fixed[v] = lc.clamped[v] = true;
  lc.forces = RowMatX3d::Zero(mesh.num_vertices(), 3);
  for (int v : test::select_vertices(mesh, [](const Vec3& p) { return p.x() > 0.4 - 1e-9; })) lc.forces(v, axis) = 1;
  return lc;
}

/// Tables of K by biaxiality made from the worst states' samples (test::test_biaxiality_table).
FillStiffnessCurve with_biaxiality(FillStiffnessCurve c) {
  c.membrane_concentration_by_biaxiality = test::test_biaxiality_table(c.membrane_concentration);
  c.bending_concentration_by_biaxiality = test::test_biaxiality_table(c.bending_concentration);
  return c;
}

/// The fixture's shell with concentration samples (K_b ≠ K_m, so that mixing them up shows), and
/// with `by_state` their tables by biaxiality.
ShellModel concentrated(const test::CapFixture& fx, bool by_state = false) {
  MechanicsSettings mech = fx.model->mechanics();
  mech.stiffness_curve = with_concentration(mech.stiffness_curve, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0},
                                            {1.9, 1.8, 1.7, 1.6, 1.5, 1.45});
  if (by_state) mech.stiffness_curve = with_biaxiality(mech.stiffness_curve);
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
  const LoadCase lc = cantilever(mesh, 0);
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

TEST(PeakEnergyDensity, ASymmetryPlaneIsNoSupportForThePeakAwayFromSupports) {
  LoadCase lc;
  lc.fixed = {true, false, false, false};
  lc.clamped = {false, false, false, false};
  lc.held_axes = {0, kHeldY, kHeldY | kHeldZ, 0};
  lc.symmetry_axes = {0, kHeldY, kHeldY, 0};  // 1: on the plane y = c alone; 2: on it and held along z
  EXPECT_EQ(supported_vertices(lc), (std::vector<bool>{true, true, true, false}));
  EXPECT_EQ(support_held_vertices(lc), (std::vector<bool>{true, false, true, false}));
}

// K ramps from its dilute sample to 1 over [1 − δ, 1]: continuous at both ends, its slope the
// derivative of the value (central differences), and 1 at α = 1 exactly.
TEST(PeakEnergyDensity, ConcentrationRampsToOneNearTheUncutFaceWithAContinuousSlope) {
  const FillStiffnessCurve base = test::test_stiffness_curve();  // α = 0.3 0.45 0.6 0.75 0.9 1
  const ConcentrationMap K(with_concentration(base, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0}, {1.9, 1.8, 1.7, 1.6, 1.5, 1.45}));
  const double d = kConcentrationRamp;
  using Factor = double (ConcentrationMap::*)(double, double*) const;
  for (Factor k : {static_cast<Factor>(&ConcentrationMap::membrane), static_cast<Factor>(&ConcentrationMap::bending)}) {
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
// with fill ratios across the samples, between them and in the ramp, for both bending models, with
// the worst state's K and with K by the faces' biaxiality (whose ρ moves with x and, through the
// split's ratios, with α).
TEST(PeakEnergyDensity, VectorJacobianProductsMatchCentralDifferences) {
  for (bool by_state : {false, true})
  for (bool square : {false, true})
  for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
    SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
    SCOPED_TRACE(square ? "square lattice" : "hexagonal lattice");
    SCOPED_TRACE(by_state ? "K by biaxiality" : "the worst state's K");
    test::CapFixture fx(61, bending, FillStiffness::Homogenised, square);
    const ShellModel model = concentrated(fx, by_state);
    const ConcentrationMap K(model.mechanics().stiffness_curve);
    ASSERT_EQ(K.by_biaxiality(), by_state);
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
  // Tables by biaxiality: a short row, a row too many, a factor below 1, one part without the other.
  const FillStiffnessCurve good = with_biaxiality(with_concentration(base, ok, ok));
  EXPECT_TRUE(ConcentrationMap(good).by_biaxiality());
  FillStiffnessCurve bad = good;
  bad.membrane_concentration_by_biaxiality[1].pop_back();
  EXPECT_THROW(ConcentrationMap{bad}, InputError);
  bad = good;
  bad.bending_concentration_by_biaxiality.push_back(bad.bending_concentration_by_biaxiality.back());
  EXPECT_THROW(ConcentrationMap{bad}, InputError);
  bad = good;
  bad.membrane_concentration_by_biaxiality[2][3] = 0.8;
  EXPECT_THROW(ConcentrationMap{bad}, InputError);
  bad = good;
  bad.bending_concentration_by_biaxiality.clear();
  EXPECT_THROW(ConcentrationMap{bad}, InputError);
}

// K(α, ρ) by biaxiality: the node values at the nodes (sample α: the samples themselves), 1 at
// α = 1, C¹ in ρ (Catmull–Rom) with both slopes the derivatives of the value, and the worst
// state's K where the curve has no table.
TEST(PeakEnergyDensity, ConcentrationByBiaxialityInterpolatesTheNodesWithExactSlopes) {
  const FillStiffnessCurve base = test::test_stiffness_curve();  // α = 0.3 0.45 0.6 0.75 0.9 1
  const FillStiffnessCurve curve =
      with_biaxiality(with_concentration(base, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0}, {1.9, 1.8, 1.7, 1.6, 1.5, 1.45}));
  const ConcentrationMap K(curve);
  for (size_t s = 0; s + 1 < base.alpha.size(); ++s)
    for (int j = 0; j < kBiaxialityNodes; ++j) {
      EXPECT_NEAR(K.membrane(base.alpha[s], biaxiality_node(j), nullptr, nullptr),
                  curve.membrane_concentration_by_biaxiality[s][size_t(j)], 1e-13);
      EXPECT_NEAR(K.bending(base.alpha[s], biaxiality_node(j), nullptr, nullptr),
                  curve.bending_concentration_by_biaxiality[s][size_t(j)], 1e-13);
    }
  EXPECT_EQ(K.membrane(1.0, 0.3, nullptr, nullptr), 1.0);
  const double h = 1e-6;
  for (double a : {0.33, 0.52, 0.8, 0.97})
    for (double r : {-0.999, -0.8, -0.37, 0.0, 0.1, 0.5, 0.77, 0.999}) {
      double da = 0, dr = 0;
      const double k = K.membrane(a, r, &da, &dr);
      EXPECT_GE(k, 1.0);
      const auto at = [&](double aa, double rr) { return K.membrane(aa, rr, nullptr, nullptr); };
      EXPECT_NEAR(da, (at(a + h, r) - at(a - h, r)) / (2 * h), 1e-5 * std::max(1.0, std::abs(da))) << a << " " << r;
      EXPECT_NEAR(dr, (at(a, r + h) - at(a, r - h)) / (2 * h), 1e-5 * std::max(1.0, std::abs(dr))) << a << " " << r;
    }
  // C¹ across a node: the ρ-slopes on both sides agree.
  for (int j = 1; j + 1 < kBiaxialityNodes; ++j) {
    double below = 0, above = 0;
    K.bending(0.52, biaxiality_node(j) - 1e-10, nullptr, &below);
    K.bending(0.52, biaxiality_node(j) + 1e-10, nullptr, &above);
    EXPECT_NEAR(below, above, 1e-6 * std::max(1.0, std::abs(below))) << "node " << j;
  }
  // Without tables: the worst state's K, and no ρ-slope.
  const ConcentrationMap worst(with_concentration(base, {3.1, 2.7, 2.4, 2.2, 2.05, 2.0}, {1.9, 1.8, 1.7, 1.6, 1.5, 1.45}));
  double dr = 1;
  EXPECT_EQ(worst.membrane(0.52, -0.4, nullptr, &dr), worst.membrane(0.52));
  EXPECT_EQ(dr, 0.0);
}

// The biaxiality ρ of stress and moment: a flat plate in a uniform Green strain E (x = F X with
// F = √(I + 2E) exactly) whose perforated-material stress has principal values (1, ρ) along θ reads
// ρ on every face; bent into w = ½ Xᵀ H X whose moments have principal values (1, ρ), every
// interior face (a full patch: the quadratic is reproduced exactly, and k = n_z H scales both
// principal curvatures alike) reads ρ. The perforated material's stress uses the split's bulk and
// shear ratios at the face's α (with ratios 1, the solid's: the two differ, so using the wrong
// one shows). W_peak of the membrane state is K_m(α, ρ) W.
TEST(PeakEnergyDensity, StressBiaxialityReadsThePrincipalRatioOfUniformStates) {
  const SurfaceMesh mesh = test::grid_rectangle(0.4, 0.3, 8, 6);
  const LoadCase lc = cantilever(mesh, 2);
  MechanicsSettings mech;
  mech.stiffness = FillStiffness::Homogenised;
  mech.stiffness_curve =
      with_biaxiality(with_concentration(test::test_stiffness_curve(), {3.1, 2.7, 2.4, 2.2, 2.05, 2.0},
                                         {1.9, 1.8, 1.7, 1.6, 1.5, 1.45}));
  const ShellModel model(mesh, test::pa12(), lc, mech);
  const ConcentrationMap K(model.mechanics().stiffness_curve);
  const Material& m = model.material();
  const double nu = m.poisson_ratio, E = m.youngs_modulus, h = m.thickness;
  const double kappa = E * h / (2 * (1 - nu)), mu = E * h / (2 * (1 + nu));  // membrane bulk and shear moduli
  const double D = E * h * h * h / (12 * (1 - nu * nu));
  const std::vector<int> interior = [&] {
    std::vector<int> faces;
    for (const ShellBend& b : model.bends())
      if (b.v[3] >= 0 && b.v[4] >= 0 && b.v[5] >= 0) faces.push_back(b.face);
    return faces;
  }();
  ASSERT_GT(interior.size(), 20u);
  for (const double a : {0.6, 1.0})
    for (const double rho : {-1.0, -0.6, 0.0, 0.35, 1.0})
      for (const double theta : {0.0, 0.5}) {
        SCOPED_TRACE(::testing::Message() << "alpha " << a << ", rho " << rho << ", theta " << theta);
        const Eigen::VectorXd alpha = Eigen::VectorXd::Constant(mesh.num_faces(), a);
        const Eigen::Vector2d rm = K.split_ratios(false, a), rb = K.split_ratios(true, a);
        const Eigen::Vector2d n(std::cos(theta), std::sin(theta)), t(-n.y(), n.x());
        const Eigen::Matrix2d sigma = n * n.transpose() + rho * t * t.transpose();  // stress or moment
        const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
        const Eigen::Matrix2d dev = sigma - 0.5 * sigma.trace() * I;
        // Membrane: E = tr σ/(4κ*) I + dev σ/(2μ*), small (1e-4).
        const Eigen::Matrix2d strain = 1e-4 * (sigma.trace() / (4 * kappa * rm[0]) * I + dev / (2 * mu * rm[1])) * E * h;
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(I + 2 * strain);
        const Eigen::Matrix2d F = eig.operatorSqrt();
        RowMatX3d x = mesh.vertices();
        for (int v = 0; v < x.rows(); ++v) x.row(v).head<2>() = (F * x.row(v).head<2>().transpose()).transpose();
        const Eigen::MatrixX2d b = stress_biaxiality(model, x, alpha, K);
        const Eigen::VectorXd W = energy_density(model, x, alpha), P = peak_energy_density(model, x, alpha, K);
        // Tolerances 1e-7: at ρ = ±1 one part's energy is round-off (1e-16 of the other's) and ρ
        // reads its square root.
        for (int f = 0; f < mesh.num_faces(); ++f) {
          EXPECT_NEAR(b(f, 0), rho, 1e-7) << "membrane, face " << f;
          const double k = K.membrane(a, rho, nullptr, nullptr);
          EXPECT_NEAR(P[f], k * W[f], 1e-7 * k * W[f]) << "face " << f;
        }
        // Bending: curvature H = tr M/(2 D (1 + ν) r_K) I + dev M/(D (1 − ν) r_G), w small.
        const Eigen::Matrix2d H = 1e-3 * (sigma.trace() / (2 * D * (1 + nu) * rb[0]) * I + dev / (D * (1 - nu) * rb[1])) * D;
        RowMatX3d y = mesh.vertices();
        for (int v = 0; v < y.rows(); ++v) {
          const Eigen::Vector2d p = y.row(v).head<2>().transpose() - Eigen::Vector2d(0.2, 0.15);
          y(v, 2) = 0.5 * p.dot(H * p);
        }
        const Eigen::MatrixX2d c = stress_biaxiality(model, y, alpha, K);
        for (const int f : interior) EXPECT_NEAR(c(f, 1), rho, 1e-7) << "bending, face " << f;
      }
}

}  // namespace
}  // namespace cutwork::solvers

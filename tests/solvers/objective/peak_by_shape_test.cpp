// W_peak's factors by shape and by corner (solvers/objective/peak_energy_density.h): a face covered
// by one shape reads that shape's factors, exactly the one-shape rule; a face of several shapes the
// smooth maximum, between the largest and 2^(1/p) times it; without a cover, or with a row of
// zeros, the worst shape's factors as before. By corner: the tables at their nodes, linear and
// continuous between, held beyond ε = 1. And the vector–Jacobian products in the cover (covered
// fractions and corner moments) with those in x and α against central differences, through the
// ramp of a shape entering a face.
#include <algorithm>
#include <cmath>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "solvers/objective/energy_density.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/objective/structural_objective.h"
#include "solvers/objective/structural_quantities.h"
#include "tests/solvers/support/finite_difference.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

using test::test_biaxiality_table;

/// Two shapes on the test curve's samples (α = 0.3 0.45 0.6 0.75 0.9 1): a mild one (circle-like)
/// and a sharp one whose factors are larger at some samples and smaller at others (so that neither
/// is the worst everywhere), the worst the samplewise maximum as the calibration makes it.
struct TwoShapes {
  std::vector<double> km[2] = {{2.9, 2.6, 2.5, 2.3, 2.2, 2.1}, {3.4, 4.5, 5.0, 4.8, 1.9, 1.8}};
  std::vector<double> kb[2] = {{1.8, 1.7, 1.6, 1.55, 1.5, 1.45}, {2.2, 1.5, 2.6, 2.7, 2.8, 2.6}};

  /// The curve with both shapes' own factors (`which` < 0) or with shape `which`'s alone as the
  /// curve's only (worst) factors.
  FillStiffnessCurve curve(bool by_state, int which = -1) const {
    FillStiffnessCurve c = test::test_stiffness_curve();
    const size_t n = c.alpha.size();
    std::vector<double> wm(n), wb(n);
    for (size_t i = 0; i < n; ++i) {
      wm[i] = which >= 0 ? km[which][i] : std::max(km[0][i], km[1][i]);
      wb[i] = which >= 0 ? kb[which][i] : std::max(kb[0][i], kb[1][i]);
    }
    c.membrane_concentration = wm;
    c.bending_concentration = wb;
    if (by_state) {
      c.membrane_concentration_by_biaxiality = test_biaxiality_table(wm);
      c.bending_concentration_by_biaxiality = test_biaxiality_table(wb);
    }
    if (which < 0)
      for (int s = 0; s < 2; ++s) {
        FillStiffnessCurve::ShapeConcentration k{km[s], kb[s], {}, {}, {}, {}};
        if (by_state) {
          k.membrane_by_biaxiality = test_biaxiality_table(km[s]), k.bending_by_biaxiality = test_biaxiality_table(kb[s]);
          // Shape 1 has corners: its factors fall with the corner rule's radius ε, towards half
          // their excess at ε = 1; shape 0 (a circle) has the same at every node.
          if (corners) {
            k.membrane_by_corner = by_corner(k.membrane_by_biaxiality, s == 1, tool);
            k.bending_by_corner = by_corner(k.bending_by_biaxiality, s == 1, tool);
          }
        }
        c.shape_concentration.push_back(k);
      }
    c.tool_cut = corners && tool;
    return c;
  }

  /// Tables by corner node from tables by biaxiality: K_c = 1 + (K − 1)(1 − ε_c(1 − ε_c/2)) where
  /// `falls`, K otherwise; by the tool's nodes (`tool`), K_c = 1 + (K − 1)(τ_0/τ_c)^0.8, a round's
  /// peak falling about as 1/τ.
  static std::vector<std::vector<double>> by_corner(const std::vector<std::vector<double>>& table, bool falls,
                                                    bool tool) {
    std::vector<std::vector<double>> out;
    for (const std::vector<double>& row : table) {
      std::vector<double> r;
      for (int c = 0; c < (tool ? kToolNodes : kCornerNodes); ++c) {
        const double e = corner_node(c);
        const double f = !falls ? 1.0 : tool ? std::pow(tool_node(0) / tool_node(c), 0.8) : 1 - e * (1 - 0.5 * e);
        for (const double k : row) r.push_back(1 + (k - 1) * f);
      }
      out.push_back(r);
    }
    return out;
  }

  bool corners = false;  ///< give shape 1 tables by corner (with by_state)
  bool tool = false;     ///< … the tool's, at tool_node(c) (FillStiffnessCurve::tool_cut)
};

/// A cover from covered fractions h, with corner moments h·ε̄ when `epsilon` is given (#F × 2).
ShapeCover make_cover(const Eigen::MatrixXd& h, const Eigen::MatrixXd* epsilon = nullptr) {
  ShapeCover c;
  c.covered = h;
  if (epsilon) c.corner = h.cwiseProduct(*epsilon);
  return c;
}

ShellModel with_curve(const test::CapFixture& fx, const FillStiffnessCurve& curve) {
  MechanicsSettings mech = fx.model->mechanics();
  mech.stiffness_curve = curve;
  return ShellModel(fx.mesh, test::pa12(), fx.lc, mech);
}

/// Fill ratios across the samples and in the ramp near 1, with covered fractions that add up to
/// 1 − α, split between the shapes by `share` (shape 1's part; 0: shape 0 alone).
Eigen::MatrixXd split_cover(const Eigen::VectorXd& alpha, const Eigen::VectorXd& share) {
  Eigen::MatrixXd h(alpha.size(), 2);
  for (Eigen::Index t = 0; t < alpha.size(); ++t) {
    h(t, 1) = share[t] * (1 - alpha[t]);
    h(t, 0) = (1 - alpha[t]) - h(t, 1);
  }
  return h;
}

Eigen::VectorXd varied_alpha(const test::CapFixture& fx) {
  Eigen::VectorXd alpha = fx.alpha;
  const double ramp[] = {0.955, 0.97, 0.985, 0.994};
  for (int t = 0; t < alpha.size(); t += 5) alpha[t] = ramp[(t / 5) % 4];
  return alpha;
}

// One shape in every face: the rule by shape is the one-shape rule of that shape's factors, face
// by face, whatever the state rule, the blend weights and the ramp (1 − α = h, so the ramp in h is
// the ramp in α).
TEST(PeakByShape, AFaceOfOneShapeReadsThatShapesFactors) {
  const TwoShapes shapes;
  for (bool by_state : {false, true}) {
    SCOPED_TRACE(by_state ? "K by biaxiality" : "the worst state's K");
    test::CapFixture fx(71, BendingModel::ShapeOperator, FillStiffness::Homogenised);
    const ShellModel model = with_curve(fx, shapes.curve(by_state));
    const ConcentrationMap K(model.mechanics().stiffness_curve);
    ASSERT_TRUE(K.by_shape());
    ASSERT_EQ(K.num_shapes(), 2);
    ASSERT_TRUE(concentration_by_shape(model.mechanics(), model.material()));
    const RowMatX3d x = fx.perturbed(72);
    const Eigen::VectorXd alpha = varied_alpha(fx);
    Eigen::VectorXd w(model.num_faces());
    for (int t = 0; t < w.size(); ++t) w[t] = (t % 3) / 2.0;
    for (int s = 0; s < 2; ++s) {
      SCOPED_TRACE(s == 0 ? "shape 0 alone" : "shape 1 alone");
      const ShapeCover h = make_cover(split_cover(alpha, Eigen::VectorXd::Constant(alpha.size(), double(s))));
      const ShellModel own_model = with_curve(fx, shapes.curve(by_state, s));
      const ConcentrationMap own(own_model.mechanics().stiffness_curve);
      ASSERT_FALSE(own.by_shape());
      const Eigen::VectorXd P = peak_energy_density(model, x, alpha, K, &w, &h);
      const Eigen::VectorXd P_own = peak_energy_density(own_model, x, alpha, own, &w);
      for (int t = 0; t < P.size(); ++t) EXPECT_NEAR(P[t], P_own[t], 1e-12 * P_own.maxCoeff()) << "face " << t;
    }
    // Without covered fractions, and for rows of zeros, the worst shape's factors (the rule before).
    const Eigen::VectorXd P_worst = peak_energy_density(model, x, alpha, K, &w);
    const ShellModel worst_model = with_curve(fx, [&] {
      FillStiffnessCurve c = shapes.curve(by_state);
      c.shape_concentration.clear();
      return c;
    }());
    const Eigen::VectorXd P_before = peak_energy_density(worst_model, x, alpha, ConcentrationMap(worst_model.mechanics().stiffness_curve), &w);
    EXPECT_EQ((P_worst - P_before).norm(), 0.0);
    const ShapeCover zeros = make_cover(Eigen::MatrixXd::Zero(alpha.size(), 2));
    EXPECT_EQ((peak_energy_density(model, x, alpha, K, &w, &zeros) - P_before).norm(), 0.0);
  }
}

// Two shapes in a face, each past the ramp (h ≥ δ): K − 1 lies between the larger of the two
// shapes' K − 1 and 2^(1/p) times it — the smooth maximum, not the mean and not the sum — and the
// worst shape's K (the samplewise maximum, which takes membrane and bending from different shapes
// at some samples) is never exceeded by more than that factor.
TEST(PeakByShape, AFaceOfTwoShapesReadsTheSmoothMaximum) {
  const TwoShapes shapes;
  test::CapFixture fx(73, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  const FillStiffnessCurve curve = shapes.curve(false);
  const ConcentrationMap K(curve);
  // A uniform membrane state isolates K_m: W_peak − W over W^memb. Read K_m directly instead
  // through shape_factor and a face's mixture.
  const double bound = std::pow(2.0, 1 / kShapeNorm);
  for (const double a : {0.3, 0.5, 0.6}) {
    const double k0 = K.shape_factor(0, false, a, nullptr, 0, nullptr, nullptr);
    const double k1 = K.shape_factor(1, false, a, nullptr, 0, nullptr, nullptr);
    const double largest = std::max(k0, k1) - 1;
    // Through the peak rule: a flat face stretched in its plane, W_peak/W = K_m.
    const SurfaceMesh mesh = test::grid_rectangle(0.2, 0.2, 2, 2);
    LoadCase lc;
    lc.fixed.assign(mesh.num_vertices(), false);
    lc.clamped.assign(mesh.num_vertices(), false);
    lc.forces = RowMatX3d::Zero(mesh.num_vertices(), 3);
    for (int v = 0; v < mesh.num_vertices(); ++v)  // the model needs a support; the densities do not see it
      if (mesh.vertices()(v, 0) < 1e-9) lc.fixed[size_t(v)] = lc.clamped[size_t(v)] = true;
      else if (mesh.vertices()(v, 0) > 0.2 - 1e-9) lc.forces(v, 0) = 1;
    MechanicsSettings mech;
    mech.stiffness = FillStiffness::Homogenised;
    mech.stiffness_curve = curve;
    const ShellModel model(mesh, test::pa12(), lc, mech);
    RowMatX3d x = mesh.vertices();
    for (int v = 0; v < x.rows(); ++v) x(v, 0) *= 1.001;
    const Eigen::VectorXd alpha = Eigen::VectorXd::Constant(mesh.num_faces(), a);
    const Eigen::VectorXd W = energy_density(model, x, alpha);
    for (const double share : {0.2, 0.5, 0.8}) {
      const ShapeCover h = make_cover(split_cover(alpha, Eigen::VectorXd::Constant(alpha.size(), share)));
      ASSERT_GE(h.covered.minCoeff(), kConcentrationRamp);
      const Eigen::VectorXd P = peak_energy_density(model, x, alpha, K, nullptr, &h);
      for (int t = 0; t < P.size(); ++t) {
        const double k = P[t] / W[t] - 1;
        EXPECT_GE(k, largest * (1 - 1e-12)) << "α " << a << " share " << share;
        EXPECT_LE(k, largest * bound * (1 + 1e-12)) << "α " << a << " share " << share;
      }
    }
  }
}

/// The cover as one vector (covered, then corner, column-major) and back.
Eigen::VectorXd flat(const ShapeCover& c) {
  Eigen::VectorXd v(c.covered.size() + c.corner.size());
  v << Eigen::Map<const Eigen::VectorXd>(c.covered.data(), c.covered.size()),
      Eigen::Map<const Eigen::VectorXd>(c.corner.data(), c.corner.size());
  return v;
}
ShapeCover unflat(const Eigen::VectorXd& v, const ShapeCover& like) {
  ShapeCover c;
  c.covered = Eigen::Map<const Eigen::MatrixXd>(v.data(), like.covered.rows(), like.covered.cols());
  if (like.corner.size() > 0)
    c.corner = Eigen::Map<const Eigen::MatrixXd>(v.data() + like.covered.size(), like.corner.rows(), like.corner.cols());
  return c;
}

// Σ c_t W_peak_t by shape: its gradients in the cover, α and x against central differences, with
// faces of one shape, of two, and of a shape inside its ramp (h < δ), with and without blend
// weights, for the worst state's K and K by biaxiality, and with shape 1's factors by corner at
// radii ε̄ between the nodes, on them and beyond the last.
TEST(PeakByShape, VectorJacobianProductsMatchCentralDifferences) {
  // none, the corner rule's, the tool's, the tool's with the thick plate's transition
  for (int corner_mode : {0, 1, 2, 3})
    for (bool by_state : {false, true})
      for (BendingModel bending : {BendingModel::ShapeOperator, BendingModel::Hinge}) {
        const bool corners = corner_mode > 0, tool = corner_mode >= 2, thick = corner_mode == 3;
        if (corners && !by_state) continue;  // tables by corner come with tables by biaxiality
        SCOPED_TRACE(bending == BendingModel::Hinge ? "hinge" : "shape operator");
        SCOPED_TRACE(by_state ? "K by biaxiality" : "the worst state's K");
        SCOPED_TRACE(thick ? "K by the tool, thick plate" : tool ? "K by the tool" : corners ? "K by corner" : "ε = 0");
        TwoShapes shapes;
        shapes.corners = corners;
        shapes.tool = tool;
        test::CapFixture fx(74, bending, FillStiffness::Homogenised);
        const ShellModel model = with_curve(fx, shapes.curve(by_state));
        // ρ/h = 0.01: φ from 0.30 at the tool's first node to 0.95 at its last.
        const ConcentrationMap K(model.mechanics().stiffness_curve, thick ? 0.01 : 0.0);
        ASSERT_EQ(K.thick_scale(), thick ? 0.01 : 0.0);
        const RowMatX3d x = fx.perturbed(75);
        const Eigen::VectorXd alpha = varied_alpha(fx);
        std::mt19937 rng(76);
        std::uniform_real_distribution<double> u(0, 1);
        std::normal_distribution<double> n;
        Eigen::VectorXd share(alpha.size()), c(alpha.size()), w(alpha.size());
        Eigen::MatrixXd epsilon(alpha.size(), 2);
        for (int t = 0; t < share.size(); ++t) {
          const int kind = t % 4;  // shape 0 alone, shape 1 alone, both, shape 1 in its ramp
          share[t] = kind == 0 ? 0.0 : kind == 1 ? 1.0 : kind == 2 ? u(rng) : 0.3 * kConcentrationRamp / std::max(1e-3, 1 - alpha[t]);
          share[t] = std::min(share[t], 1.0);
          c[t] = n(rng);
          w[t] = t % 7 == 0 ? 0.0 : u(rng);
          // Below the tool's first node (1/64), between its nodes and beyond its last (1/2).
          epsilon(t, 0) = tool ? std::exp(std::log(0.008) + std::log(80.0) * u(rng)) : 1.2 * u(rng);
          epsilon(t, 1) = tool ? std::exp(std::log(0.008) + std::log(80.0) * u(rng)) : 1.2 * u(rng);
        }
        const ShapeCover h = make_cover(split_cover(alpha, share), corners ? &epsilon : nullptr);
        const Eigen::VectorXd* no_weight = nullptr;
        for (const Eigen::VectorXd* weight : {no_weight, static_cast<const Eigen::VectorXd*>(&w)}) {
          SCOPED_TRACE(weight ? "blend weights" : "no weights");
          RowMatX3d dx;
          Eigen::VectorXd da;
          ShapeCover dh;
          peak_energy_density_vjp(model, x, alpha, K, weight, c, &dx, &da, &h, &dh);
          ASSERT_EQ(dh.covered.rows(), h.covered.rows());
          ASSERT_EQ(dh.covered.cols(), 2);
          ASSERT_EQ(dh.corner.size(), h.corner.size());
          EXPECT_GT(dh.covered.norm(), 0.0);
          if (corners) {
            EXPECT_GT(dh.corner.col(1).norm(), 0.0);
          }
          const auto of_cover = [&](const Eigen::VectorXd& v) {
            const ShapeCover hv = unflat(v, h);
            return c.dot(peak_energy_density(model, x, alpha, K, weight, &hv));
          };
          const auto ch = test::check_gradient(of_cover, flat(h), flat(dh), 1e-3);
          EXPECT_LE(ch.best, 1e-6) << ch.table();
          const auto of_alpha = [&](const Eigen::VectorXd& a) {
            return c.dot(peak_energy_density(model, x, a, K, weight, &h));
          };
          const auto ca = test::check_gradient(of_alpha, alpha, da, 0.01);
          EXPECT_LE(ca.best, 1e-6) << ca.table();
          const auto of_positions = [&](const Eigen::VectorXd& xf) {
            RowMatX3d y = x;
            model.scatter_free(xf, y);
            return c.dot(peak_energy_density(model, y, alpha, K, weight, &h));
          };
          const auto cx = test::check_gradient(of_positions, model.gather_free(x), model.gather_free(dx), 0.01);
          EXPECT_LE(cx.best, 1e-6) << cx.table();
        }
      }
}

// K by corner: at the nodes the tables themselves (ε = 0 the tables by biaxiality), linear and
// continuous between them, held beyond ε = 1; a shape without corners the same at every ε; and a
// design of one shape with corners reads its factors by shape.
TEST(PeakByShape, FactorsByCornerInterpolateTheNodes) {
  TwoShapes shapes;
  shapes.corners = true;
  const FillStiffnessCurve curve = shapes.curve(true);
  const ConcentrationMap K(curve);
  const double a = curve.alpha[2], rho = biaxiality_node(3);
  for (int part = 0; part < 2; ++part) {
    const auto& table = (part == 0 ? curve.shape_concentration[1].membrane_by_corner : curve.shape_concentration[1].bending_by_corner)[2];
    for (int node = 0; node < kCornerNodes; ++node)
      EXPECT_NEAR(K.shape_factor(1, part == 1, a, &rho, corner_node(node), nullptr, nullptr),
                  table[size_t(node * kBiaxialityNodes + 3)], 1e-12)
          << "node " << node;
    EXPECT_EQ(K.shape_factor(1, part == 1, a, &rho, 1.7, nullptr, nullptr), K.shape_factor(1, part == 1, a, &rho, 1.0, nullptr, nullptr));
    for (const double e : {0.0, 0.3, 0.9, 1.4})
      EXPECT_NEAR(K.shape_factor(0, part == 1, a, &rho, e, nullptr, nullptr), K.shape_factor(0, part == 1, a, &rho, 0, nullptr, nullptr), 1e-12);
    // Continuous across a node; the slope in ε against central differences between nodes.
    EXPECT_NEAR(K.shape_factor(1, part == 1, a, &rho, corner_node(3) - 1e-12, nullptr, nullptr),
                K.shape_factor(1, part == 1, a, &rho, corner_node(3) + 1e-12, nullptr, nullptr), 1e-9);
    for (const double e : {0.2, 0.47, 0.93}) {
      double slope = 0;
      K.shape_factor(1, part == 1, a, &rho, e, nullptr, nullptr, &slope);
      const double d = 1e-6;
      const double fd = (K.shape_factor(1, part == 1, a, &rho, e + d, nullptr, nullptr) -
                         K.shape_factor(1, part == 1, a, &rho, e - d, nullptr, nullptr)) / (2 * d);
      EXPECT_NEAR(slope, fd, 1e-6 * std::max(1.0, std::abs(fd))) << "ε " << e;
    }
  }
  // One shape with corners: by shape; one without (the circle alone): not.
  FillStiffnessCurve one = curve;
  one.shape_concentration[0] = {};
  EXPECT_TRUE(ConcentrationMap(one).by_shape());
  one = curve;
  one.shape_concentration[1] = {};
  EXPECT_FALSE(ConcentrationMap(one).by_shape());
}

// K by the tool: at the nodes τ_c the tables, a power law between two (the geometric mean at their
// geometric mean), held below the first node and beyond the last; the slope in τ against central
// differences; a shape the tool does not change the same at every τ.
TEST(PeakByShape, FactorsByTheToolFollowAPowerLawBetweenTheNodes) {
  TwoShapes shapes;
  shapes.corners = shapes.tool = true;
  const FillStiffnessCurve curve = shapes.curve(true);
  ASSERT_TRUE(curve.tool_cut);
  const ConcentrationMap K(curve);
  EXPECT_TRUE(K.by_shape());
  const double a = curve.alpha[2], rho = biaxiality_node(3);
  for (int part = 0; part < 2; ++part) {
    const bool bending = part == 1;
    const auto& row = (part == 0 ? curve.shape_concentration[1].membrane_by_corner
                                 : curve.shape_concentration[1].bending_by_corner)[2];
    ASSERT_EQ(row.size(), size_t(kToolNodes * kBiaxialityNodes));
    const auto at = [&](int node) { return row[size_t(node * kBiaxialityNodes + 3)]; };
    for (int node = 0; node < kToolNodes; ++node)
      EXPECT_NEAR(K.shape_factor(1, bending, a, &rho, tool_node(node), nullptr, nullptr), at(node), 1e-12) << node;
    for (int node = 0; node + 1 < kToolNodes; ++node)
      EXPECT_NEAR(K.shape_factor(1, bending, a, &rho, std::sqrt(tool_node(node) * tool_node(node + 1)), nullptr, nullptr),
                  std::sqrt(at(node) * at(node + 1)), 1e-12) << node;
    // Below the first node the first interval's power law goes on (its exponent here 0.6–0.8);
    // beyond the last the last node is held.
    const double p = std::log(at(0) / at(1)) / std::log(2.0);
    ASSERT_GT(p, 0.3);
    ASSERT_LT(p, 1.0);
    for (const double below : {0.25, 0.002 / tool_node(0)})
      EXPECT_NEAR(K.shape_factor(1, bending, a, &rho, below * tool_node(0), nullptr, nullptr),
                  at(0) * std::pow(below, -p), 1e-12 * at(0) * std::pow(below, -p)) << below;
    EXPECT_EQ(K.shape_factor(1, bending, a, &rho, 0.9, nullptr, nullptr), at(kToolNodes - 1));
    for (const double e : {0.0, 0.001, 0.01, 0.1, 0.7})
      EXPECT_NEAR(K.shape_factor(0, bending, a, &rho, e, nullptr, nullptr),
                  K.shape_factor(0, bending, a, &rho, 0.05, nullptr, nullptr), 1e-12);
    for (const double e : {0.002, 0.01, 0.02, 0.05, 0.11, 0.4}) {
      double slope = 0;
      K.shape_factor(1, bending, a, &rho, e, nullptr, nullptr, &slope);
      const double d = 1e-7;
      const double fd = (K.shape_factor(1, bending, a, &rho, e + d, nullptr, nullptr) -
                         K.shape_factor(1, bending, a, &rho, e - d, nullptr, nullptr)) / (2 * d);
      EXPECT_LT(slope, 0) << "τ " << e;
      EXPECT_NEAR(slope, fd, 1e-6 * std::max(1.0, std::abs(fd))) << "τ " << e;
    }
  }
  // Tables of the corner rule's size on a tool's curve are refused.
  FillStiffnessCurve wrong = curve;
  wrong.tool_cut = false;
  EXPECT_THROW(ConcentrationMap{wrong}, InputError);
}

// Below the tool's first node the power law's exponent is held to [0, 1]: a first interval that
// falls faster than a crack's 1/τ goes on as 1/τ, and one that rises is held at the first node;
// the slopes in α, ρ and τ match central differences either way.
TEST(PeakByShape, BelowTheToolsFirstNodeItsExponentIsHeldToACracks) {
  TwoShapes shapes;
  shapes.corners = shapes.tool = true;
  const FillStiffnessCurve base = shapes.curve(true);
  const double a = 0.5 * (base.alpha[2] + base.alpha[3]), rho = biaxiality_node(3) + 0.1, tau0 = tool_node(0);
  for (const double scale : {3.0, 1.0 / 1.5}) {
    SCOPED_TRACE(fmt::format("node 0 = {} node 1", scale));
    // Node 0 is the shape's tables by biaxiality (and the first block of its tables by corner),
    // node 1 the second block: node 0 set to 3× node 1, or node 1 to 1.5× node 0.
    FillStiffnessCurve curve = base;
    FillStiffnessCurve::ShapeConcentration& k = curve.shape_concentration[1];
    for (int part = 0; part < 2; ++part) {
      auto& states = part == 0 ? k.membrane_by_biaxiality : k.bending_by_biaxiality;
      auto& corner = part == 0 ? k.membrane_by_corner : k.bending_by_corner;
      auto& worst = part == 0 ? k.membrane : k.bending;
      for (size_t i = 0; i < states.size(); ++i) {
        for (int j = 0; j < kBiaxialityNodes; ++j) {
          double& k0 = corner[i][size_t(j)];
          double& k1 = corner[i][size_t(kBiaxialityNodes + j)];
          if (scale > 1)
            k0 = scale * k1;
          else
            k1 = k0 / scale;
          states[i][size_t(j)] = k0;
        }
        worst[i] = *std::max_element(states[i].begin(), states[i].end());
      }
    }
    const ConcentrationMap K(curve);
    for (int part = 0; part < 2; ++part) {
      const bool bending = part == 1;
      const auto f = [&](double alpha, double r, double tau, double* da = nullptr, double* dr = nullptr,
                         double* de = nullptr) { return K.shape_factor(1, bending, alpha, &r, tau, da, dr, de); };
      const double k0 = f(a, rho, tau0);
      for (const double tau : {tau0 / 4, tau0 / 16}) {
        // 1/τ where the first interval falls faster; the first node's K where it rises.
        EXPECT_NEAR(f(a, rho, tau), scale > 1 ? k0 * tau0 / tau : k0, 1e-12 * k0 * tau0 / tau) << tau;
        double da = 0, dr = 0, de = 0;
        f(a, rho, tau, &da, &dr, &de);
        const double h = 1e-6, ht = 1e-7 * tau;
        const double fa = (f(a + h, rho, tau) - f(a - h, rho, tau)) / (2 * h);
        const double fr = (f(a, rho + h, tau) - f(a, rho - h, tau)) / (2 * h);
        const double ft = (f(a, rho, tau + ht) - f(a, rho, tau - ht)) / (2 * ht);
        EXPECT_NEAR(da, fa, 1e-5 * std::max(1.0, std::abs(fa))) << tau;
        EXPECT_NEAR(dr, fr, 1e-5 * std::max(1.0, std::abs(fr))) << tau;
        EXPECT_NEAR(de, ft, 1e-5 * std::max(1.0, std::abs(ft))) << tau;
        if (scale < 1) {
          EXPECT_EQ(de, 0.0);
        }
      }
    }
  }
}

// The peak objective carries ∂S/∂(cover) (ObjectiveTerms::d_cover) when it is given a cover and
// the factors are by shape, and nothing otherwise.
TEST(PeakByShape, ThePeakObjectiveCarriesItsCoverGradient) {
  TwoShapes shapes;
  shapes.corners = true;
  test::CapFixture fx(77, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  const ShellModel model = with_curve(fx, shapes.curve(true));
  const ConcentrationMap K(model.mechanics().stiffness_curve);
  const RowMatX3d x = fx.perturbed(78);
  const Eigen::VectorXd alpha = varied_alpha(fx);
  Eigen::VectorXd share(alpha.size());
  Eigen::MatrixXd epsilon(alpha.size(), 2);
  for (int t = 0; t < share.size(); ++t) share[t] = (t % 5) / 4.0, epsilon(t, 0) = 0.1, epsilon(t, 1) = 0.05 + 0.1 * (t % 7);
  const ShapeCover h = make_cover(split_cover(alpha, share), &epsilon);
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  const double beta = 0.5 * W.maxCoeff(), w_ref = W.maxCoeff();
  const PeakMeasure peak{&K, nullptr, &h};
  const ObjectiveTerms t = energy_density_objective(model, x, alpha, beta, w_ref, nullptr, &peak);
  ASSERT_EQ(t.d_cover.covered.rows(), alpha.size());
  ASSERT_EQ(t.d_cover.corner.rows(), alpha.size());
  const auto of_cover = [&](const Eigen::VectorXd& v) {
    const ShapeCover hv = unflat(v, h);
    const PeakMeasure p{&K, nullptr, &hv};
    return energy_density_objective(model, x, alpha, beta, w_ref, nullptr, &p).value;
  };
  const Eigen::VectorXd g = flat(t.d_cover);
  ASSERT_GT(g.norm(), 0.0);
  const auto ch = test::check_gradient(of_cover, flat(h), g, 1e-3);
  EXPECT_LE(ch.best, 1e-6) << ch.table();
  const PeakMeasure without{&K, nullptr, nullptr};
  EXPECT_TRUE(energy_density_objective(model, x, alpha, beta, w_ref, nullptr, &without).d_cover.empty());
  // summarize_equilibrium's W_peak reads the same rule.
  const EquilibriumSummary s = summarize_equilibrium(model, x, alpha, nullptr, &h);
  EXPECT_EQ((s.peak_energy_density - peak_energy_density(model, x, alpha, K, nullptr, &h)).norm(), 0.0);
}

TEST(PeakByShape, MalformedFactorsByShapeAreRejected) {
  const TwoShapes shapes;
  FillStiffnessCurve c = shapes.curve(true);
  c.shape_concentration[1].membrane.pop_back();
  EXPECT_THROW(ConcentrationMap{c}, InputError);
  c = shapes.curve(true);
  c.shape_concentration[0].bending[2] = 0.5;
  EXPECT_THROW(ConcentrationMap{c}, InputError);
  c = shapes.curve(true);
  c.shape_concentration[0].membrane_by_biaxiality.clear();
  c.shape_concentration[0].bending_by_biaxiality.clear();
  EXPECT_THROW(ConcentrationMap{c}, InputError);
  // One shape with its own factors (and no corners) is not "by shape": the worst is that shape's.
  c = shapes.curve(true);
  c.shape_concentration[1] = {};
  EXPECT_FALSE(ConcentrationMap(c).by_shape());
  MechanicsSettings one_shape;
  one_shape.stiffness_curve = c;
  EXPECT_FALSE(concentration_by_shape(one_shape, test::pa12()));
  // Tables by corner of the wrong size.
  TwoShapes cornered;
  cornered.corners = true;
  c = cornered.curve(true);
  c.shape_concentration[1].membrane_by_corner[0].pop_back();
  EXPECT_THROW(ConcentrationMap{c}, InputError);
}

// The thick-plate transition (peak_energy_density.h "Thick plates") is Roark's fit
// of Reissner's circular hole in bending (Young & Budynas, Table 17.1, ν = 0.3) between Goodier's
// 1.79 and Kirsch's 3: 0.984 where the hole is far thinner than the plate (the fit's 2.981), 0
// where it is far wider; decreasing between.
TEST(ThickPlate, TheTransitionIsRoarksFitOfReissnersHoleNormalised) {
  const auto roark = [](double x) { return 1.79 + 0.25 / (0.39 + x) + 0.81 / (1 + x * x) - 0.26 / (1 + x * x * x); };
  EXPECT_NEAR(thick_round_transition(0), (roark(0) - 1.79) / (3 - 1.79), 1e-15);
  EXPECT_NEAR(thick_round_transition(0), 0.9843, 1e-4);
  EXPECT_EQ(thick_round_transition(INFINITY), 0.0);
  EXPECT_LT(thick_round_transition(1e6), 1e-6);
  double last = 2;
  for (double x = 0; x <= 20; x += 0.01) {
    const double phi = thick_round_transition(x);
    EXPECT_NEAR(1.79 + (3 - 1.79) * phi, roark(x), 1e-12) << x;
    EXPECT_LT(phi, last) << x;
    last = phi;
  }
  // Two points of the fit: x = 1/12 and 1/3.
  EXPECT_NEAR(thick_round_transition(2 * 0.0005 / 0.012), 0.8866, 5e-4);
  EXPECT_NEAR(thick_round_transition(2 * 0.0005 / 0.003), 0.6809, 5e-4);
  EXPECT_THROW(thick_round_transition(-0.1), InternalError);
  EXPECT_THROW(thick_round_transition(NAN), InternalError);
}

namespace {

/// A one-shape curve whose cells are a dilute circular hole's closed forms at every node
/// (StressConcentration.DiluteCircleMatches…), by the tool's nodes (`tool`) or the corner rule's:
/// membrane, Kirsch, (3 − ρ)²/(1 + ρ² − 2νρ); bending, Goodier's Kirchhoff plate,
/// ((1 + ρ) + c(1 − ρ))²/(1 + ρ² − 2νρ), c = 2(1 + ν)/(3 + ν) (the rim's M_tt; the twist's peak
/// towards pure shear left out, and the factor held at 1 or more: the tests read ρ = 0 only).
FillStiffnessCurve dilute_circle(double nu, bool tool) {
  FillStiffnessCurve c = test::test_stiffness_curve();
  const size_t n = c.alpha.size();
  const double cb = 2 * (1 + nu) / (3 + nu);
  std::vector<double> km, kb;
  for (int j = 0; j < kBiaxialityNodes; ++j) {
    const double r = biaxiality_node(j), mean = 1 + r * r - 2 * nu * r;
    km.push_back((3 - r) * (3 - r) / mean);
    kb.push_back(std::max(1.0, ((1 + r) + cb * (1 - r)) * ((1 + r) + cb * (1 - r)) / mean));
  }
  c.membrane_concentration.assign(n, *std::max_element(km.begin(), km.end()));
  c.bending_concentration.assign(n, *std::max_element(kb.begin(), kb.end()));
  c.membrane_concentration_by_biaxiality.assign(n, km);
  c.bending_concentration_by_biaxiality.assign(n, kb);
  FillStiffnessCurve::ShapeConcentration shape{c.membrane_concentration, c.bending_concentration,
                                               c.membrane_concentration_by_biaxiality,
                                               c.bending_concentration_by_biaxiality, {}, {}};
  std::vector<double> membrane_nodes, bending_nodes;
  for (int node = 0; node < (tool ? kToolNodes : kCornerNodes); ++node) {
    membrane_nodes.insert(membrane_nodes.end(), km.begin(), km.end());
    bending_nodes.insert(bending_nodes.end(), kb.begin(), kb.end());
  }
  shape.membrane_by_corner.assign(n, membrane_nodes);
  shape.bending_by_corner.assign(n, bending_nodes);
  c.shape_concentration = {shape};
  c.tool_cut = tool;
  return c;
}

double roark(double x) { return 1.79 + 0.25 / (0.39 + x) + 0.81 / (1 + x * x) - 0.26 / (1 + x * x * x); }

}  // namespace

// A circular hole in uniaxial bending reads Roark's factor at x = 2s/h through the map, s = ρ/e_c
// the bounding radius of the stencils at each node (the tool's τ_c = r/s, the corner rule's
// ε_c = g/s; the corner rule's ε = 0 is a stencil without bound, Kirchhoff's); the worst shape's
// factors are node 0's; the membrane's stay Kirsch's; ρ/h = 0 is Kirchhoff's map to the bit. Its
// factors by corner, equal at every node before, now vary with it: the map reads them by shape.
TEST(ThickPlate, ACircularHoleInUniaxialBendingReadsRoarksFactorAtItsSize) {
  const double nu = 0.3, goodier = (5 + 3 * nu) / (3 + nu), uniaxial = 0;
  ASSERT_EQ(biaxiality_node(kBiaxialityNodes / 2), uniaxial);
  for (const bool tool : {true, false}) {
    SCOPED_TRACE(tool ? "by the tool" : "by the corner rule");
    const FillStiffnessCurve curve = dilute_circle(nu, tool);
    const double alpha = curve.alpha[2];
    const ConcentrationMap kirchhoff(curve);
    EXPECT_FALSE(kirchhoff.by_shape());
    EXPECT_NEAR(std::sqrt(kirchhoff.bending(alpha, uniaxial, nullptr, nullptr)), goodier, 1e-12);
    for (const double scale : {0.002, 0.02, 0.1}) {  // ρ/h
      SCOPED_TRACE(fmt::format("ρ/h = {}", scale));
      const ConcentrationMap K(curve, scale);
      ASSERT_EQ(K.thick_scale(), scale);
      EXPECT_TRUE(K.by_shape());
      for (int node = 0; node < (tool ? kToolNodes : kCornerNodes); ++node) {
        const double e = tool ? tool_node(node) : corner_node(node);
        // Goodier's 1.7879 at ν = 0.3 against the fit's 1.79: the fit's own rounding, 0.12% at most.
        const double expected = e > 0 ? roark(2 * scale / e) : goodier;
        EXPECT_NEAR(std::sqrt(K.shape_factor(0, true, alpha, &uniaxial, e, nullptr, nullptr)), expected, 2.5e-3)
            << "node " << node << ", 2s/h = " << 2 * scale / e;
        EXPECT_EQ(K.shape_factor(0, false, alpha, &uniaxial, e, nullptr, nullptr),
                  kirchhoff.shape_factor(0, false, alpha, &uniaxial, e, nullptr, nullptr));
      }
      const double first = tool ? roark(2 * scale / tool_node(0)) : goodier;
      EXPECT_NEAR(std::sqrt(K.bending(alpha, uniaxial, nullptr, nullptr)), first, 2.5e-3);
      EXPECT_NEAR(K.membrane(alpha, uniaxial, nullptr, nullptr), 9.0, 1e-12);
    }
    const ConcentrationMap none(curve, 0.0);
    EXPECT_EQ(none.thick_scale(), 0.0);
    EXPECT_FALSE(none.by_shape());
    for (int j = 0; j < kBiaxialityNodes; ++j) {
      const double r = biaxiality_node(j);
      EXPECT_EQ(none.bending(alpha, r, nullptr, nullptr), kirchhoff.bending(alpha, r, nullptr, nullptr));
    }
    EXPECT_THROW(ConcentrationMap(curve, -0.1), InputError);
    EXPECT_THROW(ConcentrationMap(curve, INFINITY), InputError);
  }
}

// Every node's bending factors move to their blend with the same node's membrane factors at that
// node's φ; the membrane's stay; the power law between the tool's nodes goes through the blended
// ones; a curve without factors by corner is Kirchhoff's whatever the scale.
TEST(ThickPlate, EachNodesBendingFactorsAreBlendedAtItsStencilsSize) {
  TwoShapes shapes;
  shapes.corners = shapes.tool = true;
  const FillStiffnessCurve curve = shapes.curve(true);
  const double scale = 0.02;
  const ConcentrationMap kirchhoff(curve), K(curve, scale);
  ASSERT_EQ(K.thick_scale(), scale);
  const auto blend = [&](double kb, double km, double tau) {
    const double phi = thick_round_transition(2 * scale / tau);
    const double root = (1 - phi) * std::sqrt(kb) + phi * std::sqrt(km);
    return root * root;
  };
  for (const double alpha : {curve.alpha[1], curve.alpha[3], 0.82})
    for (int j = 0; j < kBiaxialityNodes; ++j) {
      const double r = biaxiality_node(j);
      for (int shape = 0; shape < 2; ++shape)
        for (int node = 0; node < kToolNodes; ++node) {
          const double tau = tool_node(node);
          const double kb = kirchhoff.shape_factor(shape, true, alpha, &r, tau, nullptr, nullptr);
          const double km = kirchhoff.shape_factor(shape, false, alpha, &r, tau, nullptr, nullptr);
          const double now = K.shape_factor(shape, true, alpha, &r, tau, nullptr, nullptr);
          // Blended on the samples: at a sample α exactly the blend of the factors, between samples
          // the cubic through the blended samples.
          if (alpha != 0.82) {
            EXPECT_NEAR(now, blend(kb, km, tau), 1e-12 * now) << shape << ", node " << node;
          }
          EXPECT_EQ(K.shape_factor(shape, false, alpha, &r, tau, nullptr, nullptr), km);
        }
      // Between two nodes the power law through the blended factors.
      const double mid = std::sqrt(tool_node(1) * tool_node(2));
      const double at_mid = K.shape_factor(1, true, alpha, &r, mid, nullptr, nullptr);
      EXPECT_NEAR(at_mid,
                  std::sqrt(K.shape_factor(1, true, alpha, &r, tool_node(1), nullptr, nullptr) *
                            K.shape_factor(1, true, alpha, &r, tool_node(2), nullptr, nullptr)),
                  1e-12 * at_mid);
      // The worst shape's factors: the largest of the shapes' node 0, blended (lower than
      // Kirchhoff's where a cell's membrane factor is below its bending one, as here at α 0.9 and 1).
      if (alpha != 0.82) {
        EXPECT_NEAR(K.bending(alpha, r, nullptr, nullptr),
                    std::max(K.shape_factor(0, true, alpha, &r, tool_node(0), nullptr, nullptr),
                             K.shape_factor(1, true, alpha, &r, tool_node(0), nullptr, nullptr)),
                    1e-12 * K.bending(alpha, r, nullptr, nullptr));
      }
      EXPECT_EQ(K.membrane(alpha, r, nullptr, nullptr), kirchhoff.membrane(alpha, r, nullptr, nullptr));
    }
  // No factors by corner: nothing to blend.
  const FillStiffnessCurve plain = TwoShapes{}.curve(true);
  const ConcentrationMap unblended(plain, scale);
  EXPECT_EQ(unblended.thick_scale(), 0.0);
  const double r0 = 0;
  EXPECT_EQ(unblended.shape_factor(1, true, 0.6, &r0, 0.05, nullptr, nullptr),
            ConcentrationMap(plain).shape_factor(1, true, 0.6, &r0, 0.05, nullptr, nullptr));
}

// A model's map takes its corner radius against the shell's thickness; a summary reports the peak
// with Kirchhoff's factors beside the part's, and the cover decision follows the blended map.
TEST(ThickPlate, AModelsMapAndSummaryTakeTheStencilsAgainstTheThickness) {
  TwoShapes shapes;
  shapes.corners = shapes.tool = true;
  test::CapFixture fx(77, BendingModel::ShapeOperator, FillStiffness::Homogenised);
  MechanicsSettings mech = fx.model->mechanics();
  mech.stiffness_curve = shapes.curve(true);
  const Material material = test::pa12();
  mech.corner_radius = 0;
  EXPECT_EQ(ConcentrationMap::for_mechanics(mech, material).thick_scale(), 0.0) << "no corner radius";
  mech.tool_radius = mech.corner_radius = 0.0005;
  EXPECT_EQ(ConcentrationMap::for_mechanics(mech, material).thick_scale(), 0.0005 / material.thickness);
  MechanicsSettings plain = mech;
  plain.stiffness_curve = TwoShapes{}.curve(true);  // no factors by corner
  EXPECT_EQ(ConcentrationMap::for_mechanics(plain, material).thick_scale(), 0.0);
  MechanicsSettings circle = mech;
  circle.stiffness_curve = dilute_circle(0.4, true);
  EXPECT_TRUE(concentration_by_shape(circle, material));
  circle.corner_radius = 0;
  EXPECT_FALSE(concentration_by_shape(circle, material));

  const ShellModel model(fx.mesh, material, fx.lc, mech);
  const RowMatX3d x = fx.perturbed(78);
  const Eigen::VectorXd alpha = varied_alpha(fx);
  const EquilibriumSummary s = summarize_equilibrium(model, x, alpha);
  EXPECT_EQ(s.W_peak_thick_scale, 0.0005 / material.thickness);
  ASSERT_EQ(s.peak_energy_density_kirchhoff.size(), model.num_faces());
  const Eigen::VectorXd kirchhoff = peak_energy_density(model, x, alpha, ConcentrationMap(mech.stiffness_curve));
  EXPECT_EQ((s.peak_energy_density_kirchhoff - kirchhoff).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NE(s.W_peak_max, s.W_peak_kirchhoff_max);
  EXPECT_EQ(s.W_peak_kirchhoff_max, kirchhoff.maxCoeff());

  const ShellModel unblended(fx.mesh, material, fx.lc, plain);
  const EquilibriumSummary p = summarize_equilibrium(unblended, x, alpha);
  EXPECT_EQ(p.W_peak_thick_scale, 0.0);
  EXPECT_TRUE(std::isnan(p.W_peak_kirchhoff_max));
  EXPECT_EQ(p.peak_energy_density_kirchhoff.size(), 0);
}
}  // namespace
}  // namespace cutwork::solvers

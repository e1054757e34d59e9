// Stress concentration of the cell problems (cell_homogenisation.h, ConcentrationState): K = peak /
// mean energy density over the cell's material, against Kirsch's circular hole at dilute fill, and
// carried by the fill stiffness calibration (fill_stiffness_calibration.h).
#include <cmath>
#include <iostream>
#include <numbers>

#include <gtest/gtest.h>

#include "solvers/homogenise/cell_homogenisation.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

StencilShape circle() { return make_builtin_stencil("circle", {}, "circle"); }

double state_factor(const std::vector<ConcentrationState>& states, const std::string& name, double angle) {
  for (const ConcentrationState& s : states)
    if (s.state == name && std::abs(s.angle - angle) < 1e-9) return s.factor;
  ADD_FAILURE() << "no state " << name << " at " << angle;
  return NAN;
}

/// Mean of K over the states called `name` (every angle).
double mean_factor(const std::vector<ConcentrationState>& states, const std::string& name) {
  double sum = 0;
  int n = 0;
  for (const ConcentrationState& s : states)
    if (s.state == name) {
      sum += s.factor;
      ++n;
    }
  return sum / n;
}

TEST(StressConcentration, SolidCellHasNone) {
  const CellStiffness c = homogenise_cell(circle(), test::pa12(), 1.0);
  ASSERT_EQ(c.membrane_states.size(), 17u);
  ASSERT_EQ(c.bending_states.size(), 17u);
  for (const auto* states : {&c.membrane_states, &c.bending_states})
    for (const ConcentrationState& s : *states) EXPECT_NEAR(s.factor, 1.0, 1e-8) << s.state << " " << s.angle;
  EXPECT_NEAR(c.membrane_concentration, 1.0, 1e-8);  // a max over ~1000 faces' round-off
  EXPECT_NEAR(c.bending_concentration, 1.0, 1e-8);
}

TEST(StressConcentration, DiluteCircleMatchesKirsch) {
  // A circle at α = 0.99 (hole radius 0.053 lattice spacings; neighbours 19 radii away) is Kirsch's
  // hole in an infinite sheet to O(1 − α): rim stress 3σ∞ (uniaxial), 2σ∞ (equibiaxial), 4τ (pure
  // shear), so K = 9, 2/(1 − ν), 8/(1 + ν) in energy. Resolution 96 puts 5 target edges across the
  // hole's radius (at the default 24 the hole is one edge across and K is under half of Kirsch's).
  // The rim value is recovered along the rim's edges (free_edge_strain.h). Measured: K falls short
  // of Kirsch by the rim's discretisation and the half-edge smoothing window; the cell's mean over its
  // material is within O(1 − α) of the far field. Measured (angle means): uniaxial 8.57 (−4.8%),
  // equibiaxial 3.45 (+3.6%), shear 5.42 (−5.1%); single angles spread 8.0–9.0 (remeshed rim).
  const Material m = test::pa12();
  const double nu = m.poisson_ratio;
  CellOptions o;
  o.resolution = 96;
  const CellStiffness c = homogenise_cell(circle(), m, 0.99, o);
  const double uniaxial = mean_factor(c.membrane_states, "uniaxial");
  const double equibiaxial = state_factor(c.membrane_states, "equibiaxial", 0);
  const double shear = mean_factor(c.membrane_states, "shear");
  std::cout << "alpha 0.99, resolution 96 (" << c.faces << " faces): K uniaxial " << uniaxial << " (0 deg "
            << state_factor(c.membrane_states, "uniaxial", 0) << ", max over states " << c.membrane_concentration
            << "), equibiaxial " << equibiaxial << ", shear " << shear << "; Kirsch 9, " << 2 / (1 - nu) << ", "
            << 8 / (1 + nu) << "; bending K " << c.bending_concentration << "\n";
  EXPECT_NEAR(uniaxial, 9.0, 0.06 * 9.0);
  EXPECT_NEAR(equibiaxial, 2 / (1 - nu), 0.06 * 2 / (1 - nu));
  EXPECT_NEAR(shear, 8 / (1 + nu), 0.06 * 8 / (1 + nu));
  for (const ConcentrationState& s : c.membrane_states)
    EXPECT_NEAR(s.factor, s.state == "uniaxial" ? uniaxial : s.state == "shear" ? shear : equibiaxial,
                0.08 * c.membrane_concentration)
        << s.state << " at " << s.angle << ": a dilute circle is isotropic";
}

TEST(StressConcentration, CalibrationCarriesTheFactors) {
  StencilLibrary shapes;
  shapes.add(circle());
  const FillStiffnessCurve curve = calibrate_fill_stiffness(shapes, test::pa12());
  const size_t n = curve.alpha.size();
  ASSERT_EQ(curve.membrane_concentration.size(), n);
  ASSERT_EQ(curve.bending_concentration.size(), n);
  for (size_t k = 0; k < n; ++k) {
    std::cout << "alpha " << curve.alpha[k] << ": K_m " << curve.membrane_concentration[k] << ", K_b "
              << curve.bending_concentration[k] << "\n";
    EXPECT_GT(curve.membrane_concentration[k], 1.5) << "a hole concentrates stress at alpha " << curve.alpha[k];
    EXPECT_GT(curve.bending_concentration[k], 1.2) << "a hole concentrates stress at alpha " << curve.alpha[k];
  }
  EXPECT_EQ(curve.membrane_concentration[n - 1], curve.membrane_concentration[n - 2]) << "the dilute side is held";
  EXPECT_EQ(curve.bending_concentration[n - 1], curve.bending_concentration[n - 2]);
}

}  // namespace
}  // namespace cutwork::solvers

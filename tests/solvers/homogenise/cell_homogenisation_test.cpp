// Cell homogenisation (cell_homogenisation.h): a solid patch returns the closed-form plate
// stiffnesses; dilute circular holes soften a sheet by Young's modulus 1 − 3φ (plane elasticity);
// a hexagonal lattice of circles is isotropic in the plane; perforated stiffness lies below the
// Voigt bound α and grows with α; the factors converge as the cell's mesh is refined.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "solvers/homogenise/cell_homogenisation.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/shell/fill_stiffness_map.h"
#include "solvers/shell/shell_material.h"
#include "tests/solvers/support/shell_fixtures.h"

namespace cutwork::solvers {
namespace {

StencilShape circle() { return make_builtin_stencil("circle", {}, "circle"); }

double relative(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return (a - b).norm() / b.norm(); }

TEST(CellHomogenisation, SolidPatchReturnsTheClosedForms) {
  const Material m = test::pa12();
  const CellStiffness c = homogenise_cell(circle(), m, 1.0);
  EXPECT_NEAR(c.window_fill_ratio, 1.0, 1e-12);
  EXPECT_LE(relative(c.membrane, solid_membrane_stiffness(m)), 1e-9) << c.membrane;
  EXPECT_LE(relative(c.bending, solid_bending_stiffness(m)), 1e-9) << c.bending;
  EXPECT_NEAR(c.membrane_factor, 1.0, 1e-9);
  EXPECT_NEAR(c.bending_factor, 1.0, 1e-9);
}

TEST(CellHomogenisation, DiluteCircularHolesSoftenYoungsModulusAsPlaneElasticitySays) {
  // Plane elasticity, a sparse array of circular holes (area fraction φ): E*/E = 1 − 3φ + O(φ²),
  // whatever ν; the Mori–Tanaka estimate 1/(1 + 3φ), accurate for hexagonal arrays at low φ, is the
  // other side of the O(φ²) term. At φ = 0.03 (resolution 48; converged: 0.9153) E*/E must fall
  // between them, and be the same along x and y (hexagonal symmetry).
  for (double nu : {0.0, 0.4}) {
    Material m = test::pa12();
    m.poisson_ratio = nu;
    CellOptions o;
    o.resolution = 48;
    o.rim_edges = 0;  // the stiffness at this resolution (the rim's own refinement is for the peak)
    const CellStiffness c = homogenise_cell(circle(), m, 0.97, o);
    const double phi = 1 - c.window_fill_ratio, E = m.youngs_modulus * m.thickness;
    const double E_x = 1.0 / c.membrane.inverse()(0, 0) / E, E_y = 1.0 / c.membrane.inverse()(1, 1) / E;
    std::cout << "nu " << nu << ": phi " << phi << ", E*/E " << E_x << " (x) " << E_y << " (y), bounds "
              << 1 - 3 * phi << ", " << 1 / (1 + 3 * phi) << "; g_m " << c.membrane_factor << ", g_b "
              << c.bending_factor << ", " << c.faces << " faces\n";
    EXPECT_GT(E_x, 1 - 3 * phi) << "nu " << nu;
    EXPECT_LT(E_x, 1 / (1 + 3 * phi)) << "nu " << nu;
    EXPECT_NEAR(E_x, E_y, 5e-4);
  }
}

TEST(CellHomogenisation, PerforatedStiffnessIsIsotropicBelowVoigtAndGrowsWithFill) {
  const Material m = test::pa12();
  double last_m = 0, last_b = 0;
  for (double alpha : {0.4, 0.6, 0.8}) {
    const CellStiffness c = homogenise_cell(circle(), m, alpha);
    std::cout << "alpha " << alpha << " (window " << c.window_fill_ratio << "): g_m " << c.membrane_factor
              << ", g_b " << c.bending_factor << "\n  C* = " << c.membrane.row(0) << " | " << c.membrane.row(1)
              << " | " << c.membrane.row(2) << "\n";
    EXPECT_NEAR(c.window_fill_ratio, alpha, 0.01);
    // Hexagonal symmetry: C*_11 = C*_22 and C*_33 = (C*_11 − C*_12)/2.
    const Eigen::Matrix3d& C = c.membrane;
    EXPECT_NEAR(C(0, 0), C(1, 1), 0.02 * C(0, 0));
    EXPECT_NEAR(C(2, 2), 0.5 * (C(0, 0) - C(0, 1)), 0.03 * C(2, 2));
    EXPECT_LE(std::abs(C(0, 2)) + std::abs(C(1, 2)), 0.01 * C(0, 0));
    EXPECT_LT(c.membrane_factor, alpha);
    EXPECT_LT(c.bending_factor, alpha);
    EXPECT_GT(c.membrane_factor, last_m);
    EXPECT_GT(c.bending_factor, last_b);
    last_m = c.membrane_factor;
    last_b = c.bending_factor;
  }
}

// The isotropic split (fill_stiffness_map.h): the projection returns the solid's bulk and shear
// moduli in closed form; on the hexagonal lattice, where C* and D* are isotropic, the scalar factor
// is their mean over the three modes, (g_K + 2 g_G)/3; and a perforation softens the bending bulk
// modulus far more than the bending shear modulus (the perforated plate's ν* is well below ν:
// measured 0.09 at α = 0.5 against the material's 0.4), so one scalar cannot carry both.
TEST(CellHomogenisation, IsotropicSplitOfTheHexagonalCell) {
  const Material m = test::pa12();
  const double nu = m.poisson_ratio;
  const ShellStiffness k = shell_stiffness(m);
  const Eigen::Vector2d membrane = isotropic_moduli(solid_membrane_stiffness(m));
  const Eigen::Vector2d bending = isotropic_moduli(solid_bending_stiffness(m));
  EXPECT_NEAR(membrane[0], k.mu + k.lambda, 1e-9 * k.mu);
  EXPECT_NEAR(membrane[1], k.mu, 1e-9 * k.mu);
  EXPECT_NEAR(bending[0], k.bending * (1 + nu) / 2, 1e-12 * k.bending);
  EXPECT_NEAR(bending[1], k.bending * (1 - nu) / 2, 1e-12 * k.bending);
  for (double alpha : {0.5, 0.8}) {
    const CellStiffness c = homogenise_cell(circle(), m, alpha);
    const double nu_b = c.bending(0, 1) / c.bending(0, 0);
    std::cout << "alpha " << alpha << ": membrane bulk " << c.membrane_bulk_factor << ", shear "
              << c.membrane_shear_factor << "; bending bulk " << c.bending_bulk_factor << ", shear "
              << c.bending_shear_factor << "; bending nu* " << nu_b << "\n";
    EXPECT_NEAR((c.membrane_bulk_factor + 2 * c.membrane_shear_factor) / 3, c.membrane_factor, 2e-3 * c.membrane_factor);
    EXPECT_NEAR((c.bending_bulk_factor + 2 * c.bending_shear_factor) / 3, c.bending_factor, 2e-3 * c.bending_factor);
    for (double f : {c.membrane_bulk_factor, c.membrane_shear_factor, c.bending_bulk_factor, c.bending_shear_factor}) {
      EXPECT_GT(f, 0.0);
      EXPECT_LT(f, alpha);  // below Voigt
    }
    EXPECT_LT(c.bending_bulk_factor, 0.8 * c.bending_shear_factor);
    EXPECT_LT(nu_b, nu - 0.1);
  }
}

// The square lattice (CellOptions::lattice): a solid cell is the closed forms; circles on it give a
// stiffness with the square's symmetry (C11 = C22, no shear-stretch coupling along the axes) and two
// deviatoric moduli, (C11 − C12)/2 for a shear along the axes and C33 at 45° to them.
//  - Stretched, the straight ligaments between nearest neighbours carry a shear along the axes
//    (ε_xx = −ε_yy) in tension and compression, and one at 45° in bending: measured
//    (C11 − C12)/2 / C33 = 3.67, 1.89, 1.17 at α = 0.5, 0.67, 0.85, and Young's modulus along the
//    axes 1.40, 1.17, 1.05 times the hexagonal lattice's at the same α.
//  - Bent, it is the other way round: the ligaments bent along the axes are free strips (their
//    anticlastic curvature is free), twisted at 45° they are not; measured 0.87, 0.94, 0.98, and the
//    plate's Young's modulus in bending along the axes 0.925, 0.966, 0.982 of the hexagonal
//    lattice's. A cantilever along the axes bends: the perforated-lattice suite's square rows
//    (coarse, calibrated on the hexagonal cell, against conforming: 0.929 / 0.928 at α = 0.5, 0.967 /
//    0.972 at 0.67 at 1 d / 2 d) are this ratio. Of the 7.5% at α = 0.5, 3.5% is the isotropic
//    projection's (0.965 of the hexagonal lattice's) and 4.1% the anisotropy's (0.959).
TEST(CellHomogenisation, TheSquareLatticeHasTheSquaresSymmetryAndTwoShearModuli) {
  const Material m = test::pa12();
  CellOptions square;
  square.lattice = CellLattice::Square;
  const CellStiffness solid = homogenise_cell(circle(), m, 1.0, square);
  EXPECT_LE(relative(solid.membrane, solid_membrane_stiffness(m)), 1e-9) << solid.membrane;
  EXPECT_LE(relative(solid.bending, solid_bending_stiffness(m)), 1e-9) << solid.bending;
  // The bounding circle within 0.45 spacings of the centre on both lattices: the square cell (area
  // 1) holds less hole than the hexagonal one (√3/2).
  const double circle_area = circle().area;
  EXPECT_NEAR(max_hole_fraction(circle(), 0.1, CellLattice::Square), circle_area * 0.45 * 0.45, 1e-12);
  EXPECT_NEAR(max_hole_fraction(circle(), 0.1), circle_area * 0.45 * 0.45 / (0.5 * std::numbers::sqrt3), 1e-12);
  double last_membrane = INFINITY;
  for (double alpha : {0.5, 0.67, 0.85}) {
    const CellStiffness c = homogenise_cell(circle(), m, alpha, square);
    const CellStiffness h = homogenise_cell(circle(), m, alpha);
    EXPECT_NEAR(c.window_fill_ratio, alpha, 0.01);
    for (const auto& [C, H, bending] : {std::tuple{c.membrane, h.membrane, false}, std::tuple{c.bending, h.bending, true}}) {
      const double G_axes = 0.5 * (C(0, 0) - C(0, 1)), G_45 = C(2, 2);
      const double E_axes = 1 / C.inverse()(0, 0), E_hex = 1 / H.inverse()(0, 0);
      const Eigen::Vector2d iso = isotropic_moduli(C);
      // Young's modulus of the isotropic projection (what the isotropic split gives a cantilever).
      const Eigen::Matrix3d P = (Eigen::Matrix3d() << iso[0] + iso[1], iso[0] - iso[1], 0, iso[0] - iso[1],
                                 iso[0] + iso[1], 0, 0, 0, iso[1]).finished();
      const double E_projection = 1 / P.inverse()(0, 0);
      std::cout << "alpha " << alpha << (bending ? " bending" : " membrane") << ": square G_axes/G_45 "
                << G_axes / G_45 << ", E_axes / E_hex " << E_axes / E_hex << ", E_axes / E of its isotropic projection "
                << E_axes / E_projection << ", E of the projection / E_hex " << E_projection / E_hex << "\n";
      // q of the rule's anisotropic part (fill_stiffness_map.h); the hexagonal lattice has none
      // (its q is the cell mesh's asymmetry), so the calibration leaves it out.
      EXPECT_NEAR(bending ? c.bending_anisotropy : c.membrane_anisotropy, (G_axes - G_45) / (G_axes + G_45), 0.005);
      EXPECT_LT(std::abs(bending ? h.bending_anisotropy : h.membrane_anisotropy), 0.01) << alpha;
      EXPECT_NEAR(C(0, 0), C(1, 1), 0.01 * C(0, 0)) << bending;
      EXPECT_LE(std::abs(C(0, 2)) + std::abs(C(1, 2)), 0.01 * C(0, 0)) << bending;
      if (!bending) {
        EXPECT_GT(G_axes, 1.1 * G_45) << alpha;
        EXPECT_LT(G_axes / G_45, last_membrane) << "the anisotropy fades as the holes shrink";
        EXPECT_GT(E_axes, E_hex) << alpha;
        last_membrane = G_axes / G_45;
      } else {
        EXPECT_LT(G_axes, G_45) << alpha;
        EXPECT_LT(E_axes, E_hex) << alpha;
        if (alpha == 0.5) {
          EXPECT_LT(E_axes, 0.95 * E_hex);
        }
      }
    }
  }
}

TEST(CellHomogenisation, ConvergesUnderRefinement) {
  // α = 0.6 (circles): resolutions 24 (the default), 48 and 96 edges per lattice spacing.
  const Material m = test::pa12();
  std::vector<CellStiffness> c;
  for (double resolution : {24.0, 48.0, 96.0}) {
    CellOptions o;
    o.resolution = resolution;
    o.rim_edges = 0;  // the resolution asked, not raised for the rim
    c.push_back(homogenise_cell(circle(), m, 0.6, o));
    std::cout << "resolution " << resolution << " (" << c.back().faces << " faces): g_m " << c.back().membrane_factor
              << ", g_b " << c.back().bending_factor << "\n";
  }
  const auto error = [&](size_t k, bool membrane) {
    return membrane ? std::abs(c[k].membrane_factor - c[2].membrane_factor) / c[2].membrane_factor
                    : std::abs(c[k].bending_factor - c[2].bending_factor) / c[2].bending_factor;
  };
  for (bool membrane : {true, false}) {
    EXPECT_LT(error(0, membrane), 0.015) << (membrane ? "membrane" : "bending");
    EXPECT_LT(error(1, membrane), error(0, membrane)) << (membrane ? "membrane" : "bending");
  }
}

TEST(CellHomogenisation, EveryBuiltInShapeHomogenisesAtTheCalibrationFillRatios) {
  // What calibrate_fill_stiffness computes for each built-in kind (default parameters, default
  // resolution 24, raised where the ligament is narrow): the grid's fill ratios, raised to the
  // lowest the lattice holds — where the holes cross the period cell's sides for most kinds. The flower at
  // α = 0.75 threw "homogenisation cell: face 391 has zero area" (a flat cap on two collinear
  // outline edges after the remesh) before the remesh's cap-and-needle repair; measured without
  // it, 61 of 1416 cells (9 kinds, α 0.40–0.99, resolutions 12–48) failed that way.
  // Sane factors: 0 < g_m < g_b ≤ α (Voigt bound; membrane softened more than bending), both
  // increasing with α, and the meshed cell's fill ratio the one asked for.
  const Material m = test::pa12();
  for (const std::string& kind : builtin_stencil_kinds()) {
    const StencilShape shape = make_builtin_stencil(kind, {}, kind);
    const double lowest = 1 - max_hole_fraction(shape);
    std::vector<double> alphas;
    for (double a : calibration_grid())
      if (a < 1 && (alphas.empty() || std::max(a, lowest) > alphas.back())) alphas.push_back(std::max(a, lowest));
    double last_m = 0, last_b = 0;
    for (double a : alphas) {
      SCOPED_TRACE(kind + " at alpha " + std::to_string(a));
      CellStiffness c;
      ASSERT_NO_THROW(c = homogenise_cell(shape, m, a));
      EXPECT_NEAR(c.window_fill_ratio, a, 1e-3);
      EXPECT_GT(c.membrane_factor, 0);
      EXPECT_LT(c.membrane_factor, c.bending_factor);
      EXPECT_LE(c.bending_factor, a);
      EXPECT_GT(c.membrane_factor, last_m);
      EXPECT_GT(c.bending_factor, last_b);
      last_m = c.membrane_factor;
      last_b = c.bending_factor;
    }
  }
}

// A shape that cannot reach the grid's lower fill ratios (the default star: its bounding circles
// come within a tenth of a spacing at α 0.656 on the hexagonal lattice) has no cell below that,
// and its curve must follow its cells from there up: the lowest is a sample of its own
// (calibration_samples), and below it the ratios continue the secant of the lowest two samples to
// the grid point under it (then held), so the cubic leaves the lowest at the cells' slope. Checked
// against cells solved between the lowest and the next sample (α 0.67 and 0.70): within 2% on each
// of the split's four ratios, and closer than the grid alone — the lowest cell's ratios held at
// the grid point below it, the curve rising from there, as before (up to 8% too stiff at 0.67; the
// output lines) — and closer than holding them flat from the lowest (the cubic then starts flat
// and lags: 5% soft). A circle's library, whose lowest (0.27) is below the grid, is sampled on the
// grid alone.
TEST(FillStiffnessCalibration, AShapesCurveFollowsItsCellsFromItsLowestFillRatio) {
  const Material m = test::pa12();
  StencilLibrary circles;
  circles.add(circle());
  EXPECT_EQ(calibration_samples(circles, CellLattice::Hexagonal), calibration_grid());
  StencilLibrary stars;
  stars.add(make_builtin_stencil("star", {}, "star"));
  const double lowest = 1 - max_hole_fraction(stars[0]);
  ASSERT_GT(lowest, 0.6);
  ASSERT_LT(lowest, 0.75);
  const std::vector<double> samples = calibration_samples(stars, CellLattice::Hexagonal);
  ASSERT_EQ(samples.size(), calibration_grid().size() + 1);
  EXPECT_EQ(std::count(samples.begin(), samples.end(), lowest), 1);
  EXPECT_TRUE(std::is_sorted(samples.begin(), samples.end()));
  const size_t k = size_t(std::find(samples.begin(), samples.end(), lowest) - samples.begin());
  ASSERT_EQ(samples[k - 1], 0.6);

  const FillStiffnessCurve curve = calibrate_fill_stiffness(stars, m);
  ASSERT_EQ(curve.alpha, samples);
  const CellStiffness cell_low = homogenise_cell(stars[0], m, lowest);
  std::vector<CellStiffness> cells;
  for (const double a : {0.67, 0.70}) cells.push_back(homogenise_cell(stars[0], m, a));
  using Factor = double CellStiffness::*;
  const std::vector<std::tuple<const char*, const std::vector<double>*, Factor>> ratios = {
      {"membrane bulk", &curve.membrane_bulk, &CellStiffness::membrane_bulk_factor},
      {"membrane shear", &curve.membrane_shear, &CellStiffness::membrane_shear_factor},
      {"bending bulk", &curve.bending_bulk, &CellStiffness::bending_bulk_factor},
      {"bending shear", &curve.bending_shear, &CellStiffness::bending_shear_factor}};
  for (const auto& [what, r, factor] : ratios) {
    SCOPED_TRACE(what);
    const MonotoneCurve now(curve.alpha, *r);
    const double r_low = cell_low.*factor / cell_low.window_fill_ratio;
    // (The calibration solves its cells with a canonical material of the same ν: round-off apart.)
    EXPECT_NEAR((*r)[k], r_low, 1e-6) << "the lowest cell's ratio at the lowest";
    // Below: the secant continued to 0.6, held from there, softer than the lowest cell.
    const double slope = ((*r)[k + 1] - (*r)[k]) / (samples[k + 1] - samples[k]);
    EXPECT_NEAR(now(0.6), std::max((*r)[k] - slope * (lowest - 0.6), (*r)[k] / 2), 1e-12);
    EXPECT_NEAR(now(0.45), now(0.6), 1e-14);
    EXPECT_LT(now(0.63), r_low);
    // The grid alone (the lowest sample left out, its ratio held at the grid point below, as
    // before), and the ratio held flat from the lowest.
    std::vector<double> x = curve.alpha, y = *r, flat = *r;
    for (size_t j = 0; j < k; ++j) flat[j] = r_low;
    x.erase(x.begin() + std::ptrdiff_t(k));
    y.erase(y.begin() + std::ptrdiff_t(k));
    for (size_t j = 0; j < k; ++j) y[j] = r_low;
    const MonotoneCurve grid_alone(x, y), held_flat(curve.alpha, flat);
    for (size_t c = 0; c < cells.size(); ++c) {
      const double a = cells[c].fill_ratio, exact = cells[c].*factor / cells[c].window_fill_ratio;
      std::printf("%s at α %.2f: cell %.4f, curve %.4f (%+.1f%%), the grid alone %+.1f%%, held flat %+.1f%%\n", what,
                  a, exact, now(a), 100 * (now(a) / exact - 1), 100 * (grid_alone(a) / exact - 1),
                  100 * (held_flat(a) / exact - 1));
      EXPECT_NEAR(now(a) / exact, 1.0, 0.02) << a;
      EXPECT_LT(std::abs(now(a) - exact), std::abs(grid_alone(a) - exact)) << a;
      EXPECT_LT(std::abs(now(a) - exact), std::abs(held_flat(a) - exact)) << a;
    }
  }
}

TEST(CellHomogenisation, RejectsFillRatiosTheLatticeCannotHold) {
  // Circles reach α = 0.27 (bounding circles a tenth of a spacing apart), not 0.2.
  EXPECT_NEAR(1 - max_hole_fraction(circle()), 1 - circle().area * 0.45 * 0.45 / (std::sqrt(3.0) / 2), 1e-12);
  EXPECT_THROW(homogenise_cell(circle(), test::pa12(), 0.2), InputError);
  EXPECT_THROW(homogenise_cell(circle(), test::pa12(), 1.2), InputError);
}

TEST(CellHomogenisation, RejectsBadOptions) {
  for (const double resolution : {5.0, 201.0, double(NAN)}) {
    CellOptions o;
    o.resolution = resolution;
    EXPECT_THROW(homogenise_cell(circle(), test::pa12(), 0.8, o), InputError) << resolution;
  }
  for (const double edges : {-1.0, 65.0, double(NAN)}) {
    CellOptions o;
    o.rim_edges = edges;
    EXPECT_THROW(homogenise_cell(circle(), test::pa12(), 0.8, o), InputError) << edges;
  }
}

}  // namespace
}  // namespace cutwork::solvers

// The ligament peak estimate of solvers/objective/ligament_peak.h: the two-hole table, the lattice's
// ligament at a fill ratio, the pair parameter of unequal holes, and the rule on a small mesh.
// The table itself is what the conforming solver measures: tests/solvers/conforming/ligament_test.cpp.
#include "solvers/objective/ligament_peak.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>

#include "host/core/error.h"
#include "host/surfaces/generators.h"

namespace cutwork::solvers {
namespace {

TEST(LigamentPeak, TheTwoHoleTableGrowsAsTheRootOfRadiusOverWidth) {
  EXPECT_DOUBLE_EQ(two_hole_concentration(0), 3.0);  // Kirsch
  EXPECT_DOUBLE_EQ(two_hole_concentration(4), 5.71);
  EXPECT_DOUBLE_EQ(two_hole_concentration(64), 24.34);
  // Increasing between the samples, and √x beyond the last.
  double last = 0;
  for (double x = 0; x <= 64; x += 0.25) {
    const double k = two_hole_concentration(x);
    EXPECT_GT(k, last) << x;
    last = k;
  }
  EXPECT_NEAR(two_hole_concentration(256), 2 * 24.34, 1e-12);
  // Bending: Goodier's (5 + 3ν)/(3 + ν) at ν = 0.4, and the same growth.
  EXPECT_NEAR(two_hole_bending_concentration(0), 6.2 / 3.4, 1e-12);
  last = 0;
  for (double x = 0; x <= 64; x += 0.25) {
    const double k = two_hole_bending_concentration(x);
    EXPECT_GT(k, last) << x;
    EXPECT_LT(k, two_hole_concentration(x)) << x;
    last = k;
  }
  EXPECT_NEAR(two_hole_bending_concentration(256), 2 * 14.84, 1e-12);
  // The measured samples' own growth per doubling at small w approaches √2 (the asymptotics).
  EXPECT_NEAR(two_hole_concentration(64) / two_hole_concentration(32), std::sqrt(2.0), 0.05);
}

TEST(LigamentPeak, TheLatticeLigamentFollowsTheHexagonalPacking) {
  EXPECT_EQ(lattice_ligament_parameter(1.0), 0.0);
  // α = 1 − (2π/√3)(R/p)²: a lattice of R/p = 0.4 has ligament p − 2R = 0.2 p, so x = R/w = 2.
  const double rp = 0.4, alpha = 1 - 2 * std::numbers::pi / std::sqrt(3.0) * rp * rp;
  EXPECT_NEAR(lattice_ligament_parameter(alpha), 2.0, 1e-12);
  EXPECT_NEAR(lattice_ligament_parameter(0.3), 3.62, 0.01);
  // Touching circles: no ligament.
  EXPECT_TRUE(std::isinf(lattice_ligament_parameter(1 - std::numbers::pi / (2 * std::sqrt(3.0)) - 1e-12)));
  // The square lattice: α = 1 − π (R/p)², so R/p = 0.4 at α = 1 − 0.16π, x = 2 again; at the same
  // α its holes are larger than the hexagonal lattice's and its ligaments narrower.
  const PerforationLattice square = PerforationLattice::Square;
  EXPECT_NEAR(lattice_ligament_parameter(1 - std::numbers::pi * rp * rp, square), 2.0, 1e-12);
  EXPECT_GT(lattice_ligament_parameter(0.6, square), lattice_ligament_parameter(0.6));
  EXPECT_TRUE(std::isinf(lattice_ligament_parameter(1 - std::numbers::pi / 4 - 1e-12, square)));
  EXPECT_TRUE(std::isfinite(lattice_ligament_parameter(1 - std::numbers::pi / 4 + 1e-9, square)));
}

TEST(LigamentPeak, UnequalHolesReadTheTableAtTheirPairParameter) {
  Ligament l;
  l.width = 0.001;
  l.radius_a = l.radius_b = 0.02;
  l.size_a = l.size_b = 0.02;
  EXPECT_NEAR(pair_parameter(l), 20.0, 1e-12);  // R/w for equal holes
  EXPECT_NEAR(bending_pair_parameter(l), 20.0, 1e-12);
  // ρ_b = 2 ρ_a: R_h = 4/3 ρ_a, S = 5/3 ρ_a, x = S²/(R_h w) = 25/12 ρ_a/w, x_b = R_h/w = 4/3 ρ_a/w.
  l.radius_b = l.size_b = 0.04;
  EXPECT_NEAR(pair_parameter(l), 25.0 / 12 * 20, 1e-9);
  EXPECT_NEAR(bending_pair_parameter(l), 4.0 / 3 * 20, 1e-9);
  // A straight rim counts as large as its hole.
  l.radius_b = std::numeric_limits<double>::infinity();
  EXPECT_NEAR(pair_parameter(l), 25.0 / 12 * 20, 1e-9);
  EXPECT_NEAR(bending_pair_parameter(l), 4.0 / 3 * 20, 1e-9);
  l.width = 0;
  EXPECT_TRUE(std::isinf(bending_pair_parameter(l)));
  l.width = 0.001;
  // The readings the header quotes for the measured unequal pairs (w = R/8; ρ_b/ρ_a = 3 at R/16).
  struct Pair {
    double ratio, w;
    double measured;
  };
  for (const Pair& p : {Pair{0.5, 0.125, 8.29}, Pair{1.5, 0.125, 10.73}, Pair{2, 0.125, 13.13}, Pair{3, 0.0625, 25.75},
                        Pair{4, 0.125, 22.92}}) {
    Ligament q;
    q.width = p.w;
    q.radius_a = q.size_a = 1;
    q.radius_b = q.size_b = p.ratio;
    const double k = two_hole_concentration(pair_parameter(q));
    std::cout << "rho_b/rho_a " << p.ratio << ": measured " << p.measured << ", read " << k << "\n";
    EXPECT_NEAR(k, p.measured, 0.11 * p.measured) << p.ratio;
  }
}

/// A flat 0.2 m square of 2 × 8² triangles.
SurfaceMesh square() { return generate_shape("plate", {{"width", 0.2}, {"height", 0.2}}, 0.025); }

TEST(LigamentPeak, TheRuleRaisesTheFacesAboutANarrowLigamentByTheFactorsRatio) {
  const SurfaceMesh mesh = square();
  const int nf = mesh.num_faces();
  Eigen::VectorXd alpha = Eigen::VectorXd::Ones(nf), W = Eigen::VectorXd::Constant(nf, 2.0);
  // One face with holes (α = 0.5) and a larger W_peak, near the ligament.
  Ligament l;
  l.width = 0.0005;
  l.radius_a = l.radius_b = l.size_a = l.size_b = 0.01;
  l.point_a = Vec3(-0.00025, 0, 0);
  l.point_b = Vec3(0.00025, 0, 0);
  const double x = pair_parameter(l);
  ASSERT_NEAR(x, 20, 1e-9);
  const double K = two_hole_concentration(x);
  // All faces uncut: the pair in solid material, K(x)² × W, read at a face about the midpoint.
  std::vector<LigamentPeak> p = ligament_peaks(mesh, alpha, W, std::span(&l, 1), 0.3);
  ASSERT_EQ(p.size(), 1u);
  const double Kb = two_hole_bending_concentration(x), kb0 = two_hole_bending_concentration(0);
  // The larger of the two ratios: here the membrane's, (11.6/3)² against the bending's (7.4/1.82)².
  const double f0 = std::max((K / 3) * (K / 3), (Kb / kb0) * (Kb / kb0));
  EXPECT_NEAR(p[0].W, 2.0 * f0, 1e-9);
  EXPECT_NEAR(p[0].x_lattice, 0.0, 0);
  EXPECT_NEAR(p[0].x_bending, 20, 1e-9);
  EXPECT_LE((mesh.vertices().row(mesh.faces()(p[0].face, 0)).transpose() - l.midpoint()).norm(), 0.05);
  // A perforated face nearby with W_peak 10 at α = 0.5: the factor at its lattice.
  int near = -1;
  for (int f = 0; f < nf && near < 0; ++f) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 3; ++k) c += mesh.vertices().row(mesh.faces()(f, k)).transpose() / 3;
    if ((c - l.midpoint()).norm() < 0.01) near = f;
  }
  ASSERT_GE(near, 0);
  alpha(near) = 0.5;
  W(near) = 10;
  p = ligament_peaks(mesh, alpha, W, std::span(&l, 1), 0.3);
  auto factor = [&](double a) {
    const double xl = lattice_ligament_parameter(a);
    const double rm = K / two_hole_concentration(xl), rb = Kb / two_hole_bending_concentration(xl);
    return std::max(rm * rm, rb * rb);
  };
  EXPECT_EQ(p[0].face, near);
  EXPECT_NEAR(p[0].W, 10 * factor(0.5), 1e-9);
  // Below the calibrated curve's lowest sample the lattice is the one at that sample.
  alpha(near) = 0.1;
  p = ligament_peaks(mesh, alpha, W, std::span(&l, 1), 0.3);
  EXPECT_NEAR(p[0].W, 10 * factor(0.3), 1e-9);
  // A ligament as wide as the lattice's (x below x_lat) is not lowered: the factor is at least 1.
  l.width = 0.01 / 2;  // x = 2 < x_lat(0.3) = 3.6
  l.point_a = Vec3(-0.0025, 0, 0);
  l.point_b = Vec3(0.0025, 0, 0);
  p = ligament_peaks(mesh, alpha, W, std::span(&l, 1), 0.3);
  EXPECT_GE(p[0].factor, 1.0);
  EXPECT_GE(p[0].W, 10.0);
  // Sizes that do not match are refused.
  EXPECT_THROW(ligament_peaks(mesh, alpha.head(3), W, std::span(&l, 1), 0.3), InputError);
}

// The faces about each ligament are found in a slab of the faces sorted by x: the same estimate
// as a scan of every face (the brute-force twin below), on random ligaments over a random field.
TEST(LigamentPeak, TheSlabSearchIsTheBruteForceScan) {
  const SurfaceMesh mesh = generate_shape("plate", {{"width", 0.2}, {"height", 0.2}}, 0.01);
  const int nf = mesh.num_faces();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::VectorXd alpha(nf), W(nf);
  for (int f = 0; f < nf; ++f) alpha(f) = 0.2 + 0.8 * u(rng), W(f) = 10 * u(rng);
  std::vector<Ligament> ls;
  for (int k = 0; k < 200; ++k) {
    Ligament l;
    l.width = 0.0005 + 0.01 * u(rng);
    l.radius_a = l.size_a = 0.002 + 0.03 * u(rng);
    l.radius_b = l.size_b = 0.002 + 0.03 * u(rng);
    const Vec3 m(0.2 * u(rng) - 0.1, 0.2 * u(rng) - 0.1, 0);
    l.point_a = m - Vec3(l.width / 2, 0, 0);
    l.point_b = m + Vec3(l.width / 2, 0, 0);
    ls.push_back(l);
  }
  const std::vector<LigamentPeak> p = ligament_peaks(mesh, alpha, W, ls, 0.3);
  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  for (std::size_t i = 0; i < ls.size(); ++i) {
    const Ligament& l = ls[i];
    const double x = pair_parameter(l), S = l.pair_radius();
    const double Km = two_hole_concentration(x), Kb = two_hole_bending_concentration(bending_pair_parameter(l));
    double best = -1, nearest_d2 = INFINITY;
    int nearest = -1;
    auto value = [&](int f) {
      const double xl = lattice_ligament_parameter(std::clamp(alpha(f), 0.3, 1.0));
      const double rm = Km / two_hole_concentration(xl), rb = Kb / two_hole_bending_concentration(xl);
      return std::max({1.0, rm * rm, rb * rb}) * W(f);
    };
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const Vec3 c = (V.row(F(f, 0)) + V.row(F(f, 1)) + V.row(F(f, 2))).transpose() / 3.0;
      const double d2 = (c - l.midpoint()).squaredNorm();
      if (d2 < nearest_d2) nearest_d2 = d2, nearest = f;
      if (d2 <= S * S) best = std::max(best, value(f));
    }
    best = std::max(best, value(nearest));
    EXPECT_DOUBLE_EQ(p[i].W, best) << i;
  }
}

}  // namespace
}  // namespace cutwork::solvers

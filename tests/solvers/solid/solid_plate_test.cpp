// The 3-D plate solver (solvers/solid/solid_plate.h) against exact fields and closed forms.
//
//  - Without holes the exact membrane and bending fields are quadratic in x, y, z: quadratic
//    tetrahedra hold them exactly (the patch test), whatever the mesh's grading.
//  - A circular hole of radius a in a thin plate (t = a/10) under uniaxial tension: Kirsch's 3.
//  - The same hole in uniaxial bending: Roark's fit of Reissner's factor (Young & Budynas, Table
//    17.1, ν = 0.3), K_t(x) = 1.79 + 0.25/(0.39 + x) + 0.81/(1 + x²) − 0.26/(1 + x³), x = 2a/t.
//    Where the plate is thin (x = 4) the 3-D face reads it. Where it is thick (x = 0.5) the 3-D
//    face reads about 10% below it (2.22–2.24 against 2.49 over meshes of 6–10 layers and rims at
//    a/10–a/20), the largest σ_tt lies just below the face, and the same plate in tension reads
//    2.56 on the face and 3.07 on the mid-plane: the free face's corner effect, which a plate
//    theory (Reissner's σ_zz = 0 and a fixed shear profile through the thickness) does not have.
//    That test checks the bounds and the 3-D signature, not Roark's value.
//
// The DISABLED_ measurement at the end reads the built-in star opened by a tool of radius 1/8
// against W_peak's thick-plate rule k_b' = (1 − φ) k_b,thin + φ k_m, φ = thick_round_transition
// (solvers/objective/peak_energy_density.h "Thick plates"), read at x = 2r/t (the round) and at
// 2s/t (the star's size, what W_peak reads) (run with --gtest_also_run_disabled_tests; 3.5 min,
// 3.9 GB). Measured (face z = t/2; the rule's columns with φ normalised by 3 − 1.79):
//   star: k_m 6.38 / 6.31 and k_b,thin (x = 8) 2.99 / 2.98 at rims r/12 / r/24;
//   x = 2r/t     2      1      0.5    0.25
//   k_3D, r/12   3.188  3.318  3.504  3.742
//   k_3D, r/24   3.150  3.284  3.463  3.699   (−1.0 to −1.2% from r/12)
//   rule, x = 2r/t   3.63   4.23   4.90   5.45    (+15% to +47%: r/t does not govern the star)
//   rule, x = 2s/t (s = 1, the star's size)   3.03 3.09 3.25 3.63   (−1.8% to −6.1%, r/24)
//   circle (a = 1, k_m 3.018, k_b,thin 1.848): k_3D 1.982, 2.106, 2.267, 2.398 against Roark
//   2.028, 2.245, 2.488, 2.687 and the rule 2.078, 2.288, 2.523, 2.715 (+5% to +13%).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "host/stencil/stencil_opening.h"
#include "host/stencil/stencil_shape.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/solid/solid_plate.h"

namespace cutwork::solvers {
namespace {

/// Roark's fit of Reissner's bending factor at a circular hole, x = 2a/t (ν = 0.3).
double roark_bending(double x) {
  return 1.79 + 0.25 / (0.39 + x) + 0.81 / (1 + x * x) - 0.26 / (1 + x * x * x);
}

std::vector<Vec2> square(double half_width) {
  return {{-half_width, -half_width}, {half_width, -half_width}, {half_width, half_width}, {-half_width, half_width}};
}

/// A circular hole of radius 1 at the centre of a square plate, uniaxial along x.
SolidPlateInput circle_plate(PlateLoadKind kind, double thickness, double half_width, double rim_edge, int layers,
                             double layer_ratio) {
  SolidPlateInput in;
  in.outer = square(half_width);
  in.holes = {circle_polyline(Vec2::Zero(), 1.0, 1024)};
  in.thickness = thickness;
  in.young = 1.0;
  in.poisson = 0.3;
  in.load = {kind, 1.0, 0.0, 0.0};
  in.mesh.rim_edge = rim_edge;
  in.mesh.max_edge = half_width / 4;
  in.mesh.growth = 0.3;
  in.mesh.layers = layers;
  in.mesh.layer_ratio = layer_ratio;
  return in;
}

void print(const char* name, const SolidPlateResult& r, double reference) {
  std::printf("%s: k %.4f (reference %.4f, %+.2f%%), largest at any z %.4f at z %.3f; %d tetrahedra, %d unknowns, "
              "factor %ld nonzeros; mesh %.2f s, assembly %.2f s, solve %.2f s\n",
              name, r.k, reference, 100 * (r.k / reference - 1), r.peak_sigma_tt_any_z / r.nominal, r.peak_z,
              r.tetrahedra, r.free_dofs, r.factor_nonzeros, r.mesh_seconds, r.assembly_seconds, r.solve_seconds);
}

TEST(SolidPlate, ReproducesTheExactMembraneAndBendingFieldsWithoutHoles) {
  for (PlateLoadKind kind : {PlateLoadKind::Membrane, PlateLoadKind::Bending}) {
    SolidPlateInput in;
    in.outer = {{-2.0, -1.5}, {2.5, -1.3}, {2.2, 1.2}, {-1.8, 1.4}};
    in.thickness = 0.4;
    in.young = 200.0;
    in.poisson = 0.3;
    in.load = {kind, 1.3, -0.4, 0.7};  // every component, so that a wrong sign or factor shows
    in.mesh.rim_edge = 0.3;
    in.mesh.max_edge = 0.6;
    in.mesh.focus = {{0.2, 0.1}};
    in.mesh.layers = 3;
    in.mesh.layer_ratio = 0.5;
    const SolidPlateResult r = solve_solid_plate(in);
    // The interior is solved for, not imposed: most unknowns are free.
    ASSERT_GT(r.free_dofs, r.dofs / 2);
    double error = 0, scale = 0;
    for (std::size_t n = 0; n < r.node_positions.size(); ++n) {
      const Vec3 exact = plate_exact_displacement(in, r.node_positions[n]);
      error = std::max(error, (r.displacements[n] - exact).norm());
      scale = std::max(scale, exact.norm());
    }
    std::printf("%s: %d nodes, largest error %.2e of the largest displacement\n",
                kind == PlateLoadKind::Membrane ? "membrane" : "bending", r.nodes, error / scale);
    EXPECT_LT(error, 1e-8 * scale);
    EXPECT_TRUE(r.rims.empty());
  }
}

TEST(SolidPlate, TheExactBendingFieldIsInEquilibriumWithFreeFaces) {
  // The closed form itself: σ_iz = 0 at every z (free faces), and its moments are the input's.
  SolidPlateInput in;
  in.thickness = 0.3;
  in.young = 7.0;
  in.poisson = 0.25;
  in.load = {PlateLoadKind::Bending, 2.0, -1.0, 0.5};
  const double t = in.thickness;
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  const int steps = 64;  // the midpoint rule is exact for z² up to rounding
  for (int i = 0; i < steps; ++i) {
    const double z = -t / 2 + t * (i + 0.5) / steps;
    moment += plate_exact_stress(in, z) * z * (t / steps);
  }
  EXPECT_NEAR(moment(0, 0), 2.0, 1e-3);
  EXPECT_NEAR(moment(1, 1), -1.0, 1e-3);
  EXPECT_NEAR(moment(0, 1), 0.5, 1e-3);
  EXPECT_EQ(plate_exact_stress(in, t / 2).col(2).norm(), 0.0);
  // The strain of the displacement by central differences is Hooke's of the stress.
  const Vec3 p(0.3, -0.7, 0.11);
  const double h = 1e-4;
  Eigen::Matrix3d grad;
  for (int j = 0; j < 3; ++j) {
    const Vec3 dp = Vec3::Unit(j) * h;
    grad.col(j) = (plate_exact_displacement(in, p + dp) - plate_exact_displacement(in, p - dp)) / (2 * h);
  }
  const Eigen::Matrix3d eps = 0.5 * (grad + grad.transpose());
  const double nu = in.poisson, e = in.young;
  const Eigen::Matrix3d sigma =
      e / (1 + nu) * (eps + nu / (1 - 2 * nu) * eps.trace() * Eigen::Matrix3d::Identity());
  EXPECT_LT((sigma - plate_exact_stress(in, p.z())).norm(), 1e-7 * plate_exact_stress(in, p.z()).norm());
}

TEST(SolidPlate, ACircularHoleInTensionReadsKirsch) {
  // A thin plate (t = a/10): generalised plane stress, Kirsch's 3 at θ = ±90°. The plate's half
  // width is 15a, the far field imposed there; the hole's disturbance is down to a²/r² ≈ 0.4%.
  const SolidPlateInput in = circle_plate(PlateLoadKind::Membrane, 0.1, 15.0, 1.0 / 12, 1, 1.0);
  const SolidPlateResult r = solve_solid_plate(in);
  print("tension, t = a/10", r, 3.0);
  EXPECT_NEAR(r.k, 3.0, 0.03 * 3.0);
  // At θ = ±90° (the rim node nearest it; the rim is resampled on the 1024-gon's chords).
  EXPECT_GT(std::abs(r.peak_position.y()), 0.99);
  EXPECT_LT(std::abs(r.peak_position.x()), 0.1);
  // Kirsch's rim stress at θ = 0 is −σ.
  double at_zero = 0, closest = 1e9;
  for (const RimStress& s : r.rims[0])
    if (std::abs(s.position.y()) < closest && s.position.x() > 0) closest = std::abs(s.position.y()), at_zero = s.sigma_tt;
  EXPECT_NEAR(at_zero / r.nominal, -1.0, 0.05);
}

TEST(SolidPlate, ACircularHoleInBendingReadsRoarkWhereThePlateIsThin) {
  const double x = 4.0;  // 2a/t: t = a/2
  const SolidPlateInput in = circle_plate(PlateLoadKind::Bending, 2.0 / x, 12.0, 0.1, 2, 1.0);
  const SolidPlateResult r = solve_solid_plate(in);
  print("bending, x = 4", r, roark_bending(x));
  EXPECT_NEAR(r.k, roark_bending(x), 0.03 * roark_bending(x));
  EXPECT_GT(std::abs(r.peak_position.y()), 0.99);
  EXPECT_LT(std::abs(r.peak_position.x()), 0.1);
}

TEST(SolidPlate, ACircularHoleInBendingWhereThePlateIsThickReadsBetweenKirchhoffAndReissner) {
  // x = 0.5: t = 4a. See the file's head: the 3-D face reads about 10% below Reissner's 2.49.
  const double x = 0.5;
  const SolidPlateInput in = circle_plate(PlateLoadKind::Bending, 2.0 / x, 12.0, 0.1, 6, 0.7);
  const SolidPlateResult r = solve_solid_plate(in);
  print("bending, x = 0.5", r, roark_bending(x));
  // Above Goodier's thin-plate 1.79 by most of the way to Reissner's, below Reissner's.
  EXPECT_GT(r.k, 1.79 + 0.6 * (roark_bending(x) - 1.79));
  EXPECT_LT(r.k, roark_bending(x));
  // The 3-D signature: the largest σ_tt lies just below the face (within the top 10%), above it.
  EXPECT_LT(r.peak_z, in.thickness / 2);
  EXPECT_GT(r.peak_z, 0.4 * in.thickness);
  EXPECT_GT(r.peak_sigma_tt_any_z, r.peak_sigma_tt);
}

// ---------------------------------------------------------------------------------------------
// Measurement (not a test): the built-in star (bounding radius s = 1) opened by a tool of radius
// r = 1/8, one hole in a plate of half-width 12, uniaxial along x, against the rule; and the circle
// (a = 1) against Roark. The star is turned so that one tip points along +y (across the load,
// where the tips' peak is: checked by the angles scanned) and that tip's round is the focus.

struct StarCase {
  double k = 0;
  double k_any_z = 0;  ///< the largest σ_tt at any z over the nominal
  bool at_focus = true;
  int unknowns = 0;
  double seconds = 0;
};

StarCase star_case(const std::vector<Vec2>& hole, const Vec2& tip, PlateLoadKind kind, double thickness,
                   double rim_edge, int layers, double layer_ratio) {
  SolidPlateInput in;
  in.outer = square(12.0);
  in.holes = {hole};
  in.thickness = thickness;
  in.young = 1.0;
  in.poisson = 0.3;
  in.load = {kind, 1.0, 0.0, 0.0};
  in.mesh.rim_edge = rim_edge;
  in.mesh.max_edge = 3.0;
  in.mesh.growth = 0.3;
  in.mesh.layers = layers;
  in.mesh.layer_ratio = layer_ratio;
  for (const Vec2& p : hole)
    if ((p - tip).norm() < 0.3) in.mesh.focus.push_back(p);
  const SolidPlateResult r = solve_solid_plate(in);
  return {r.k, r.peak_sigma_tt_any_z / r.nominal, (r.peak_position - tip).norm() < 0.3, r.free_dofs,
          r.mesh_seconds + r.assembly_seconds + r.solve_seconds};
}

/// Layers over the half thickness, graded by 0.7 until the top one is about 1.5 rim edges.
int layers_for(double half, double rim_edge) {
  for (int n = 1; n < 12; ++n) {
    const double top = half * 0.3 / (1 - std::pow(0.7, n)) * std::pow(0.7, n - 1);
    if (top < 1.5 * rim_edge) return n;
  }
  return 12;
}

/// The built-in star (bounding radius 1) with the drawn tip nearest +y (a vertex on the bounding
/// circle) turned onto +y, plus `extra` radians, opened by a tool of radius `r_tool` (1° arcs): the
/// hole and where that tip is.
std::pair<std::vector<Vec2>, Vec2> turned_star(double r_tool, double extra) {
  const StencilShape star = make_builtin_stencil("star", {}, "star");
  const auto from_up = [](const Vec2& p) { return std::abs(std::atan2(p.x(), p.y())); };
  Vec2 tip = Vec2::Zero();
  for (const Vec2& p : star.polygon)
    if (p.norm() > 0.99 && (tip.norm() == 0 || from_up(p) < from_up(tip))) tip = p;
  const double a = std::numbers::pi / 2 - std::atan2(tip.y(), tip.x()) + extra;
  const Eigen::Rotation2Dd rot(a);
  std::vector<Vec2> drawn;
  for (const Vec2& p : star.polygon) drawn.push_back(rot * p);
  const OpenedPolygon opened = open_polygon(drawn, r_tool, std::numbers::pi / 180);
  return {opened.polygon, Vec2(rot * tip)};
}

TEST(SolidPlate, DISABLED_StarAndCircleAgainstTheRule) {
  const double r_tool = 1.0 / 8;
  const auto turned = [&](double extra) { return turned_star(r_tool, extra); };
  const double h = r_tool / 12;  // 12 edges per round radius

  // The angle scan (membrane, thin): the tip across the load, and turned by 10°, 20°.
  for (double deg : {0.0, 10.0, 20.0}) {
    const auto [hole, tip_at] = turned(deg * std::numbers::pi / 180);
    const StarCase c = star_case(hole, tip_at, PlateLoadKind::Membrane, r_tool / 4, h, 1, 1.0);
    std::printf("star k_m, tip turned %.0f deg from across the load: %.3f (peak at the focus tip: %d)\n", deg, c.k,
                c.at_focus);
    std::fflush(stdout);
  }
  for (double refine : {1.0, 0.5}) {
    const double hr = h * refine;
    const auto [hole, tip_at] = turned(0.0);
    const StarCase km = star_case(hole, tip_at, PlateLoadKind::Membrane, r_tool / 4, hr, 1, 1.0);
    const StarCase kb = star_case(hole, tip_at, PlateLoadKind::Bending, r_tool / 4, hr, 2, 1.0);
    std::printf("\nstar, rim edge r/%.0f: k_m %.3f (%d unknowns), k_b,thin (x = 8) %.3f (%d unknowns)\n", r_tool / hr,
                km.k, km.unknowns, kb.k, kb.unknowns);
    std::printf("| x = 2r/t | k_3D | largest at any z | rule | rule's error | rule at 2s/t | its error | unknowns "
                "| seconds |\n");
    for (double x : {2.0, 1.0, 0.5, 0.25}) {
      const double t = 2 * r_tool / x;
      const StarCase c = star_case(hole, tip_at, PlateLoadKind::Bending, t, hr, layers_for(t / 2, hr), 0.7);
      // W_peak's transition (peak_energy_density.h "Thick plates") read at the round's radius r …
      const double phi = thick_round_transition(x);
      const double rule = (1 - phi) * kb.k + phi * km.k;
      // … and at the star's own size s = 1, as W_peak reads it.
      const double phi_s = thick_round_transition(2.0 / t);
      const double rule_s = (1 - phi_s) * kb.k + phi_s * km.k;
      std::printf("| %.2f | %.3f | %.3f | %.3f | %+.1f%% | %.3f | %+.1f%% | %d | %.1f |%s\n", x, c.k, c.k_any_z, rule,
                  100 * (rule / c.k - 1), rule_s, 100 * (rule_s / c.k - 1), c.unknowns, c.seconds,
                  c.at_focus ? "" : " (peak not at the focus tip)");
      std::fflush(stdout);
    }
  }

  // The circle, a = 1, against Roark and against the rule with its own thin factors.
  const auto circle = [](PlateLoadKind kind, double t, int layers, double ratio) {
    return solve_solid_plate(circle_plate(kind, t, 16.0, 1.0 / 12, layers, ratio));
  };
  const double km = circle(PlateLoadKind::Membrane, 0.25, 1, 1.0).k;
  const double kb = circle(PlateLoadKind::Bending, 0.25, 2, 1.0).k;
  std::printf("\ncircle: k_m %.3f, k_b,thin (x = 8) %.3f (Roark %.3f)\n", km, kb, roark_bending(8));
  std::printf("| x = 2a/t | k_3D | largest at any z | Roark | rule | rule's error |\n");
  for (double x : {2.0, 1.0, 0.5, 0.25}) {
    const double t = 2.0 / x;
    const SolidPlateResult c = circle(PlateLoadKind::Bending, t, layers_for(t / 2, 1.0 / 12), 0.7);
    const double phi = thick_round_transition(x);
    const double rule = (1 - phi) * kb + phi * km;
    std::printf("| %.2f | %.3f | %.3f | %.3f | %.3f | %+.1f%% |\n", x, c.k, c.peak_sigma_tt_any_z / c.nominal,
                roark_bending(x), rule, 100 * (rule / c.k - 1));
    std::fflush(stdout);
  }
}

// Measurement (not a test): the star's rounds sharper and its plate thicker, towards the chair's
// (0.5 mm rounds on stars of 3.8–20.8 mm in 12 mm: r/s = 0.024–0.13, 2s/t = 0.63–3.5), against the
// rule by 2s/t. 12 and 6 rim edges per round radius at r = 1/16 and 1/32 (the same absolute rim
// edge, s/192), layers as above (at most 12 over the half thickness). 6 min, this build:
//   r = s/16: k_m 9.161, k_b,thin 3.898; 2s/t = 2, 1, 0.5: k_3D 5.070, 5.463, 5.893 (largest at
//   any z 5.711, 6.541, 7.412), the rule −2.7%, +7.6%, +17.6%;
//   r = s/32: k_m 12.549, k_b,thin 4.738; k_3D 6.623, 7.124, 7.762 (7.948, 9.045, 10.229), the
//   rule −5.3%, +7.7%, +19.1%.
TEST(SolidPlate, DISABLED_SharperRoundsInThickerPlates) {
  for (const double r_tool : {1.0 / 16, 1.0 / 32}) {
    const auto [hole, tip_at] = turned_star(r_tool, 0.0);
    const double hr = 1.0 / 192;
    const StarCase km = star_case(hole, tip_at, PlateLoadKind::Membrane, r_tool / 4, hr, 1, 1.0);
    const StarCase kb = star_case(hole, tip_at, PlateLoadKind::Bending, r_tool / 4, hr, 2, 1.0);
    std::printf("\nstar, r = s/%.0f, rim edge r/%.0f: k_m %.3f, k_b,thin (2r/t = 8) %.3f\n", 1 / r_tool, r_tool / hr,
                km.k, kb.k);
    std::printf("| 2s/t | 2r/t | k_3D | largest at any z | rule by 2s/t | its error | unknowns | seconds |\n");
    for (const double xs : {2.0, 1.0, 0.5}) {
      const double t = 2.0 / xs;
      const StarCase c = star_case(hole, tip_at, PlateLoadKind::Bending, t, hr, layers_for(t / 2, hr), 0.7);
      const double phi = thick_round_transition(xs);
      const double rule = (1 - phi) * kb.k + phi * km.k;
      std::printf("| %.2f | %.3f | %.3f | %.3f | %.3f | %+.1f%% | %d | %.1f |%s\n", xs, 2 * r_tool / t, c.k,
                  c.k_any_z, rule, 100 * (rule / c.k - 1), c.unknowns, c.seconds,
                  c.at_focus ? "" : " (peak not at the focus tip)");
      std::fflush(stdout);
    }
  }
}

// Measurement (not a test): a long hole — an ellipse of semi-axes a = 1 across the load and b = 1/3
// along it (the built-in "ellipse" at aspect 3, its tips' radius ρ = b²/a = 1/9), K_m = 1 + 2a/b = 7
// in tension — in bending by plates 2a/t = 2, 1, 0.5 thick, against W_peak's thick-plate rule read at
// the bounding radius a (as W_peak reads every shape), at the half-width b, and at the tips' radius ρ.
// Which length the transition follows for a shape that is long and thin is what this measures.
// 3 min, this build: k_m 6.868 (Inglis 7), k_b,thin 3.154 at 2ρ/t = 8 (Kirchhoff's 3.364 at t → 0);
// 2a/t = 2, 1, 0.5: k_3D 4.062, 4.365, 4.688 (largest at any z 4.333, 4.925, 5.629); the rule by a
// −4.4%, +4.2%, +13.0%, by b +22.7%, +30.2%, +31.3%, by ρ +47.4%, +45.3%, +39.9% (303k–452k
// unknowns). The bounding radius is the length: as on the star, the factor nears the membrane's
// only once the plate is thick against the whole hole.
TEST(SolidPlate, DISABLED_EllipseAgainstTheRuleBySizeAndWidth) {
  const double a = 1.0, b = 1.0 / 3.0, rho = b * b / a;
  std::vector<Vec2> hole;
  for (int k = 0; k < 2048; ++k) {
    const double th = 2 * std::numbers::pi * k / 2048;
    hole.emplace_back(b * std::cos(th), a * std::sin(th));
  }
  const Vec2 tip(0.0, a);
  const double hr = rho / 12;
  const StarCase km = star_case(hole, tip, PlateLoadKind::Membrane, rho / 4, hr, 1, 1.0);
  const StarCase kb = star_case(hole, tip, PlateLoadKind::Bending, rho / 4, hr, 2, 1.0);
  std::printf("\nellipse a/b = 3, rim edge rho/12: k_m %.3f (Inglis 7), k_b,thin (2 rho/t = 8) %.3f (Kirchhoff %.3f)\n",
              km.k, kb.k, 1 + 2 * (1 + 0.3) / (3 + 0.3) * a / b);
  std::printf("| 2a/t | k_3D | largest at any z | rule by a | error | rule by b | error | rule by rho | error | unknowns | s |\n");
  for (const double xa : {2.0, 1.0, 0.5}) {
    const double t = 2 * a / xa;
    const StarCase c = star_case(hole, tip, PlateLoadKind::Bending, t, hr, layers_for(t / 2, hr), 0.7);
    const auto rule = [&](double length) {
      const double phi = thick_round_transition(2 * length / t);
      return (1 - phi) * kb.k + phi * km.k;
    };
    std::printf("| %.2f | %.3f | %.3f | %.3f | %+.1f%% | %.3f | %+.1f%% | %.3f | %+.1f%% | %d | %.1f |%s\n", xa, c.k,
                c.k_any_z, rule(a), 100 * (rule(a) / c.k - 1), rule(b), 100 * (rule(b) / c.k - 1), rule(rho),
                100 * (rule(rho) / c.k - 1), c.unknowns, c.seconds, c.at_focus ? "" : " (peak not at the tip)");
    std::fflush(stdout);
  }
}

// Measurement (not a test): W_peak's thick-plate transition is Reissner's uniaxial one, applied to
// every state. A circular hole (a = 1) in the uniaxial, equibiaxial and pure-twist bending states, in
// plates 2a/t = 2, 1, 0.5 thick, against the rule with each state's own thin and membrane factors
// (the solid's, at 2a/t = 8 and in tension). 1.5 min, this build:
//   uniaxial   k_m 3.018, k_b,thin 1.848; k_3D 1.982, 2.106, 2.267; the rule +4.8%, +8.6%, +11.3%
//   equibiax.  k_m 2.049, k_b,thin 2.029; k_3D 2.043, 2.046, 2.048; the rule −0.5%, −0.4%, −0.3%
//   pure twist k_m 3.994, k_b,thin 1.676; k_3D 1.929, 2.178, 2.496 (any z 1.929, 2.196, 2.648); the
//              rule +10.5%, +17.0%, +20.7%
// The 3-D φ = (k_3D − k_b)/(k_m − k_b) is the same in the uniaxial state and the twist (0.115, 0.221,
// 0.359 against 0.109, 0.217, 0.354): the transition does not depend on the state; Roark's φ is higher.
TEST(SolidPlate, DISABLED_CircleInEveryBendingState) {
  struct State {
    const char* name;
    double xx, yy;
  };
  for (const State& st : {State{"uniaxial", 1.0, 0.0}, State{"equibiaxial", 1.0, 1.0}, State{"pure twist", 1.0, -1.0}}) {
    const auto solve = [&](PlateLoadKind kind, double t, int layers, double ratio) {
      SolidPlateInput in = circle_plate(kind, t, 16.0, 1.0 / 12, layers, ratio);
      in.load = {kind, st.xx, st.yy, 0.0};
      return solve_solid_plate(in);
    };
    const double km = solve(PlateLoadKind::Membrane, 0.25, 1, 1.0).k;
    const double kb = solve(PlateLoadKind::Bending, 0.25, 2, 1.0).k;
    std::printf("\ncircle, %s: k_m %.3f, k_b,thin (2a/t = 8) %.3f\n", st.name, km, kb);
    std::printf("| 2a/t | k_3D | largest at any z | rule | error |\n");
    for (const double x : {2.0, 1.0, 0.5}) {
      const double t = 2.0 / x;
      const SolidPlateResult c = solve(PlateLoadKind::Bending, t, layers_for(t / 2, 1.0 / 12), 0.7);
      const double phi = thick_round_transition(x);
      const double rule = (1 - phi) * kb + phi * km;
      std::printf("| %.2f | %.3f | %.3f | %.3f | %+.1f%% |\n", x, c.k, c.peak_sigma_tt_any_z / c.nominal, rule,
                  100 * (rule / c.k - 1));
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace cutwork::solvers

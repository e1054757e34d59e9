// Plate and beam theory at α = 1 and small loads (linear regime), against closed forms of
// Kirchhoff plate theory (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells): the default
// shape-operator bending for clamped square and circular plates, an annular plate with a free hole,
// a cantilever strip and a free strip's anticlastic curvature; and the paper's hinge model where it
// is right (clamped plates) and where it is not (its Poisson coupling).
#include <cmath>
#include <numbers>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "solvers/equilibrium/equilibrium_solver.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

Material plate_material(double nu) {
  Material m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = nu;
  m.thickness = 0.01;
  m.density = 0;
  return m;
}

double bending_stiffness(const Material& m) {
  return m.youngs_modulus * std::pow(m.thickness, 3) / (12 * (1 - m.poisson_ratio * m.poisson_ratio));
}

MechanicsSettings with_bending(BendingModel b) {
  MechanicsSettings m;
  m.bending = b;
  return m;
}

/// Equilibrium displacements (#V×3) of `mesh` with the given clamped vertices (fixed too) and forces.
RowMatX3d solve_displacements(const SurfaceMesh& mesh, const std::vector<bool>& clamped, const RowMatX3d& forces,
                              const Material& mat, BendingModel bending) {
  LoadCase lc;
  lc.clamped = clamped;
  lc.fixed = clamped;
  lc.forces = forces;
  const ShellModel model(mesh, mat, lc, with_bending(bending));
  EquilibriumSolver solver(model);
  solver.solve(Eigen::VectorXd::Ones(mesh.num_faces()));
  return solver.displacements();
}

/// Relative errors of a refinement sequence, printed as a table; checks that the error falls with
/// every refinement and ends within `tolerance`.
void expect_converges(const std::string& what, const std::vector<std::string>& rows,
                      const std::vector<double>& errors, double tolerance) {
  std::string table = what + "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) table += rows[i] + fmt::format("   rel.error {:+.4f}\n", errors[i]);
  std::cout << table;
  for (std::size_t i = 1; i < errors.size(); ++i) EXPECT_LT(std::abs(errors[i]), std::abs(errors[i - 1])) << table;
  EXPECT_LE(std::abs(errors.back()), tolerance) << table;
}

// ---- clamped square plate -----------------------------------------------------------------------

/// Centre deflection of a clamped a×a plate under uniform pressure q on an nx-segment mesh.
double clamped_plate_deflection(int nx, double a, double q, const Material& mat, BendingModel bending) {
  const SurfaceMesh mesh = test::equilateral_rectangle(a, a, nx);
  const RowMatX3d u = solve_displacements(mesh, mesh.is_boundary_vertex(),
                                          test::pressure_forces(mesh, q, Vec3(0, 0, -1)), mat, bending);
  return -u.col(2).minCoeff();
}

TEST(PlateTheory, ClampedSquarePlateUnderPressureMatchesKirchhoff) {
  const Material mat = plate_material(0.3);
  const double a = 1.0, q = 1.0;
  // w_max = 0.00126 q a⁴ / D (Table 35; the series gives 0.0012653).
  const double exact = 0.0012653 * q * std::pow(a, 4) / bending_stiffness(mat);
  std::vector<std::string> rows;
  std::vector<double> errors;
  for (int nx : {8, 16, 32}) {
    const double w = clamped_plate_deflection(nx, a, q, mat, BendingModel::ShapeOperator);
    errors.push_back((w - exact) / exact);
    rows.push_back(fmt::format("  nx {:3d}   w_max {:.6e}", nx, w));
  }
  expect_converges(fmt::format("clamped square plate (shape operator), Kirchhoff w_max = {:.6e} m", exact), rows,
                   errors, 0.02);
}

TEST(PlateTheory, HingeModelIsRightForClampedSquarePlate) {
  // The Gaussian-curvature term integrates to zero on a clamped plate, so the hinges' wrong Poisson
  // coupling does not show: within 0.5% of Kirchhoff at nx = 64 (+6%, +1%, −0.2%, −0.3%).
  const Material mat = plate_material(0.3);
  const double exact = 0.0012653 / bending_stiffness(mat);
  const double w = clamped_plate_deflection(64, 1.0, 1.0, mat, BendingModel::Hinge);
  EXPECT_LE(std::abs(w - exact) / exact, 0.005);
}

// ---- clamped circular plate and annular plate with a free hole ---------------------------------

/// Kirchhoff's axisymmetric solution w(r) = q r⁴/(64D) + C1 + C2 r² + C3 ln r + C4 r² ln r of an annular
/// plate b ≤ r ≤ a under uniform pressure q, clamped at r = a (w = w' = 0) and free at r = b
/// (M_r = 0 and Q_r = 0; the latter fixes C4 = −q b²/(8D)); b = 0 is the clamped disc (C3 = C4 = 0).
struct AnnularPlate {
  double a, b, q, D, nu;
  Eigen::Vector4d C = Eigen::Vector4d::Zero();

  AnnularPlate(double a_, double b_, double q_, double D_, double nu_) : a(a_), b(b_), q(q_), D(D_), nu(nu_) {
    if (b == 0) {
      C[1] = -q * a * a / (32 * D);  // w'(a) = 0
      C[0] = -q * std::pow(a, 4) / (64 * D) - C[1] * a * a;
      return;
    }
    C[3] = -q * b * b / (8 * D);
    // Unknowns C1, C2, C3: w(a) = 0, w'(a) = 0, w''(b) + ν w'(b)/b = 0.
    Eigen::Matrix3d M;
    Eigen::Vector3d rhs;
    M << 1, a * a, std::log(a), 0, 2 * a, 1 / a, 0, 2 + 2 * nu, -(1 - nu) / (b * b);
    rhs << -(q * std::pow(a, 4) / (64 * D) + C[3] * a * a * std::log(a)),
        -(q * std::pow(a, 3) / (16 * D) + C[3] * (2 * a * std::log(a) + a)),
        -(3 * q * b * b / (16 * D) + C[3] * (2 * std::log(b) + 3) +
          nu * (q * b * b / (16 * D) + C[3] * (2 * std::log(b) + 1)));
    const Eigen::Vector3d c = M.fullPivLu().solve(rhs);
    C.head<3>() = c;
  }
  double w(double r) const {
    double v = q * std::pow(r, 4) / (64 * D) + C[0] + C[1] * r * r;
    if (b > 0) v += C[2] * std::log(r) + C[3] * r * r * std::log(r);
    return v;
  }
  /// Work of the load ∫ q w dA = 2π q ∫_b^a w r dr (Gauss–Legendre on 200 panels: exact to round-off).
  double compliance() const {
    const double g[2] = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
    double s = 0;
    const int n = 2000;
    for (int i = 0; i < n; ++i) {
      const double r0 = b + (a - b) * i / n, r1 = b + (a - b) * (i + 1) / n;
      for (double t : g) {
        const double r = 0.5 * (r0 + r1) + 0.5 * (r1 - r0) * t;
        s += 0.5 * (r1 - r0) * w(r) * r;
      }
    }
    return 2 * std::numbers::pi * q * s;
  }
};

struct PlateResult {
  double w_inner;     ///< mean deflection of the innermost ring (the centre for a disc), m
  double compliance;  ///< fᵀu, J
};

PlateResult solve_annulus(double b, double a, double h, double q, const Material& mat) {
  const SurfaceMesh mesh = test::annulus(b, a, h);
  std::vector<bool> rim(mesh.num_vertices(), false);
  for (int v = 0; v < mesh.num_vertices(); ++v) rim[v] = mesh.vertices().row(v).norm() > a - 1e-9;
  const RowMatX3d f = test::pressure_forces(mesh, q, Vec3(0, 0, -1));
  const RowMatX3d u = solve_displacements(mesh, rim, f, mat, BendingModel::ShapeOperator);
  PlateResult r{0, 0};
  int n = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (mesh.vertices().row(v).norm() < b + 1e-9) {
      r.w_inner += -u(v, 2);
      ++n;
    }
  }
  r.compliance = f.cwiseProduct(u).sum();
  r.w_inner /= n;
  return r;
}

TEST(PlateTheory, ClampedCircularPlateUnderPressureMatchesKirchhoff) {
  const Material mat = plate_material(0.3);
  const double a = 1.0, q = 1.0;
  const AnnularPlate exact(a, 0.0, q, bending_stiffness(mat), 0.3);
  ASSERT_NEAR(exact.w(0), q / (64 * bending_stiffness(mat)), 1e-15);  // w0 = q a⁴/(64 D)
  std::vector<std::string> rows;
  std::vector<double> w_err, c_err;
  for (double h : {a / 12, a / 24, a / 48}) {
    const PlateResult r = solve_annulus(0.0, a, h, q, mat);
    w_err.push_back((r.w_inner - exact.w(0)) / exact.w(0));
    c_err.push_back((r.compliance - exact.compliance()) / exact.compliance());
    rows.push_back(fmt::format("  h {:.4f}   w0 {:.6e}   compliance {:.6e} ({:+.4f})", h, r.w_inner, r.compliance,
                               c_err.back()));
  }
  expect_converges(fmt::format("clamped disc (shape operator), Kirchhoff w0 = {:.6e} m", exact.w(0)), rows, w_err,
                   0.02);
  EXPECT_LE(std::abs(c_err.back()), 0.02);
}

// (No simply supported disc: a pinned polygonal rim does not converge to the curved simply supported
// plate in Kirchhoff theory — Babuška's paradox — so Timoshenko's circle is not the limit of any
// mesh; measured here: +0.81%, +0.17%, −0.25% at h = a/12, a/24, a/48, drifting away.)

TEST(PlateTheory, AnnularPlateWithFreeHoleMatchesKirchhoffForTwoPoissonRatios) {
  // The free hole edge is where the Poisson coupling shows (the hinge model behaves as ν = −1/3
  // there, hinge_energy.h): deflection of the hole's edge and compliance against the exact
  // axisymmetric solution, for ν = 0.25 and 0.45.
  const double a = 1.0, b = 0.3, q = 1.0;
  for (double nu : {0.25, 0.45}) {
    const Material mat = plate_material(nu);
    const AnnularPlate exact(a, b, q, bending_stiffness(mat), nu);
    std::vector<std::string> rows;
    std::vector<double> w_err, c_err;
    for (double h : {a / 8, a / 16, a / 32}) {
      const PlateResult r = solve_annulus(b, a, h, q, mat);
      w_err.push_back((r.w_inner - exact.w(b)) / exact.w(b));
      c_err.push_back((r.compliance - exact.compliance()) / exact.compliance());
      rows.push_back(fmt::format("  h {:.4f}   w(b) {:.6e}   compliance {:.6e} ({:+.4f})", h, r.w_inner,
                                 r.compliance, c_err.back()));
    }
    expect_converges(fmt::format("annulus b/a = {}, free hole, nu = {}: Kirchhoff w(b) = {:.6e} m", b / a, nu,
                                 exact.w(b)),
                     rows, w_err, 0.02);
    EXPECT_LE(std::abs(c_err.back()), 0.02);
  }
}

// ---- cantilever strip and anticlastic curvature -------------------------------------------------

/// Cantilever strip of length L clamped at x = 0 under a total tip load P (−z), on an exactly
/// equilateral mesh with nx segments along the length and ny rows across; returns displacements.
struct Strip {
  SurfaceMesh mesh;
  RowMatX3d u;
  double width;
};

Strip cantilever_strip(double L, int nx, int ny, double P, const Material& mat, BendingModel bending) {
  const double b = ny * std::sqrt(3.0) / 2.0 * L / nx;
  Strip s{test::equilateral_rectangle(L, b, nx, ny), {}, b};
  std::vector<bool> clamped(s.mesh.num_vertices(), false);
  for (int v : test::select_vertices(s.mesh, [](const Vec3& p) { return p.x() < 1e-9; })) clamped[v] = true;
  RowMatX3d f = RowMatX3d::Zero(s.mesh.num_vertices(), 3);
  const auto tip = test::select_vertices(s.mesh, [&](const Vec3& p) { return p.x() > L - 1e-9; });
  for (int v : tip) f(v, 2) = -P / tip.size();
  s.u = solve_displacements(s.mesh, clamped, f, mat, bending);
  return s;
}

double tip_deflection(const Strip& s, double L) {
  const auto tip = test::select_vertices(s.mesh, [&](const Vec3& p) { return p.x() > L - 1e-9; });
  double w = 0;
  for (int v : tip) w += -s.u(v, 2) / tip.size();
  return w;
}

/// Euler–Bernoulli tip deflection P L³ / (3 E I), I = b h³/12.
double euler_bernoulli(double L, double b, double P, const Material& mat) {
  const double I = b * std::pow(mat.thickness, 3) / 12;
  return P * L * L * L / (3 * mat.youngs_modulus * I);
}

TEST(PlateTheory, CantileverStripUnderTipLoadMatchesBeamTheory) {
  // A narrow strip (L/b ≈ 23) is a beam: its anticlastic curvature is free, so its stiffness is E I
  // for any ν (a plate's D b only within ~b of the clamp, which moves the tip by ≪ 1%).
  const Material mat = plate_material(0.3);
  const double L = 1.0, P = 1e-3;  // w_tip/L ≈ 1e-3: linear regime
  std::vector<std::string> rows;
  std::vector<double> errors;
  for (int nx : {20, 40, 80}) {
    const int ny = nx / 20;
    const Strip s = cantilever_strip(L, nx, ny, P, mat, BendingModel::ShapeOperator);
    const double exact = euler_bernoulli(L, s.width, P, mat);
    errors.push_back((tip_deflection(s, L) - exact) / exact);
    rows.push_back(fmt::format("  nx {:3d} ny {:2d}   w_tip {:.6e}   (Euler-Bernoulli {:.6e})", nx, ny,
                               tip_deflection(s, L), exact));
  }
  expect_converges("cantilever strip (shape operator), nu = 0.3", rows, errors, 0.02);
}

/// Second derivatives (w_xx, w_yy) of the deflection at (x0, y0), from a least-squares cubic fit over
/// the vertices within `radius`.
Vec2 curvatures_at(const Strip& s, double x0, double y0, double radius) {
  std::vector<int> vs = test::select_vertices(
      s.mesh, [&](const Vec3& p) { return std::abs(p.x() - x0) < radius && std::abs(p.y() - y0) < radius; });
  Eigen::MatrixXd A(vs.size(), 10);
  Eigen::VectorXd w(vs.size());
  for (std::size_t i = 0; i < vs.size(); ++i) {
    const double x = s.mesh.vertices()(vs[i], 0) - x0, y = s.mesh.vertices()(vs[i], 1) - y0;
    A.row(i) << 1, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y;
    w[i] = s.u(vs[i], 2);
  }
  const Eigen::VectorXd c = A.colPivHouseholderQr().solve(w);
  return Vec2(2 * c[3], 2 * c[5]);
}

TEST(PlateTheory, FreeStripBendsAnticlasticallyWithPoissonsRatio) {
  // Away from the clamp a narrow strip carries M_y = 0, so Kirchhoff gives w_yy = −ν w_xx: the
  // hinge model gives −0.33 to −0.36 for ν = 0.4 (the wrong way); the shape operator must give ν.
  const double L = 1.0, P = 1e-4;
  for (double nu : {0.2, 0.4}) {
    const Material mat = plate_material(nu);
    const int nx = 60, ny = 8;
    const Strip s = cantilever_strip(L, nx, ny, P, mat, BendingModel::ShapeOperator);
    const Vec2 k = curvatures_at(s, 0.5 * L, 0.5 * s.width, 0.6 * s.width);
    const double ratio = -k[1] / k[0];
    std::cout << fmt::format("free strip, nu = {}: -w_yy/w_xx = {:.4f}\n", nu, ratio);
    EXPECT_NEAR(ratio, nu, 0.05 * nu);
  }
}

TEST(PlateTheory, HingeStripStiffnessShowsItsPoissonCoupling) {
  // With ν = 0 a free strip should bend with E I = D b, but the hinges let it curl anticlastically as
  // if ν = −1/3 (hinge_energy.h), lowering its stiffness to (1 − 1/9) D b: the tip deflects 9/8 of
  // Euler–Bernoulli. (A clamped plate has no such error: the Gaussian-curvature term integrates to
  // zero there.)
  const Material mat = plate_material(0.0);
  const double L = 1.0, P = 1e-2;
  const Strip s = cantilever_strip(L, 80, 8, P, mat, BendingModel::Hinge);
  const double ratio = tip_deflection(s, L) / euler_bernoulli(L, s.width, P, mat);
  std::cout << "hinge cantilever strip, nu = 0: w_tip / w_Euler-Bernoulli = " << ratio << " (expected 9/8)\n";
  EXPECT_NEAR(ratio, 9.0 / 8.0, 0.04);
}

}  // namespace
}  // namespace cutwork::solvers

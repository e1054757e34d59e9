// Per-element energies against central differences at random deformed states with random fill
// ratios: gradient vs energy, Hessian vs gradient, fill-ratio partials vs energy and gradient.
#include <numbers>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "solvers/shell/hinge_energy.h"
#include "solvers/shell/membrane_energy.h"
#include "tests/solvers/support/finite_difference.h"

namespace cutwork::solvers {
namespace {

using test::check_gradient;
using test::check_jacobian;

constexpr double kTolerance = 1e-6;
constexpr double kMu = 1.3e3, kLambda = 0.7e3;  // N/m

Eigen::VectorXd random_vector(std::mt19937& rng, int n, double scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = scale * u(rng);
  return v;
}

double random_alpha(std::mt19937& rng) {
  // Log-uniform over [1e-4, 1]: the fill kernel's full range.
  std::uniform_real_distribution<double> u(std::log(1e-4), 0.0);
  return std::exp(u(rng));
}

struct RandomTriangle {
  Vec9 rest, deformed;
};

RandomTriangle random_triangle(std::mt19937& rng) {
  for (;;) {
    RandomTriangle t;
    t.rest = random_vector(rng, 9, 1.0);
    const Vec3 e1 = t.rest.segment<3>(3) - t.rest.segment<3>(0);
    const Vec3 e2 = t.rest.segment<3>(6) - t.rest.segment<3>(0);
    const double area = 0.5 * e1.cross(e2).norm();
    if (area < 0.2) continue;  // avoid slivers: the check is about the maths, not conditioning
    // A large deformation: rotation-free stretch/compression of ~30 % plus translation.
    t.deformed = t.rest + random_vector(rng, 9, 0.3);
    return t;
  }
}

TEST(MembraneEnergy, GradientAndHessianMatchCentralDifferences) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 25; ++trial) {
    const RandomTriangle t = random_triangle(rng);
    const MembraneRest rest = membrane_rest(t.rest.segment<3>(0), t.rest.segment<3>(3), t.rest.segment<3>(6));
    const double alpha = random_alpha(rng);
    auto energy = [&](const Eigen::VectorXd& x) { return membrane_energy(x, rest, kMu, kLambda, alpha); };
    auto gradient = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd {
      return membrane_gradient(x, rest, kMu, kLambda, alpha);
    };
    const Eigen::VectorXd x = t.deformed;
    const auto cg = check_gradient(energy, x, gradient(x), 1.0);
    EXPECT_LE(cg.best, kTolerance) << "membrane gradient, trial " << trial << "\n" << cg.table();
    const Mat9 h = membrane_hessian(t.deformed, rest, kMu, kLambda, alpha);
    const auto ch = check_jacobian(gradient, x, h, 1.0);
    EXPECT_LE(ch.best, kTolerance) << "membrane Hessian, trial " << trial << "\n" << ch.table();
    EXPECT_LE((h - h.transpose()).norm(), 1e-12 * h.norm());

    // Fill-ratio partials: the energy is linear in α.
    auto energy_of_alpha = [&](const Eigen::VectorXd& a) { return membrane_energy(x, rest, kMu, kLambda, a[0]); };
    const Eigen::VectorXd a = Eigen::VectorXd::Constant(1, alpha);
    const double dW_dalpha = membrane_energy(x, rest, kMu, kLambda, 1.0);
    const auto ca = check_gradient(energy_of_alpha, a, Eigen::VectorXd::Constant(1, dW_dalpha), alpha);
    EXPECT_LE(ca.best, kTolerance) << ca.table();
    auto gradient_of_alpha = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
      return membrane_gradient(x, rest, kMu, kLambda, b[0]);
    };
    const Eigen::MatrixXd dg_dalpha = membrane_gradient(x, rest, kMu, kLambda, 1.0);
    const auto cga = check_jacobian(gradient_of_alpha, a, dg_dalpha, alpha);
    EXPECT_LE(cga.best, kTolerance) << cga.table();
  }
}

// The membrane with a general constitutive matrix (the square lattice's anisotropic part): with
// the Lamé form's matrix it is that form (energy, gradient, Hessian to round-off); with an
// indefinite anisotropic matrix plus a random symmetric one its gradient and Hessian are its
// energy's derivatives.
TEST(MembraneEnergy, GeneralConstitutiveMatrixIsTheLameFormAndItsDerivativesAreExact) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi);
  for (int trial = 0; trial < 25; ++trial) {
    const RandomTriangle t = random_triangle(rng);
    const MembraneRest rest = membrane_rest(t.rest.segment<3>(0), t.rest.segment<3>(3), t.rest.segment<3>(6));
    const double alpha = random_alpha(rng);
    const Vec9 x = t.deformed;
    double e_lame = 0, e_general = 0;
    Vec9 g_lame, g_general;
    Mat9 h_lame, h_general;
    membrane_energy_gradient_hessian(x, rest, kMu, kLambda, alpha, &e_lame, &g_lame, &h_lame);
    membrane_energy_gradient_hessian(x, rest, membrane_constitutive(kMu, kLambda), alpha, &e_general, &g_general,
                                     &h_general);
    EXPECT_NEAR(e_general, e_lame, 1e-12 * std::abs(e_lame));
    EXPECT_LE((g_general - g_lame).norm(), 1e-12 * g_lame.norm());
    EXPECT_LE((h_general - h_lame).norm(), 1e-12 * h_lame.norm());

    const double phi = angle(rng), c = std::cos(4 * phi), sn = std::sin(4 * phi);
    Eigen::Matrix3d C;
    C << c, -c, sn, -c, c, -sn, sn, -sn, -c;
    const Eigen::Matrix3d R = Eigen::Matrix3d::Random();
    C = kMu * C + 100.0 * (R + R.transpose());
    auto energy = [&](const Eigen::VectorXd& y) {
      double e = 0;
      membrane_energy_gradient_hessian(y, rest, C, alpha, &e, nullptr, nullptr);
      return e;
    };
    auto gradient = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd {
      Vec9 g;
      membrane_energy_gradient_hessian(y, rest, C, alpha, nullptr, &g, nullptr);
      return g;
    };
    Mat9 h;
    membrane_energy_gradient_hessian(x, rest, C, alpha, nullptr, nullptr, &h);
    const auto cg = check_gradient(energy, x, gradient(x), 1.0);
    EXPECT_LE(cg.best, kTolerance) << "general membrane gradient, trial " << trial << "\n" << cg.table();
    const auto ch = check_jacobian(gradient, x, h, 1.0);
    EXPECT_LE(ch.best, kTolerance) << "general membrane Hessian, trial " << trial << "\n" << ch.table();
    EXPECT_LE((h - h.transpose()).norm(), 1e-12 * h.norm());
  }
}

/// A random hinge: two triangles on a common edge with a random rest fold, then deformed.
struct RandomHinge {
  Vec12 rest, deformed;
};

bool well_shaped(const Vec12& x) {
  const Vec3 x0 = x.segment<3>(0), x1 = x.segment<3>(3), x2 = x.segment<3>(6), x3 = x.segment<3>(9);
  const Vec3 e = x1 - x0;
  const double h0 = e.cross(x2 - x0).norm() / e.norm();
  const double h1 = e.cross(x3 - x1).norm() / e.norm();
  return e.norm() > 0.3 && h0 > 0.3 && h1 > 0.3 && std::abs(dihedral_angle(x)) < 2.5;
}

RandomHinge random_hinge(std::mt19937& rng) {
  for (;;) {
    RandomHinge h;
    h.rest << 0, 0, 0, 1, 0, 0, 0.4, 0.9, 0, 0.6, -0.8, 0;
    h.rest += random_vector(rng, 12, 0.25);
    h.deformed = h.rest + random_vector(rng, 12, 0.3);
    if (well_shaped(h.rest) && well_shaped(h.deformed)) return h;
  }
}

TEST(HingeEnergy, DihedralAngleSignAndValue) {
  // Flat: 0. Wings folded away from the normal side (+z): positive, by the documented convention.
  Vec12 x;
  x << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0;
  EXPECT_NEAR(dihedral_angle(x), 0.0, 1e-15);
  const double phi = 0.3;
  x.segment<3>(6) << 0.5, std::cos(phi), -std::sin(phi);
  x.segment<3>(9) << 0.5, -std::cos(phi), -std::sin(phi);
  EXPECT_NEAR(dihedral_angle(x), 2 * phi, 1e-14);
  x.segment<3>(6) << 0.5, std::cos(phi), std::sin(phi);
  x.segment<3>(9) << 0.5, -std::cos(phi), std::sin(phi);
  EXPECT_NEAR(dihedral_angle(x), -2 * phi, 1e-14);
}

TEST(HingeEnergy, DihedralAngleDerivativesMatchCentralDifferences) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 25; ++trial) {
    const Vec12 x = random_hinge(rng).deformed;
    auto angle = [](const Eigen::VectorXd& y) { return dihedral_angle(y); };
    auto grad = [](const Eigen::VectorXd& y) -> Eigen::VectorXd { return dihedral_angle_gradient(y); };
    const auto cg = check_gradient(angle, x, dihedral_angle_gradient(x), 1.0);
    EXPECT_LE(cg.best, kTolerance) << "dθ/dx, trial " << trial << "\n" << cg.table();
    const Mat12 h = dihedral_angle_hessian(x);
    const auto ch = check_jacobian(grad, x, h, 1.0);
    EXPECT_LE(ch.best, kTolerance) << "d²θ/dx², trial " << trial << "\n" << ch.table();
  }
}

TEST(HingeEnergy, GradientHessianAndFillRatioPartialsMatchCentralDifferences) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 25; ++trial) {
    const RandomHinge rh = random_hinge(rng);
    HingeRest rest;
    rest.rest_angle = dihedral_angle(rh.rest);
    rest.stiffness = hinge_stiffness(0.02, 1.0, 0.3);
    const double ai = random_alpha(rng), aj = random_alpha(rng);
    const double s = std::sqrt(ai * aj);
    const Vec12 x = rh.deformed;
    auto energy = [&](const Eigen::VectorXd& y) { return hinge_energy(y, rest, s); };
    auto gradient = [&](const Eigen::VectorXd& y) -> Eigen::VectorXd { return hinge_gradient(y, rest, s); };
    const auto cg = check_gradient(energy, x, gradient(x), 1.0);
    EXPECT_LE(cg.best, kTolerance) << "hinge gradient, trial " << trial << "\n" << cg.table();
    const Mat12 h = hinge_hessian(x, rest, s);
    const auto ch = check_jacobian(gradient, x, h, 1.0);
    EXPECT_LE(ch.best, kTolerance) << "hinge Hessian, trial " << trial << "\n" << ch.table();

    // (10): W = √(α_i α_j) W_unit, so ∂W/∂α_i = W_unit √(α_j/α_i) / 2 (and likewise ∂g/∂α_i).
    auto energy_of_alpha = [&](const Eigen::VectorXd& a) { return hinge_energy(x, rest, std::sqrt(a[0] * a[1])); };
    Eigen::VectorXd a(2);
    a << ai, aj;
    const double unit = hinge_energy(x, rest, 1.0);
    Eigen::VectorXd dW(2);
    dW << 0.5 * unit * std::sqrt(aj / ai), 0.5 * unit * std::sqrt(ai / aj);
    const auto ca = check_gradient(energy_of_alpha, a, dW, std::min(ai, aj));
    EXPECT_LE(ca.best, kTolerance) << ca.table();
    auto gradient_of_alpha = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
      return hinge_gradient(x, rest, std::sqrt(b[0] * b[1]));
    };
    const Vec12 gu = hinge_gradient(x, rest, 1.0);
    Eigen::MatrixXd dg(12, 2);
    dg.col(0) = 0.5 * std::sqrt(aj / ai) * gu;
    dg.col(1) = 0.5 * std::sqrt(ai / aj) * gu;
    const auto cga = check_jacobian(gradient_of_alpha, a, dg, std::min(ai, aj));
    EXPECT_LE(cga.best, kTolerance) << cga.table();
  }
}

TEST(HingeEnergy, ZeroAtRestAndInvariantUnderRigidMotion) {
  std::mt19937 rng(14);
  const RandomHinge rh = random_hinge(rng);
  HingeRest rest{dihedral_angle(rh.rest), 1.0};
  EXPECT_NEAR(hinge_energy(rh.rest, rest, 1.0), 0.0, 1e-28);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  Vec12 moved;
  for (int k = 0; k < 4; ++k) moved.segment<3>(3 * k) = R * rh.deformed.segment<3>(3 * k) + Vec3(3, -1, 2);
  EXPECT_NEAR(hinge_energy(moved, rest, 1.0), hinge_energy(rh.deformed, rest, 1.0), 1e-12);
}

}  // namespace
}  // namespace cutwork::solvers

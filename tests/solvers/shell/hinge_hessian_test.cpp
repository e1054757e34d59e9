// The closed-form dihedral-angle Hessian against the forward-mode dual-number Jacobian of the
// closed-form gradient that it replaced (Eigen's AutoDiffScalar, kept here as the reference), on
// random hinges from nearly flat to nearly folded and with short and long hinge edges.
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <unsupported/Eigen/AutoDiff>

#include "solvers/shell/hinge_energy.h"

namespace cutwork::solvers {
namespace {

/// ∇θ, generic in the scalar (the formula of hinge_energy.cpp).
template <typename T>
Eigen::Matrix<T, 12, 1> generic_angle_gradient(const Eigen::Matrix<T, 12, 1>& x) {
  using V3 = Eigen::Matrix<T, 3, 1>;
  const V3 x0 = x.template segment<3>(0), x1 = x.template segment<3>(3);
  const V3 x2 = x.template segment<3>(6), x3 = x.template segment<3>(9);
  const V3 e = x1 - x0;
  const V3 n0 = e.cross(x2 - x0);
  const V3 n1 = (x0 - x1).cross(x3 - x1);
  const T l2 = e.squaredNorm();
  using std::sqrt;
  const T l = sqrt(l2);
  const V3 g2 = -(l / n0.squaredNorm()) * n0;
  const V3 g3 = -(l / n1.squaredNorm()) * n1;
  const T t0 = (x2 - x0).dot(e) / l2;
  const T t1 = (x3 - x0).dot(e) / l2;
  Eigen::Matrix<T, 12, 1> g;
  g.template segment<3>(0) = -(T(1) - t0) * g2 - (T(1) - t1) * g3;
  g.template segment<3>(3) = -t0 * g2 - t1 * g3;
  g.template segment<3>(6) = g2;
  g.template segment<3>(9) = g3;
  return g;
}

Mat12 dual_number_hessian(const Vec12& x) {
  using Dual = Eigen::AutoDiffScalar<Vec12>;
  Eigen::Matrix<Dual, 12, 1> xd;
  for (int i = 0; i < 12; ++i) xd[i] = Dual(x[i], 12, i);
  const Eigen::Matrix<Dual, 12, 1> g = generic_angle_gradient<Dual>(xd);
  Mat12 h;
  for (int i = 0; i < 12; ++i) h.row(i) = g[i].derivatives().transpose();
  return 0.5 * (h + h.transpose());
}

TEST(HingeHessian, ClosedFormEqualsTheDualNumberJacobian) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> u(-1, 1), angle(-3.0, 3.0), length(std::log(1e-3), std::log(10.0));
  for (int trial = 0; trial < 200; ++trial) {
    // Edge along x of length L, wings at random fold angles and lengths, then a random rigid move.
    const double L = std::exp(length(rng));
    const double phi0 = angle(rng), phi1 = angle(rng);
    const double w0 = L * (0.2 + std::abs(u(rng))), w1 = L * (0.2 + std::abs(u(rng)));
    Vec12 x;
    x << 0, 0, 0, L, 0, 0, L * (0.5 + 0.4 * u(rng)), w0 * std::cos(phi0), w0 * std::sin(phi0),
        L * (0.5 + 0.4 * u(rng)), -w1 * std::cos(phi1), w1 * std::sin(phi1);
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(angle(rng), Vec3(u(rng), u(rng), u(rng)).normalized()).toRotationMatrix();
    const Vec3 t(u(rng), u(rng), u(rng));
    for (int k = 0; k < 4; ++k) x.segment<3>(3 * k) = R * x.segment<3>(3 * k) + t;
    const Mat12 reference = dual_number_hessian(x);
    const Mat12 closed = dihedral_angle_hessian(x);
    EXPECT_LE((closed - reference).norm(), 1e-12 * reference.norm()) << "trial " << trial << ", edge " << L;
    EXPECT_LE((dihedral_angle_gradient(x) - generic_angle_gradient<double>(x)).norm(),
              1e-14 * generic_angle_gradient<double>(x).norm());
  }
}

}  // namespace
}  // namespace cutwork::solvers

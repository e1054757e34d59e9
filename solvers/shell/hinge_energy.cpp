#include "solvers/shell/hinge_energy.h"

#include <cmath>

#include <Eigen/Dense>
#include <unsupported/Eigen/AutoDiff>

namespace cutwork::solvers {

namespace {

/// The closed-form gradient of θ, generic in the scalar so that forward-mode dual numbers give its
/// exact Jacobian (the Hessian of θ).
template <typename T>
Eigen::Matrix<T, 12, 1> angle_gradient(const Eigen::Matrix<T, 12, 1>& x) {
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

}  // namespace

double hinge_stiffness(double bending_stiffness, double rest_edge_length, double hinge_area) {
  return bending_stiffness / 6.0 * rest_edge_length * rest_edge_length / hinge_area;
}

double dihedral_angle(const Vec12& x) {
  const Vec3 x0 = x.segment<3>(0), x1 = x.segment<3>(3), x2 = x.segment<3>(6), x3 = x.segment<3>(9);
  const Vec3 e = x1 - x0;
  const Vec3 n0 = e.cross(x2 - x0);
  const Vec3 n1 = (x0 - x1).cross(x3 - x1);
  return std::atan2(n0.cross(n1).dot(e) / e.norm(), n0.dot(n1));
}

Vec12 dihedral_angle_gradient(const Vec12& x) { return angle_gradient<double>(x); }

Mat12 dihedral_angle_hessian(const Vec12& x) {
  using Dual = Eigen::AutoDiffScalar<Vec12>;
  Eigen::Matrix<Dual, 12, 1> xd;
  for (int i = 0; i < 12; ++i) xd[i] = Dual(x[i], 12, i);
  const Eigen::Matrix<Dual, 12, 1> g = angle_gradient<Dual>(xd);
  Mat12 h;
  for (int i = 0; i < 12; ++i) h.row(i) = g[i].derivatives().transpose();
  // The Jacobian of an exact gradient is symmetric; symmetrise the last bits of rounding.
  return 0.5 * (h + h.transpose());
}

void hinge_energy_gradient_hessian(const Vec12& x, const HingeRest& rest, double s, double* energy,
                                   Vec12* gradient, Mat12* hessian) {
  const double d = dihedral_angle(x) - rest.rest_angle;
  const double k = s * rest.stiffness;
  if (energy) *energy = k * d * d;
  if (!gradient && !hessian) return;
  if (hessian) {
    using Dual = Eigen::AutoDiffScalar<Vec12>;
    Eigen::Matrix<Dual, 12, 1> xd;
    for (int i = 0; i < 12; ++i) xd[i] = Dual(x[i], 12, i);
    const Eigen::Matrix<Dual, 12, 1> gd = angle_gradient<Dual>(xd);
    Vec12 g;
    Mat12 jacobian;
    for (int i = 0; i < 12; ++i) {
      g[i] = gd[i].value();
      jacobian.row(i) = gd[i].derivatives().transpose();
    }
    *hessian = k * (2.0 * g * g.transpose() + d * (jacobian + jacobian.transpose()));
    if (gradient) *gradient = 2.0 * k * d * g;
    return;
  }
  *gradient = 2.0 * k * d * angle_gradient<double>(x);
}

double hinge_energy(const Vec12& x, const HingeRest& rest, double s) {
  double e = 0;
  hinge_energy_gradient_hessian(x, rest, s, &e, nullptr, nullptr);
  return e;
}

Vec12 hinge_gradient(const Vec12& x, const HingeRest& rest, double s) {
  Vec12 g;
  hinge_energy_gradient_hessian(x, rest, s, nullptr, &g, nullptr);
  return g;
}

Mat12 hinge_hessian(const Vec12& x, const HingeRest& rest, double s) {
  Mat12 h;
  hinge_energy_gradient_hessian(x, rest, s, nullptr, nullptr, &h);
  return h;
}

}  // namespace cutwork::solvers

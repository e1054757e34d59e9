#include "solvers/shell/hinge_energy.h"

#include <cmath>

#include <Eigen/Dense>

namespace cutwork::solvers {

namespace {

using Mat3x12 = Eigen::Matrix<double, 3, 12>;
using Row12 = Eigen::Matrix<double, 1, 12>;

Eigen::Matrix3d cross_matrix(const Vec3& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// d(x_j − x_i)/dx as a 3×12 block row.
Mat3x12 difference_jacobian(int i, int j) {
  Mat3x12 d = Mat3x12::Zero();
  d.block<3, 3>(0, 3 * i) = -Eigen::Matrix3d::Identity();
  d.block<3, 3>(0, 3 * j) = Eigen::Matrix3d::Identity();
  return d;
}

/// ∇θ (and, when `jacobian` is given, its exact Jacobian ∂²θ/∂x², not yet symmetrised) in closed
/// form. With e = x1 − x0, n0 = e × (x2 − x0), n1 = (x0 − x1) × (x3 − x1), l = |e|:
///   g2 = −(l/|n0|²) n0,  g3 = −(l/|n1|²) n1,  t0 = (x2 − x0)·e / l²,  t1 = (x3 − x0)·e / l²,
///   ∇θ = (−(1 − t0) g2 − (1 − t1) g3,  −t0 g2 − t1 g3,  g2,  g3),
/// differentiated term by term with the chain rule (each vector's 3×12 Jacobian, each scalar's
/// gradient row).
Vec12 angle_gradient(const Vec12& x, Mat12* jacobian) {
  const Vec3 x0 = x.segment<3>(0), x1 = x.segment<3>(3), x2 = x.segment<3>(6), x3 = x.segment<3>(9);
  const Vec3 e = x1 - x0, a = x2 - x0, b = x3 - x1, c = x3 - x0;
  const Vec3 n0 = e.cross(a);
  const Vec3 n1 = (-e).cross(b);
  const double l2 = e.squaredNorm(), l = std::sqrt(l2);
  const double q0 = n0.squaredNorm(), q1 = n1.squaredNorm();
  const Vec3 g2 = -(l / q0) * n0;
  const Vec3 g3 = -(l / q1) * n1;
  const double t0 = a.dot(e) / l2, t1 = c.dot(e) / l2;
  Vec12 g;
  g.segment<3>(0) = -(1 - t0) * g2 - (1 - t1) * g3;
  g.segment<3>(3) = -t0 * g2 - t1 * g3;
  g.segment<3>(6) = g2;
  g.segment<3>(9) = g3;
  if (!jacobian) return g;

  const Mat3x12 E = difference_jacobian(0, 1), A = difference_jacobian(0, 2);
  const Mat3x12 B = difference_jacobian(1, 3), C = difference_jacobian(0, 3);
  const Mat3x12 N0 = -cross_matrix(a) * E + cross_matrix(e) * A;  // d(e × a)
  const Mat3x12 N1 = cross_matrix(b) * E - cross_matrix(e) * B;   // d(−e × b)
  const Row12 dl = e.transpose() * E / l, dl2 = 2.0 * e.transpose() * E;
  auto normal_term = [&](const Vec3& n, const Mat3x12& N, double q) {  // d(−(l/q) n)
    const Row12 dq = 2.0 * n.transpose() * N;
    const Row12 dc = dl / q - (l / (q * q)) * dq;
    return Mat3x12(-(n * dc + (l / q) * N));
  };
  const Mat3x12 G2 = normal_term(n0, N0, q0), G3 = normal_term(n1, N1, q1);
  const Row12 dt0 = (e.transpose() * A + a.transpose() * E) / l2 - (a.dot(e) / (l2 * l2)) * dl2;
  const Row12 dt1 = (e.transpose() * C + c.transpose() * E) / l2 - (c.dot(e) / (l2 * l2)) * dl2;
  Mat12& J = *jacobian;
  J.block<3, 12>(0, 0) = g2 * dt0 - (1 - t0) * G2 + g3 * dt1 - (1 - t1) * G3;
  J.block<3, 12>(3, 0) = -g2 * dt0 - t0 * G2 - g3 * dt1 - t1 * G3;
  J.block<3, 12>(6, 0) = G2;
  J.block<3, 12>(9, 0) = G3;
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

Vec12 dihedral_angle_gradient(const Vec12& x) { return angle_gradient(x, nullptr); }

Mat12 dihedral_angle_hessian(const Vec12& x) {
  Mat12 h;
  angle_gradient(x, &h);
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
    Mat12 jacobian;
    const Vec12 g = angle_gradient(x, &jacobian);
    *hessian = k * (2.0 * g * g.transpose() + d * (jacobian + jacobian.transpose()));
    if (gradient) *gradient = 2.0 * k * d * g;
    return;
  }
  *gradient = 2.0 * k * d * angle_gradient(x, nullptr);
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

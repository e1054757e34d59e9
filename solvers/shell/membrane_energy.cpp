#include "solvers/shell/membrane_energy.h"

#include <cmath>

#include <Eigen/Dense>

namespace cutwork::solvers {

namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;

/// Row vectors β_a (a = 0,1,2) with ∂F/∂x_{a,c} = e_c β_aᵀ: F = Ds B with Ds = [x1−x0, x2−x0].
void shape_rows(const Eigen::Matrix2d& B, Eigen::Vector2d beta[3]) {
  beta[1] = B.row(0).transpose();
  beta[2] = B.row(1).transpose();
  beta[0] = -(beta[1] + beta[2]);
}

}  // namespace

MembraneRest membrane_rest(const Vec3& X0, const Vec3& X1, const Vec3& X2) {
  const Vec3 e1 = X1 - X0;
  const Vec3 e2 = X2 - X0;
  const Vec3 n = e1.cross(e2);
  const Vec3 b1 = e1.normalized();
  const Vec3 b2 = n.normalized().cross(b1);
  Eigen::Matrix2d dm;
  dm << e1.dot(b1), e2.dot(b1), e1.dot(b2), e2.dot(b2);
  MembraneRest rest;
  rest.dm_inverse = dm.inverse();
  rest.area = 0.5 * n.norm();
  return rest;
}

Eigen::Matrix<double, 3, 2> membrane_deformation_gradient(const Vec9& x, const MembraneRest& rest) {
  Mat32 ds;
  ds.col(0) = x.segment<3>(3) - x.segment<3>(0);
  ds.col(1) = x.segment<3>(6) - x.segment<3>(0);
  return ds * rest.dm_inverse;
}

double membrane_energy_density(const Eigen::Matrix<double, 3, 2>& F, double mu, double lambda) {
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  const double tr = E.trace();
  return mu * E.squaredNorm() + 0.5 * lambda * tr * tr;
}

void membrane_energy_gradient_hessian(const Vec9& x, const MembraneRest& rest, double mu,
                                      double lambda, double alpha, double* energy, Vec9* gradient,
                                      Mat9* hessian) {
  const Mat32 F = membrane_deformation_gradient(x, rest);
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  const double tr = E.trace();
  const double scale = alpha * rest.area;
  if (energy) *energy = scale * (mu * E.squaredNorm() + 0.5 * lambda * tr * tr);
  if (!gradient && !hessian) return;

  // Second Piola–Kirchhoff stress S = ∂Ψ/∂E and first Piola–Kirchhoff P = F S (N/m).
  const Eigen::Matrix2d S = 2.0 * mu * E + lambda * tr * Eigen::Matrix2d::Identity();
  const Mat32 P = F * S;
  Eigen::Vector2d beta[3];
  shape_rows(rest.dm_inverse, beta);

  if (gradient) {
    for (int a = 0; a < 3; ++a) gradient->segment<3>(3 * a) = scale * (P * beta[a]);
  }
  if (!hessian) return;

  // H_(a,c),(b,d) = αA [ δ_cd β_bᵀ S β_a + (F dS β_a)_c ],  dS = 2μ dE + λ tr(dE) I,
  // dE = ½(β_b f_dᵀ + f_d β_bᵀ), f_d = Fᵀ e_d (row d of F). With u_a = F β_a this is, block by block,
  //   H_ab = αA [ (β_aᵀ S β_b) I + μ u_b u_aᵀ + μ (β_a·β_b) F Fᵀ + λ u_a u_bᵀ ]   (H_ba = H_abᵀ).
  const Eigen::Matrix3d FFt = F * F.transpose();
  Vec3 u[3];
  for (int a = 0; a < 3; ++a) u[a] = F * beta[a];
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      Eigen::Matrix3d blk = (mu * beta[a].dot(beta[b])) * FFt;
      blk.noalias() += mu * u[b] * u[a].transpose();
      blk.noalias() += lambda * u[a] * u[b].transpose();
      blk.diagonal().array() += beta[a].dot(S * beta[b]);
      hessian->block<3, 3>(3 * a, 3 * b) = scale * blk;
      if (b != a) hessian->block<3, 3>(3 * b, 3 * a) = scale * blk.transpose();
    }
  }
}

void membrane_energy_gradient_hessian(const Vec9& x, const MembraneRest& rest, const Eigen::Matrix3d& C,
                                      double scale, double* energy, Vec9* gradient, Mat9* hessian) {
  const Mat32 F = membrane_deformation_gradient(x, rest);
  const Eigen::Matrix2d E = 0.5 * (F.transpose() * F - Eigen::Matrix2d::Identity());
  const Vec3 eps(E(0, 0), E(1, 1), 2 * E(0, 1));
  const Vec3 sigma = C * eps;
  const double s = scale * rest.area;
  if (energy) *energy = 0.5 * s * eps.dot(sigma);
  if (!gradient && !hessian) return;
  Eigen::Matrix2d S;
  S << sigma[0], sigma[2], sigma[2], sigma[1];
  const Mat32 P = F * S;
  Eigen::Vector2d beta[3];
  shape_rows(rest.dm_inverse, beta);
  if (gradient)
    for (int a = 0; a < 3; ++a) gradient->segment<3>(3 * a) = s * (P * beta[a]);
  if (!hessian) return;
  Eigen::Matrix<double, 3, 2> G[3];
  Eigen::Matrix3d FGt[3];  // F G_aᵀ
  for (int a = 0; a < 3; ++a) {
    G[a] << beta[a].x(), 0, 0, beta[a].y(), beta[a].y(), beta[a].x();
    FGt[a] = F * G[a].transpose();
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      Eigen::Matrix3d blk = FGt[a] * C * FGt[b].transpose();
      blk.diagonal().array() += beta[a].dot(S * beta[b]);
      hessian->block<3, 3>(3 * a, 3 * b) = s * blk;
      if (b != a) hessian->block<3, 3>(3 * b, 3 * a) = s * blk.transpose();
    }
  }
}

Eigen::Matrix3d membrane_constitutive(double mu, double lambda) {
  Eigen::Matrix3d C;
  C << 2 * mu + lambda, lambda, 0, lambda, 2 * mu + lambda, 0, 0, 0, mu;
  return C;
}

double membrane_energy(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha) {
  double e = 0;
  membrane_energy_gradient_hessian(x, rest, mu, lambda, alpha, &e, nullptr, nullptr);
  return e;
}

Vec9 membrane_gradient(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha) {
  Vec9 g;
  membrane_energy_gradient_hessian(x, rest, mu, lambda, alpha, nullptr, &g, nullptr);
  return g;
}

Mat9 membrane_hessian(const Vec9& x, const MembraneRest& rest, double mu, double lambda, double alpha) {
  Mat9 h;
  membrane_energy_gradient_hessian(x, rest, mu, lambda, alpha, nullptr, nullptr, &h);
  return h;
}

}  // namespace cutwork::solvers

#include "solvers/objective/energy_density.h"

#include <cmath>

#include <tbb/parallel_for.h>

#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

/// Weight w of a hinge's unit energy in W_i of its face `side` (0 or 1): w = 3 Â_i s / (Â_i + Â_j)².
double hinge_weight(const ShellModel& model, const ShellHinge& h, const Eigen::VectorXd& alpha, int side) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const int i = h.face[side], j = h.face[1 - side];
  const double ai = alpha[i] * A[i], aj = alpha[j] * A[j];
  const double s = std::sqrt(alpha[i] * alpha[j]);
  return 3.0 * ai * s / ((ai + aj) * (ai + aj));
}

}  // namespace

Eigen::VectorXd energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  const Eigen::VectorXd& A = model.mesh().face_areas();
  Eigen::VectorXd W = unit.membrane.cwiseQuotient(A);
  for (std::size_t h = 0; h < model.hinges().size(); ++h) {
    const ShellHinge& sh = model.hinges()[h];
    for (int side = 0; side < 2; ++side) W[sh.face[side]] += hinge_weight(model, sh, alpha, side) * unit.hinge[h];
  }
  for (std::size_t c = 0; c < model.clamp_hinges().size(); ++c) {
    const int f = model.clamp_hinges()[c].face;
    W[f] += 3.0 * unit.clamp[c] / A[f];
  }
  return W;
}

void energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                        const Eigen::VectorXd& weights, RowMatX3d* d_positions, Eigen::VectorXd* d_alpha) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  const ShellStiffness& k = model.stiffness();

  if (d_alpha) {
    // Only the hinge weights depend on α; with T = Â_i + Â_j,
    //   ∂ln w_i/∂α_i = 3/(2α_i) − 2A_i/T,   ∂ln w_i/∂α_j = 1/(2α_j) − 2A_j/T.
    ElementEnergies unit;
    shell_energy(model, x, alpha, &unit);
    d_alpha->setZero(nf);
    for (int h = 0; h < nh; ++h) {
      const ShellHinge& sh = model.hinges()[h];
      const double T = alpha[sh.face[0]] * A[sh.face[0]] + alpha[sh.face[1]] * A[sh.face[1]];
      for (int side = 0; side < 2; ++side) {
        const int i = sh.face[side], j = sh.face[1 - side];
        const double cw = weights[i] * hinge_weight(model, sh, alpha, side) * unit.hinge[h];
        (*d_alpha)[i] += cw * (1.5 / alpha[i] - 2.0 * A[i] / T);
        (*d_alpha)[j] += cw * (0.5 / alpha[j] - 2.0 * A[j] / T);
      }
    }
  }
  if (!d_positions) return;

  // Σ_i c_i ∂W_i/∂x = Σ_elements ω_e ∇(unit energy of e), scattered colour by colour.
  const BlockAssembly& asmb = model.assembly();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(model.num_dofs());
  auto element = [&](int e) {
    if (e < nf) {
      Vec9 ge;
      membrane_energy_gradient_hessian(membrane_positions(model, x, e), model.membranes()[e], k.mu, k.lambda,
                                       weights[e] / A[e], nullptr, &ge, nullptr);
      asmb.scatter_vector<3>(e, ge, g.data());
    } else if (e < nf + nh) {
      const ShellHinge& sh = model.hinges()[e - nf];
      const double omega = weights[sh.face[0]] * hinge_weight(model, sh, alpha, 0) +
                           weights[sh.face[1]] * hinge_weight(model, sh, alpha, 1);
      Vec12 ge;
      hinge_energy_gradient_hessian(hinge_positions(sh, x), sh.rest, omega, nullptr, &ge, nullptr);
      asmb.scatter_vector<4>(e, ge, g.data());
    } else {
      const ClampHinge& c = model.clamp_hinges()[e - nf - nh];
      Vec12 ge;
      hinge_energy_gradient_hessian(clamp_positions(c, x), c.rest, 3.0 * weights[c.face] / A[c.face], nullptr,
                                    &ge, nullptr);
      asmb.scatter_vector<4>(e, ge, g.data());
    }
  };
  for (const std::vector<int>& colour : asmb.colours()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) element(colour[i]);
                      });
  }
  *d_positions = RowMatX3d::Zero(model.num_vertices(), 3);
  model.scatter_free(g, *d_positions);
}

}  // namespace cutwork::solvers

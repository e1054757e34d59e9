#include "solvers/objective/energy_density.h"

#include <cmath>

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

/// Calls visit(face, w) for every face whose W the unit energy of element e enters with weight w.
template <typename Visit>
void for_each_density_term(const ShellModel& model, const Eigen::VectorXd& alpha, int e, Visit&& visit) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const ElementRef ref = model.element(e);
  switch (ref.kind) {
    case ElementKind::Membrane: visit(ref.index, 1.0 / A[ref.index]); return;
    case ElementKind::Bend: {
      const int f = model.bends()[ref.index].face;
      visit(f, 1.0 / A[f]);
      return;
    }
    case ElementKind::Hinge: {
      const ShellHinge& h = model.hinges()[ref.index];
      for (int side = 0; side < 2; ++side) visit(h.face[side], hinge_weight(model, h, alpha, side));
      return;
    }
    case ElementKind::Clamp: {
      const int f = model.clamp_hinges()[ref.index].face;
      visit(f, 3.0 / A[f]);
      return;
    }
  }
}

}  // namespace

Eigen::VectorXd energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  Eigen::VectorXd W = Eigen::VectorXd::Zero(model.num_faces());
  for (int e = 0; e < model.num_elements(); ++e)
    for_each_density_term(model, alpha, e, [&](int face, double w) { W[face] += w * unit[e]; });
  return W;
}

void energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                        const Eigen::VectorXd& weights, RowMatX3d* d_positions, Eigen::VectorXd* d_alpha) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const int nf = model.num_faces();

  if (d_alpha) {
    // Only the hinge weights depend on α; with T = Â_i + Â_j,
    //   ∂ln w_i/∂α_i = 3/(2α_i) − 2A_i/T,   ∂ln w_i/∂α_j = 1/(2α_j) − 2A_j/T.
    d_alpha->setZero(nf);
    if (!model.hinges().empty()) {
      ElementEnergies unit;
      shell_energy(model, x, alpha, &unit);
      for (int e = 0; e < model.num_elements(); ++e) {
        const ElementRef ref = model.element(e);
        if (ref.kind != ElementKind::Hinge) continue;
        const ShellHinge& sh = model.hinges()[ref.index];
        const double T = alpha[sh.face[0]] * A[sh.face[0]] + alpha[sh.face[1]] * A[sh.face[1]];
        for (int side = 0; side < 2; ++side) {
          const int i = sh.face[side], j = sh.face[1 - side];
          const double cw = weights[i] * hinge_weight(model, sh, alpha, side) * unit[e];
          (*d_alpha)[i] += cw * (1.5 / alpha[i] - 2.0 * A[i] / T);
          (*d_alpha)[j] += cw * (0.5 / alpha[j] - 2.0 * A[j] / T);
        }
      }
    }
  }
  if (!d_positions) return;

  // Σ_i c_i ∂W_i/∂x = Σ_elements ω_e ∇U_e with ω_e = Σ_(face, w) c_face w.
  Eigen::VectorXd omega = Eigen::VectorXd::Zero(model.num_elements());
  for (int e = 0; e < model.num_elements(); ++e)
    for_each_density_term(model, alpha, e, [&](int face, double w) { omega[e] += weights[face] * w; });
  *d_positions = RowMatX3d::Zero(model.num_vertices(), 3);
  model.scatter_free(weighted_element_gradient(model, x, omega), *d_positions);
}

}  // namespace cutwork::solvers

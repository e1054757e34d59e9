#include "solvers/objective/energy_density.h"

#include <cmath>

#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

/// Weight w of a hinge's unit energy in W_i of its face `side` (0 or 1): w = 3 Â_i s / (Â_i + Â_j)²,
/// s the hinge's fill factor.
double hinge_weight(const ShellModel& model, const ShellHinge& h, const Eigen::VectorXd& alpha, int side) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const int i = h.face[side], j = h.face[1 - side];
  const double ai = alpha[i] * A[i], aj = alpha[j] * A[j];
  return 3.0 * ai * hinge_fill_factor(model, h, alpha) / ((ai + aj) * (ai + aj));
}

/// Calls visit(face, w, dw) for every face whose W the unit energy of element e enters with weight
/// w; when `derivatives`, dw(k, ∂w/∂α_k) is called for every face k that w depends on, right after.
/// Membranes and bends: w = s_e(α_f)/(α_f A_f) = r(α_f)/A_f — the energy per remaining area (r ≡ 1
/// under the linear rule); clamp hinges: 3 r_b(α_f)/A_f (a third of the face carries them).
template <typename Visit>
void for_each_density_term(const ShellModel& model, const Eigen::VectorXd& alpha, int e, bool derivatives,
                           DensityElements which, Visit&& visit) {
  const Eigen::VectorXd& A = model.mesh().face_areas();
  const FillStiffnessMap& g = model.fill_stiffness();
  const ElementRef ref = model.element(e);
  if (which == DensityElements::Membrane && ref.kind != ElementKind::Membrane) return;
  const auto face_term = [&](int f, double factor, bool membrane) {
    double dr = 0;
    const double r = g.part_ratio(!membrane, ref.part, alpha[f], &dr);
    visit(f, factor * r / A[f], [&](auto&& dw) {
      if (derivatives && dr != 0) dw(f, factor * dr / A[f]);
    });
  };
  switch (ref.kind) {
    case ElementKind::Membrane: face_term(ref.index, 1.0, true); return;
    case ElementKind::Bend: face_term(model.bends()[ref.index].face, 1.0, false); return;
    case ElementKind::Clamp: face_term(model.clamp_hinges()[ref.index].face, 3.0, false); return;
    case ElementKind::Hinge: {
      // With T = Â_i + Â_j and s = √(g_i g_j):
      //   ∂ln w_i/∂α_i = 1/α_i + g_i'/(2 g_i) − 2A_i/T,   ∂ln w_i/∂α_j = g_j'/(2 g_j) − 2A_j/T.
      const ShellHinge& h = model.hinges()[ref.index];
      const double T = alpha[h.face[0]] * A[h.face[0]] + alpha[h.face[1]] * A[h.face[1]];
      for (int side = 0; side < 2; ++side) {
        const int i = h.face[side], j = h.face[1 - side];
        const double w = hinge_weight(model, h, alpha, side);
        visit(i, w, [&](auto&& dw) {
          if (!derivatives) return;
          double di = 0, dj = 0;
          const double gi = g.bending(alpha[i], &di), gj = g.bending(alpha[j], &dj);
          dw(i, w * (1.0 / alpha[i] + di / (2.0 * gi) - 2.0 * A[i] / T));
          dw(j, w * (dj / (2.0 * gj) - 2.0 * A[j] / T));
        });
      }
      return;
    }
  }
}

}  // namespace

Eigen::VectorXd energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                               DensityElements which) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  Eigen::VectorXd W = Eigen::VectorXd::Zero(model.num_faces());
  for (int e = 0; e < model.num_elements(); ++e)
    for_each_density_term(model, alpha, e, false, which, [&](int face, double w, auto&&) { W[face] += w * unit[e]; });
  return W;
}

void energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                        const Eigen::VectorXd& weights, RowMatX3d* d_positions, Eigen::VectorXd* d_alpha,
                        DensityElements which) {
  const int nf = model.num_faces();

  if (d_alpha) {
    // Σ_i c_i ∂W_i/∂α_k = Σ_e U_e Σ_(i, w) c_i ∂w/∂α_k: only hinge weights and homogenised ratios
    // depend on α.
    d_alpha->setZero(nf);
    if (!model.hinges().empty() || !model.fill_stiffness().linear()) {
      ElementEnergies unit;
      shell_energy(model, x, alpha, &unit);
      for (int e = 0; e < model.num_elements(); ++e)
        for_each_density_term(model, alpha, e, true, which, [&](int face, double, auto&& derivative) {
          derivative([&](int k, double dw) { (*d_alpha)[k] += weights[face] * dw * unit[e]; });
        });
    }
  }
  if (!d_positions) return;

  // Σ_i c_i ∂W_i/∂x = Σ_elements ω_e ∇U_e with ω_e = Σ_(face, w) c_face w.
  Eigen::VectorXd omega = Eigen::VectorXd::Zero(model.num_elements());
  for (int e = 0; e < model.num_elements(); ++e)
    for_each_density_term(model, alpha, e, false, which,
                          [&](int face, double w, auto&&) { omega[e] += weights[face] * w; });
  *d_positions = RowMatX3d::Zero(model.num_vertices(), 3);
  model.scatter_free(weighted_element_gradient(model, x, omega), *d_positions);
}

}  // namespace cutwork::solvers

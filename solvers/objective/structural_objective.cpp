#include "solvers/objective/structural_objective.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "host/core/internal_error.h"
#include "solvers/objective/energy_density.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {

ObjectiveTerms energy_density_objective(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                        double beta, double w_ref, Eigen::VectorXd* energy_density_out,
                                        const PeakMeasure* peak) {
  if (!(w_ref > 0) || !std::isfinite(w_ref) || !std::isfinite(beta))
    throw InternalError("energy_density_objective: W_ref must be finite and > 0 and beta finite");
  if (peak && (!peak->K || peak->K->empty()))
    throw InternalError("energy_density_objective: the peak measure needs concentration factors");
  const Eigen::VectorXd W =
      peak ? peak_energy_density(model, x, alpha, *peak->K, peak->weight, peak->cover) : energy_density(model, x, alpha);
  const int m = model.num_faces();
  // ∂S/∂W_i = (W_i − β)₊ / (m W_ref²): the weights of the vector–Jacobian products of W.
  Eigen::VectorXd weights = Eigen::VectorXd::Zero(m);
  ObjectiveTerms t;
  for (int i = 0; i < m; ++i) {
    const double excess = W[i] - beta;
    if (!(excess > 0)) continue;
    t.value += 0.5 * (excess / w_ref) * (excess / w_ref);
    weights[i] = excess / (m * w_ref * w_ref);
  }
  t.value /= m;
  t.d_positions = RowMatX3d::Zero(model.num_vertices(), 3);
  t.d_alpha = Eigen::VectorXd::Zero(m);
  if (weights.any()) {
    if (peak)
      peak_energy_density_vjp(model, x, alpha, *peak->K, peak->weight, weights, &t.d_positions, &t.d_alpha,
                              peak->cover, peak->cover && peak->K->by_shape() ? &t.d_cover : nullptr);
    else
      energy_density_vjp(model, x, alpha, weights, &t.d_positions, &t.d_alpha);
  }
  if (energy_density_out) *energy_density_out = W;
  return t;
}

ObjectiveTerms compliance_objective(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    double c_ref) {
  if (!(c_ref > 0) || !std::isfinite(c_ref))
    throw InternalError("compliance_objective: the reference compliance must be finite and > 0");
  ObjectiveTerms t = compliance_terms(model, x, alpha);
  t.value /= c_ref;
  t.d_positions /= c_ref;
  t.d_alpha /= c_ref;
  return t;
}

double adaptive_threshold(const Eigen::VectorXd& energy_density, AdaptiveThreshold mode, double y_percent) {
  const int m = int(energy_density.size());
  if (m == 0) throw InternalError("adaptive_threshold: no energy densities");
  std::vector<double> w(energy_density.data(), energy_density.data() + m);
  if (mode == AdaptiveThreshold::Median) {
    std::sort(w.begin(), w.end());
    return m % 2 ? w[size_t(m / 2)] : 0.5 * (w[size_t(m / 2 - 1)] + w[size_t(m / 2)]);
  }
  if (!(y_percent > 0 && y_percent <= 100)) throw InternalError("adaptive_threshold: y must lie in (0, 100]");
  const int k = std::max(1, int(std::ceil(y_percent / 100.0 * m - 1e-9)));
  std::sort(w.begin(), w.end(), std::greater<>());
  double sum = 0;
  for (int i = 0; i < k; ++i) sum += w[size_t(i)];
  return sum / k;
}

}  // namespace cutwork::solvers

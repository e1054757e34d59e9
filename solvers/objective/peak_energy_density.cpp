#include "solvers/objective/peak_energy_density.h"

#include "host/core/internal_error.h"

#include <fmt/format.h>

#include "host/core/error.h"
#include "solvers/objective/energy_density.h"
#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

MonotoneCurve checked_concentration(const std::vector<double>& alpha, const std::vector<double>& k, const char* what) {
  if (k.size() != alpha.size())
    throw InputError(fmt::format("{} concentration curve: {} factors for {} fill ratios", what, k.size(), alpha.size()));
  for (size_t i = 0; i < k.size(); ++i)
    if (!(k[i] >= 1 - 1e-9))
      throw InputError(fmt::format("{} concentration curve: factor {} at α = {} is below 1", what, k[i], alpha[i]));
  return MonotoneCurve(alpha, k);
}

}  // namespace

ConcentrationMap::ConcentrationMap(const FillStiffnessCurve& c) {
  if (c.membrane_concentration.empty() && c.bending_concentration.empty()) return;
  m_membrane = checked_concentration(c.alpha, c.membrane_concentration, "membrane");
  m_bending = checked_concentration(c.alpha, c.bending_concentration, "bending");
  m_membrane_ratio = MonotoneCurve(c.alpha, c.membrane);
  m_bending_ratio = MonotoneCurve(c.alpha, c.bending);
}

double ConcentrationMap::apply(const MonotoneCurve& k, double alpha) {
  if (k.empty() || alpha >= 1) return 1;
  return k(alpha);
}

Eigen::VectorXd peak_energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const ConcentrationMap& K, const Eigen::VectorXd* weight) {
  if (weight && weight->size() != model.num_faces())
    throw InternalError("peak_energy_density: the weights do not match the faces");
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  const Eigen::VectorXd& A = model.mesh().face_areas();
  Eigen::VectorXd U_membrane = Eigen::VectorXd::Zero(model.num_faces());
  for (int e = 0; e < model.num_elements(); ++e) {
    const ElementRef ref = model.element(e);
    if (ref.kind == ElementKind::Membrane) U_membrane[ref.index] += unit[e];
  }
  const FillStiffnessMap& g = model.fill_stiffness();
  Eigen::VectorXd peak(model.num_faces());
  for (int t = 0; t < model.num_faces(); ++t) {
    const double a = alpha[t];
    if (a >= 1) {
      peak[t] = W[t];
      continue;
    }
    const double w = weight ? (*weight)[t] : 1.0;
    auto blend = [w](double k) { return 1 + w * (k - 1); };
    const double membrane_model = g.membrane_ratio(a) * U_membrane[t] / A[t];
    const double membrane = K.m_membrane_ratio(a) * U_membrane[t] / A[t];
    const double bending = K.m_bending_ratio(a) / g.bending_ratio(a) * (W[t] - membrane_model);
    peak[t] = blend(K.membrane(a)) * membrane + blend(K.bending(a)) * bending;
  }
  return peak;
}

}  // namespace cutwork::solvers

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

double ConcentrationMap::apply(const MonotoneCurve& k, double alpha, double* slope) {
  if (slope) *slope = 0;
  if (k.empty() || alpha >= 1) return 1;
  double dk = 0;
  const double K = k(alpha, slope ? &dk : nullptr);
  const double t = (1 - alpha) / kConcentrationRamp;
  if (t >= 1) {
    if (slope) *slope = dk;
    return K;
  }
  // K ← 1 + (K − 1) s(t), s(t) = 3t² − 2t³, dt/dα = −1/δ.
  const double s = t * t * (3 - 2 * t), ds_dalpha = -6 * t * (1 - t) / kConcentrationRamp;
  if (slope) *slope = dk * s + (K - 1) * ds_dalpha;
  return 1 + (K - 1) * s;
}

double ConcentrationMap::ratio(const MonotoneCurve& r, double alpha, double* slope) {
  if (slope) *slope = 0;
  if (r.empty() || alpha >= 1) return 1;
  return r(alpha, slope);
}

namespace {

/// W_peak_t = a W_t + b M_t (M_t the membrane part of W_t) at α_t = alpha with blend weight w, and
/// da/dα, db/dα (the header's rule).
struct PeakCoefficients {
  double a = 1, b = 0, da = 0, db = 0;
};

PeakCoefficients peak_coefficients(const FillStiffnessMap& g, const ConcentrationMap& K, double alpha, double w) {
  PeakCoefficients c;
  if (alpha >= 1) return c;
  double dkm = 0, dkb = 0, dqm = 0, dqb = 0;
  const double km = 1 + w * (K.membrane(alpha, &dkm) - 1), kb = 1 + w * (K.bending(alpha, &dkb) - 1);
  dkm *= w, dkb *= w;
  // q: perforated material's mean energy density over the model's (1 where the model's elements
  // are the homogenised ones; the calibrated ratio ρ under the linear rule, whose r is 1).
  double qm = 1, qb = 1;
  if (g.linear()) qm = K.membrane_ratio(alpha, &dqm), qb = K.bending_ratio(alpha, &dqb);
  c.a = kb * qb;
  c.da = dkb * qb + kb * dqb;
  c.b = km * qm - c.a;
  c.db = dkm * qm + km * dqm - c.da;
  return c;
}

void check_weight(const ShellModel& model, const Eigen::VectorXd* weight) {
  if (weight && weight->size() != model.num_faces())
    throw InternalError("peak_energy_density: the weights do not match the faces");
}

}  // namespace

Eigen::VectorXd peak_energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const ConcentrationMap& K, const Eigen::VectorXd* weight) {
  check_weight(model, weight);
  const Eigen::VectorXd W = energy_density(model, x, alpha);
  const Eigen::VectorXd M = energy_density(model, x, alpha, DensityElements::Membrane);
  Eigen::VectorXd peak(model.num_faces());
  for (int t = 0; t < model.num_faces(); ++t) {
    const PeakCoefficients c = peak_coefficients(model.fill_stiffness(), K, alpha[t], weight ? (*weight)[t] : 1.0);
    peak[t] = c.a * W[t] + c.b * M[t];
  }
  return peak;
}

void peak_energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                             const ConcentrationMap& K, const Eigen::VectorXd* weight, const Eigen::VectorXd& c,
                             RowMatX3d* d_positions, Eigen::VectorXd* d_alpha) {
  check_weight(model, weight);
  const int nf = model.num_faces();
  if (c.size() != nf) throw InternalError("peak_energy_density_vjp: the weights c do not match the faces");
  Eigen::VectorXd ca(nf), cb(nf), dca(nf), dcb(nf);
  for (int t = 0; t < nf; ++t) {
    const PeakCoefficients k = peak_coefficients(model.fill_stiffness(), K, alpha[t], weight ? (*weight)[t] : 1.0);
    ca[t] = c[t] * k.a, cb[t] = c[t] * k.b, dca[t] = c[t] * k.da, dcb[t] = c[t] * k.db;
  }
  // Σ c a W + Σ c b M: through the densities' own vector–Jacobian products, plus the coefficients'
  // own α-derivatives.
  energy_density_vjp(model, x, alpha, ca, d_positions, d_alpha);
  RowMatX3d membrane_x;
  Eigen::VectorXd membrane_alpha;
  energy_density_vjp(model, x, alpha, cb, d_positions ? &membrane_x : nullptr, d_alpha ? &membrane_alpha : nullptr,
                     DensityElements::Membrane);
  if (d_positions) *d_positions += membrane_x;
  if (d_alpha) {
    *d_alpha += membrane_alpha;
    const Eigen::VectorXd W = energy_density(model, x, alpha);
    const Eigen::VectorXd M = energy_density(model, x, alpha, DensityElements::Membrane);
    for (int t = 0; t < nf; ++t) (*d_alpha)[t] += dca[t] * W[t] + dcb[t] * M[t];
  }
}

}  // namespace cutwork::solvers

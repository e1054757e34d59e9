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

/// W_peak_t = a W_t + b M_t (M_t = U_t^memb / A_t) at α_t = alpha with blend weight w, and
/// da/dα, db/dα (the header's rule).
struct PeakCoefficients {
  double a = 1, b = 0, da = 0, db = 0;
};

PeakCoefficients peak_coefficients(const FillStiffnessMap& g, const ConcentrationMap& K, double alpha, double w) {
  PeakCoefficients c;
  if (alpha >= 1) return c;
  double dkm = 0, dkb = 0, drho_m = 0, drho_b = 0, dr_m = 0, dr_b = 0;
  const double km = 1 + w * (K.membrane(alpha, &dkm) - 1), kb = 1 + w * (K.bending(alpha, &dkb) - 1);
  dkm *= w, dkb *= w;
  const double rho_m = K.membrane_ratio(alpha, &drho_m), rho_b = K.bending_ratio(alpha, &drho_b);
  const double r_m = g.membrane_ratio(alpha, &dr_m), r_b = g.bending_ratio(alpha, &dr_b);
  c.a = kb * rho_b / r_b;
  c.da = (dkb * rho_b + kb * drho_b) / r_b - kb * rho_b * dr_b / (r_b * r_b);
  c.b = km * rho_m - c.a * r_m;
  c.db = dkm * rho_m + km * drho_m - c.da * r_m - c.a * dr_m;
  return c;
}

/// U_t^memb / A_t (#F): the face's membrane element energy at unit fill per area.
Eigen::VectorXd membrane_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  const Eigen::VectorXd& A = model.mesh().face_areas();
  Eigen::VectorXd M = Eigen::VectorXd::Zero(model.num_faces());
  for (int e = 0; e < model.num_elements(); ++e) {
    const ElementRef ref = model.element(e);
    if (ref.kind == ElementKind::Membrane) M[ref.index] += unit[e] / A[ref.index];
  }
  return M;
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
  const Eigen::VectorXd M = membrane_density(model, x, alpha);
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
  // Σ c a W: through W's own vector–Jacobian product.
  energy_density_vjp(model, x, alpha, ca, d_positions, d_alpha);
  const Eigen::VectorXd& A = model.mesh().face_areas();
  if (d_alpha) {
    const Eigen::VectorXd W = energy_density(model, x, alpha);
    const Eigen::VectorXd M = membrane_density(model, x, alpha);
    for (int t = 0; t < nf; ++t) (*d_alpha)[t] += dca[t] * W[t] + dcb[t] * M[t];
  }
  if (d_positions) {
    // Σ c b U^memb / A: the membrane elements weighted by c_t b_t / A_t.
    Eigen::VectorXd omega = Eigen::VectorXd::Zero(model.num_elements());
    for (int e = 0; e < model.num_elements(); ++e) {
      const ElementRef ref = model.element(e);
      if (ref.kind == ElementKind::Membrane) omega[e] = cb[ref.index] / A[ref.index];
    }
    RowMatX3d membrane = RowMatX3d::Zero(model.num_vertices(), 3);
    model.scatter_free(weighted_element_gradient(model, x, omega), membrane);
    *d_positions += membrane;
  }
}

}  // namespace cutwork::solvers

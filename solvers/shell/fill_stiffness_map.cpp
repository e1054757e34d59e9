#include "solvers/shell/fill_stiffness_map.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork::solvers {

MonotoneCurve::MonotoneCurve(std::vector<double> x, std::vector<double> y) : m_x(std::move(x)), m_y(std::move(y)) {
  const size_t n = m_x.size();
  if (n < 2 || m_y.size() != n) throw InputError("stiffness curve: needs two or more samples of matching size");
  for (size_t k = 0; k < n; ++k) {
    if (!std::isfinite(m_x[k]) || !std::isfinite(m_y[k])) throw InputError("stiffness curve: non-finite sample");
    if (k > 0 && !(m_x[k] > m_x[k - 1])) throw InputError("stiffness curve: fill ratios must increase strictly");
  }
  // Fritsch–Carlson: secant slopes, harmonic-mean interior derivatives (zero where the data turn),
  // zero slope at the first sample (r is held constant below it), one-sided at the last.
  std::vector<double> delta(n - 1);
  for (size_t k = 0; k + 1 < n; ++k) delta[k] = (m_y[k + 1] - m_y[k]) / (m_x[k + 1] - m_x[k]);
  m_d.assign(n, 0.0);
  for (size_t k = 1; k + 1 < n; ++k) {
    if (delta[k - 1] * delta[k] <= 0) continue;
    const double h0 = m_x[k] - m_x[k - 1], h1 = m_x[k + 1] - m_x[k];
    const double w0 = 2 * h1 + h0, w1 = h1 + 2 * h0;
    m_d[k] = (w0 + w1) / (w0 / delta[k - 1] + w1 / delta[k]);
  }
  {
    const size_t k = n - 1;
    const double h0 = m_x[k] - m_x[k - 1];
    double d = delta[k - 1];
    if (n > 2) d = ((2 * h0 + (m_x[k - 1] - m_x[k - 2])) * delta[k - 1] - h0 * delta[k - 2]) / (h0 + (m_x[k - 1] - m_x[k - 2]));
    if (d * delta[k - 1] <= 0) d = 0;
    else if (std::abs(d) > 3 * std::abs(delta[k - 1])) d = 3 * delta[k - 1];
    m_d[k] = d;
  }
}

double MonotoneCurve::operator()(double alpha, double* slope) const {
  if (alpha <= m_x.front() || alpha >= m_x.back()) {
    if (slope) *slope = 0;
    return alpha <= m_x.front() ? m_y.front() : m_y.back();
  }
  const size_t k = size_t(std::upper_bound(m_x.begin(), m_x.end(), alpha) - m_x.begin()) - 1;
  const double h = m_x[k + 1] - m_x[k], t = (alpha - m_x[k]) / h;
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
  if (slope) {
    const double d00 = 6 * t2 - 6 * t, d10 = 3 * t2 - 4 * t + 1, d01 = -6 * t2 + 6 * t, d11 = 3 * t2 - 2 * t;
    *slope = (d00 * m_y[k] + d01 * m_y[k + 1]) / h + d10 * m_d[k] + d11 * m_d[k + 1];
  }
  return h00 * m_y[k] + h10 * h * m_d[k] + h01 * m_y[k + 1] + h11 * h * m_d[k + 1];
}

namespace {

MonotoneCurve checked_curve(const std::vector<double>& alpha, const std::vector<double>& ratio, const char* what) {
  if (ratio.size() != alpha.size())
    throw InputError(fmt::format("{} stiffness curve: {} ratios for {} fill ratios", what, ratio.size(), alpha.size()));
  for (size_t k = 0; k < alpha.size(); ++k)
    if (!(alpha[k] > 0 && alpha[k] <= 1) || !(ratio[k] > 0 && ratio[k] <= 1.5))
      throw InputError(fmt::format("{} stiffness curve: sample {} (α = {}, ratio {}) out of range", what, k, alpha[k],
                                   ratio[k]));
  if (alpha.back() != 1.0 || ratio.back() != 1.0)
    throw InputError(fmt::format("{} stiffness curve: the last sample must be α = 1 with ratio 1", what));
  return MonotoneCurve(alpha, ratio);
}

}  // namespace

FillStiffnessMap::FillStiffnessMap(const MechanicsSettings& mechanics) {
  if (mechanics.stiffness == FillStiffness::Linear) return;
  const FillStiffnessCurve& c = mechanics.stiffness_curve;
  if (c.empty())
    throw InputError("homogenised stiffness: no calibrated curve (solvers/homogenise must fill it in first)");
  m_membrane = checked_curve(c.alpha, c.membrane, "membrane");
  m_bending = checked_curve(c.alpha, c.bending, "bending");
  if (c.anisotropic() && !c.split())
    throw InputError("stiffness curve: an anisotropy curve needs the isotropic split's bulk and shear curves");
  if (!c.split()) return;
  m_membrane_bulk = checked_curve(c.alpha, c.membrane_bulk, "membrane bulk");
  m_membrane_shear = checked_curve(c.alpha, c.membrane_shear, "membrane shear");
  m_bending_bulk = checked_curve(c.alpha, c.bending_bulk, "bending bulk");
  m_bending_shear = checked_curve(c.alpha, c.bending_shear, "bending shear");
  if (!c.anisotropic()) return;
  for (const auto* q : {&c.membrane_anisotropy, &c.bending_anisotropy}) {
    const char* what = q == &c.membrane_anisotropy ? "membrane" : "bending";
    if (q->size() != c.alpha.size())
      throw InputError(fmt::format("{} anisotropy curve: {} samples for {} fill ratios", what, q->size(), c.alpha.size()));
    for (size_t k = 0; k < q->size(); ++k)
      if (!(std::abs((*q)[k]) < 1))
        throw InputError(fmt::format("{} anisotropy curve: sample {} (α = {}, q = {}) is not in (−1, 1)", what, k,
                                     c.alpha[k], (*q)[k]));
    if (q->back() != 0.0) throw InputError(fmt::format("{} anisotropy curve: the last sample must be q = 0", what));
  }
  m_membrane_anisotropy = MonotoneCurve(c.alpha, c.membrane_anisotropy);
  m_bending_anisotropy = MonotoneCurve(c.alpha, c.bending_anisotropy);
}

double FillStiffnessMap::anisotropy(bool bending, double alpha, double* derivative) const {
  const MonotoneCurve& q = bending ? m_bending_anisotropy : m_membrane_anisotropy;
  if (q.empty()) {
    if (derivative) *derivative = 0;
    return 0;
  }
  return q(alpha, derivative);
}

double FillStiffnessMap::anisotropic_part(bool bending, double alpha, double* derivative, bool factor) const {
  // g_A = g_G q (or r_A = r_G q): the product rule.
  double dq = 0, dg = 0;
  const double q = anisotropy(bending, alpha, derivative ? &dq : nullptr);
  const double g = factor ? apply(curve(bending, FillPart::Shear), alpha, derivative ? &dg : nullptr)
                          : ratio(curve(bending, FillPart::Shear), alpha, derivative ? &dg : nullptr);
  if (derivative) *derivative = dg * q + g * dq;
  return g * q;
}

double FillStiffnessMap::apply(const MonotoneCurve& r, double alpha, double* derivative) {
  if (r.empty()) {
    if (derivative) *derivative = 1;
    return alpha;
  }
  double slope = 0;
  const double value = r(alpha, derivative ? &slope : nullptr);
  if (derivative) *derivative = value + alpha * slope;
  return alpha * value;
}

double FillStiffnessMap::ratio(const MonotoneCurve& r, double alpha, double* derivative) {
  if (r.empty()) {
    if (derivative) *derivative = 0;
    return 1;
  }
  return r(alpha, derivative);
}

}  // namespace cutwork::solvers

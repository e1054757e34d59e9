#pragma once
/// Fill factor rules of the shell elements: how a face's membrane and bending stiffness follow
/// its fill ratio α ∈ (0, 1].
///
///  - linear (the paper's (9)–(10)): g(α) = α;
///  - homogenised: g(α) = α r(α), with r the calibrated ratio of a periodically perforated sheet's
///    stiffness to α times the solid's (FillStiffnessCurve in host/scene/load_case.h, computed by
///    solvers/homogenise). r is interpolated by the monotone cubic of Fritsch and Carlson (PCHIP)
///    through the samples, with zero slope at the smallest sample and r held constant below it, so
///    g is C¹, and g(α) → 0 as α → 0 with g(α)/α bounded away from zero (a hole's filler keeps a
///    small stiffness, as under the linear rule).
///
/// Separate curves for membrane (stretching) and bending: a perforation softens them differently.
#include <vector>

#include "host/scene/load_case.h"

namespace cutwork::solvers {

/// One monotone cubic r(α) through samples (PCHIP).
class MonotoneCurve {
 public:
  MonotoneCurve() = default;
  /// x strictly increasing (≥ 2 samples), y the same size. Throws InputError otherwise.
  MonotoneCurve(std::vector<double> x, std::vector<double> y);
  /// r(α) and, when `slope` is not null, dr/dα.
  double operator()(double alpha, double* slope = nullptr) const;
  bool empty() const { return m_x.empty(); }

 private:
  std::vector<double> m_x, m_y, m_d;  ///< samples and the derivative at each
};

class FillStiffnessMap {
 public:
  /// The linear rule.
  FillStiffnessMap() = default;
  /// The linear rule for FillStiffness::Linear; the curve's rule for Homogenised. Throws
  /// InputError for a missing or malformed curve (not increasing, ratios not in (0, 1.5], last
  /// sample not α = 1 with ratios 1).
  explicit FillStiffnessMap(const MechanicsSettings& mechanics);

  bool linear() const { return m_membrane.empty(); }
  /// g_m(α) (membrane) and dg_m/dα into `derivative` when not null.
  double membrane(double alpha, double* derivative = nullptr) const { return apply(m_membrane, alpha, derivative); }
  /// g_b(α) (bending) and dg_b/dα.
  double bending(double alpha, double* derivative = nullptr) const { return apply(m_bending, alpha, derivative); }
  /// r = g/α and dr/dα (membrane, bending).
  double membrane_ratio(double alpha, double* derivative = nullptr) const { return ratio(m_membrane, alpha, derivative); }
  double bending_ratio(double alpha, double* derivative = nullptr) const { return ratio(m_bending, alpha, derivative); }

 private:
  static double apply(const MonotoneCurve& r, double alpha, double* derivative);
  static double ratio(const MonotoneCurve& r, double alpha, double* derivative);

  MonotoneCurve m_membrane, m_bending;
};

}  // namespace cutwork::solvers

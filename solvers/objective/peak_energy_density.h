#pragma once
/// Peak energy density at the ligaments between holes (issue 21 item 5, beyond the paper).
///
/// A coarse face's W (energy_density.h) is a mean over the face's material: a hole's rim carries
/// more. The cell problems (solvers/homogenise/cell_homogenisation.h) measure, per stencil shape and
/// fill ratio, the concentration factor K = peak W / mean W over a periodic cell's material (the
/// largest over the macroscopic stress states: uniaxial at every angle, equibiaxial, pure shear;
/// separately for membrane and bending). The calibrated curve (FillStiffnessCurve's
/// membrane_concentration, bending_concentration) carries K at its sample fill ratios.
///
/// The rule. Per face t,
///     W_peak_t = K_m(α_t) W_t^memb + K_b(α_t) W_t^bend,
/// the mean energy densities of perforated material at the face's macroscopic strain and curvature:
///     W_t^memb = q_m(α_t) M_t,   W_t^bend = q_b(α_t) (W_t − M_t),
/// M_t the membrane part of the model's W_t (r_m^model U_t^memb / A_t, U_t^memb the face's membrane
/// element energy at unit fill, summed over the bulk and shear parts under the isotropic split of
/// fill_stiffness_map.h) and W_t − M_t its bending part, whatever the bending model. Under the
/// homogenised rule the model's elements are perforated material's, so q = 1 and the two parts add
/// up to W_t. Under the linear rule they do not: q = ρ, the calibrated ratio of the curve (the
/// linear rule's r is 1). The linear rule's faces are stiffer than perforated material, and at the
/// strain the linear model computes, perforated material stores ρ U/A per area of material (not
/// U/A) — the rule takes the model's strain as given; where the load, not the strain, is
/// prescribed, the linear model's strain and so its W_peak are too small by about ρ. K_m and K_b
/// apply to their own parts: a plate's membrane and bending peaks sit at the same rim points, so
/// adding them bounds the peak of the sum from above (up to the cross term). A face with α_t = 1
/// exactly is uncut: K = 1, q = 1, W_peak_t = W_t.
///
/// K(α) between samples: the shape-preserving cubic of fill_stiffness_map.h (PCHIP; K need not be
/// monotone, PCHIP does not overshoot the samples and is C¹), held constant outside the samples.
/// The last sample (α = 1) holds the dilute limit (a vanishing hole still concentrates stress, as
/// Kirsch's hole does), not the uncut value 1. Between 1 − δ and 1 (δ = kConcentrationRamp) the
/// factor ramps to 1, K ← 1 + (K − 1) s((1 − α)/δ) with the C¹ smoothstep s(t) = 3t² − 2t³: a face
/// that a stencil barely touches (or, under the cell filter, whose cone barely reaches a hole) holds
/// no rim of its own — the faces that hold the hole report its peak — and the objective built on
/// W_peak stays C¹ where a stencil first enters a face (a jump from 1 to the dilute K there would
/// stall the line search). Units: W in J/m².
///
/// As an objective (structure.measure "peak", structural_objective.h): per face,
///     W_peak_t = a(α_t) W_t + b(α_t) M_t,   a = k_b q_b,   b = k_m q_m − k_b q_b,
/// with k the blended factors; a = 1, b = 0 at α = 1. The weights w (the cell filter's blend) do not
/// depend on the stencils, so ∂W_peak/∂α is the α-derivative of a and b plus a ∂W/∂α + b ∂M/∂α
/// (peak_energy_density_vjp).
#include <Eigen/Core>

#include "host/scene/load_case.h"
#include "solvers/shell/fill_stiffness_map.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// The rule above in a line, for reports.
inline constexpr const char* kPeakEnergyDensityRule =
    "W_peak = K_m(alpha) W_membrane + K_b(alpha) W_bending per face, K = peak/mean energy density over a periodic "
    "cell's material from the cell problems (worst over shapes and stress states; K ramps to 1 over alpha in [0.95, 1] "
    "and is 1 at alpha = 1; blended towards 1 where the cell filter says a face resolves its stencils); max over "
    "material faces";
/// What reports say instead when the mechanics carries no concentration samples (W_peak null).
inline constexpr const char* kPeakEnergyDensityAbsent =
    "not computed: no concentration factors (mechanics.stiffness is not homogenised)";

/// δ of the ramp of K to 1 near α = 1 (above).
inline constexpr double kConcentrationRamp = 0.05;

/// K_m(α), K_b(α) of a calibrated curve.
class ConcentrationMap {
 public:
  /// No calibration: empty().
  ConcentrationMap() = default;
  /// From the curve's concentration samples; empty() when it has none. Throws InputError for
  /// samples of the wrong size or below 1.
  explicit ConcentrationMap(const FillStiffnessCurve& curve);

  bool empty() const { return m_membrane.empty(); }
  /// K_m(α) with the ramp to 1 above (1 for α ≥ 1, and when empty()); dK_m/dα into `slope`.
  double membrane(double alpha, double* slope = nullptr) const { return apply(m_membrane, alpha, slope); }
  double bending(double alpha, double* slope = nullptr) const { return apply(m_bending, alpha, slope); }
  /// The calibrated ratios ρ = g/α of the curve the factors came with (1 for α ≥ 1).
  double membrane_ratio(double alpha, double* slope = nullptr) const { return ratio(m_membrane_ratio, alpha, slope); }
  double bending_ratio(double alpha, double* slope = nullptr) const { return ratio(m_bending_ratio, alpha, slope); }

 private:
  static double apply(const MonotoneCurve& k, double alpha, double* slope);
  static double ratio(const MonotoneCurve& r, double alpha, double* slope);
  MonotoneCurve m_membrane, m_bending, m_membrane_ratio, m_bending_ratio;
};

/// W_peak (#F, J/m²) of the rule above at positions x (#V×3) and fill ratios alpha (#F).
/// `weight` (#F in [0, 1], optional; null: all ones): how far each face is from resolving its
/// stencils. The factors are blended, K ← 1 + w_t (K − 1), so that a face that resolves the rim
/// of a hole itself (w = 0: the cell filter's blend b of solvers/shell/cell_filter.h, 0 where four
/// or more triangles span a stencil) is not concentrated a second time. Only K is blended: the
/// ratios r convert the model's W into perforated material's mean W and stay as they are.
/// Precondition: !K.empty().
Eigen::VectorXd peak_energy_density(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const ConcentrationMap& K, const Eigen::VectorXd* weight = nullptr);

/// For weights c (#F): Σ_t c_t ∂W_peak_t/∂x into d_positions (#V×3; rows of fixed vertices zero)
/// and Σ_t c_t ∂W_peak_t/∂α into d_alpha (#F), at fixed `weight`. Either output may be null. The
/// twin of energy_density_vjp for an objective built on W_peak.
void peak_energy_density_vjp(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                             const ConcentrationMap& K, const Eigen::VectorXd* weight, const Eigen::VectorXd& c,
                             RowMatX3d* d_positions, Eigen::VectorXd* d_alpha);

}  // namespace cutwork::solvers

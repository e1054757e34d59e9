#pragma once
/// The structural objectives S(α, x) of §5.3 in the dimensionless form the joint objective
/// J = w_S S + w_P P (19) uses, with their partials for the adjoint (solvers/sensitivity).
///
/// Energy density (17):
///     S_stab = (1/m) Σ_i ½ ((W_i − β)₊ / W_ref)²,
/// W_i the per-triangle energy density (16), m the number of triangles, β the threshold and
/// W_ref a reference density — the uncut shell's W_q (energy_density_reference.h), the quantity β is a fraction of
/// (Table 2). Dividing by W_ref² is the only change to (17): it makes S independent of the
/// material's and the load's magnitudes, so that one w_S means the same on a plate loaded with
/// 1 N and a pavilion under its own weight (the paper's w_S are tied to its unstated units).
///
/// Compliance (18): S_comp = C / C_ref with C = f_ext(α) · (x − X), the work of the external
/// loads (solvers/objective/structural_quantities.h) and C_ref the compliance of the pattern
/// design. The paper writes (18) as Σ_i A_i W_i, "an equivalent formulation based on the total
/// internal energy"; with (16) as printed that sum counts bending 3/2 times and weighs the
/// membrane of a cut triangle by its uncut area, so cutwork minimises the conventional
/// quantity it stands for. (Self-weight makes the load depend on α; C includes that.)
///
/// Peak measure (structure.measure "peak", beyond the paper): W_i is replaced by the ligament peak
/// W_peak_i of peak_energy_density.h, K_m(α) W^memb + K_b(α) W^bend, everywhere above (the
/// threshold, the adaptive statistic); W_ref stays the uncut W_q, where W_peak = W.
///
/// The adaptive threshold (§5.3, §6.2): β_new = the median of W, or the mean of the top y% of W.
#include <Eigen/Core>

#include "solvers/objective/objective_terms.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// The peak measure's data: the concentration factors, the blend weights (#F; null: all ones) and
/// the stencils' cover by shape (null: the worst shape's factors everywhere).
struct PeakMeasure {
  const ConcentrationMap* K = nullptr;
  const Eigen::VectorXd* weight = nullptr;
  const ShapeCover* cover = nullptr;
};

/// S_stab and its partials at positions x (#V×3, m) and fill ratios alpha (#F).
/// beta and w_ref in J/m²; w_ref > 0. Also returns the measure (#F: W, or W_peak when `peak` is
/// given) in `energy_density` when not null.
ObjectiveTerms energy_density_objective(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                        double beta, double w_ref, Eigen::VectorXd* energy_density = nullptr,
                                        const PeakMeasure* peak = nullptr);

/// S_comp = C / c_ref and its partials; c_ref > 0 (J).
ObjectiveTerms compliance_objective(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    double c_ref);

enum class AdaptiveThreshold { Median, TopPercent };

/// The adaptive β of W (#F, non-empty): the median (mean of the two middle values for an even
/// count), or the mean of the ⌈y% · m⌉ largest values (y in (0, 100]).
double adaptive_threshold(const Eigen::VectorXd& energy_density, AdaptiveThreshold mode, double y_percent);

}  // namespace cutwork::solvers

#pragma once
/// The stencils' cover of a simulation mesh's faces, shape by shape (ShapeCover of
/// objective_terms.h), as W_peak's factors by shape and by corner read it
/// (peak_energy_density.h), and its pull-back to the stencil parameters.
///
///     covered_ts = (B h_s)_t,   h_ts = Σ fraction(i, t) over the stencils i of shape s,
///     corner_ts  = (B e_s)_t,   e_ts = Σ fraction(i, t) ε_i,   ε_i = corner_radius / scale_i,
///
/// B the cell filter (the identity unless set), applied to each column as to α: a face that takes
/// its cell's fill ratio takes its cell's cover too. ε_i is the corner rule's radius (the
/// fabrication minimum feature, MechanicsSettings::corner_radius) in stencil i's bounding radii.
#include <span>

#include <Eigen/Core>

#include "host/stencil/fill_ratio.h"
#include "solvers/objective/objective_terms.h"
#include "solvers/shell/cell_filter.h"

namespace cutwork::solvers {

/// The cover of `evaluator`'s last evaluation of `stencils`; corner empty when corner_radius is 0.
ShapeCover shape_cover(const FillRatioEvaluator& evaluator, std::span<const StencilParams> stencils,
                       double corner_radius, const CellFilter& filter);

/// d_params (#S×5) = the pull-back of ∂S/∂(cover) `d_cover` through shape_cover (Bᵀ, then the
/// clipping's pieces and, for the corner moments, ∂ε_i/∂scale_i = −ε_i/scale_i). Needs the
/// evaluator's derivatives.
void shape_cover_pullback(const FillRatioEvaluator& evaluator, std::span<const StencilParams> stencils,
                          double corner_radius, const CellFilter& filter, const ShapeCover& d_cover,
                          Eigen::VectorXd& d_params);

}  // namespace cutwork::solvers

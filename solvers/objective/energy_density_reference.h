#pragma once
/// A reference energy density that converges under mesh refinement (issue 21 item 2): the area
/// quantile of W over the material, for β (structure.beta × W_ref) where W_max diverges.
///
/// Why. W_max = max_i W_i is singular where the elastic field is: at a re-entrant clamped corner
/// or a point-like load W grows without bound as the mesh is refined, so W_max and β = beta × W_max
/// measure the mesh, not the shell. Measured on a clamped L-shaped plate (the two edges meeting at
/// the re-entrant corner clamped, uniform pressure; tests/solvers/objective/
/// energy_density_reference_test.cpp), W_max doubles with every halving of h (0.0135, 0.0284,
/// 0.0564, 0.109 J/m² at h = 1/8 … 1/64) while the compliance converges (5.46, 5.67, 5.78,
/// 5.83 mJ). Excluding the faces within a fixed distance ρ of the singular points converges only
/// once h ≪ ρ (W decays slowly from the corner: the maximum then sits at r = ρ; ρ = 0.1: 0.0094,
/// 0.0090, 0.0123, 0.0143), and needs the singular points found.
///
/// The rule. W_q(p) = the smallest face energy density w such that the faces of material with
/// W > w cover at most the fraction p of the material area: the (1 − p) area quantile. The
/// singular zones cover an area that shrinks with h, so for p well above it the quantile is a
/// property of the field. On the L-plate, p = 2%: 7.83, 5.24, 5.25, 5.20 mJ/m² (0.2% and 0.9%
/// between the last levels); p = 1% still moves by 13% from h = 1/16 to 1/32; p = 5%: 2.67, 2.88,
/// 3.01, 3.04. The excluded faces (W > W_q) are what a report names with their count and area.
/// β of the structural phase is structure.beta × W_q of the uncut shell (design_pipeline.h's
/// beta_reference); it was × W_max (W_q(2%) is 0.82 of W_max on the built-in plate, so designs
/// made with the same beta are held to a lower threshold than before).
#include <vector>

#include <Eigen/Core>

namespace cutwork::solvers {

/// Default p of the rule (see above).
inline constexpr double kReferenceAreaFraction = 0.02;

struct EnergyDensityQuantile {
  double value = 0;          ///< W_q (J/m²)
  int faces_above = 0;       ///< material faces with W > W_q (left out of the reference)
  double area_above = 0;     ///< their area (m²)
  double material_area = 0; ///< m²
};

/// W_q(p) of W (#F, J/m²) over the faces marked in `material` (#F; material_faces of
/// structural_quantities.h), with face areas `areas` (#F, m²). p ∈ [0, 1): p = 0 gives W_max.
/// Throws InputError for mismatched sizes, p outside [0, 1) or no material face.
EnergyDensityQuantile energy_density_quantile(const Eigen::VectorXd& W, const Eigen::VectorXd& areas,
                                              const std::vector<bool>& material,
                                              double fraction = kReferenceAreaFraction);

}  // namespace cutwork::solvers

#pragma once
/// Numerical homogenisation of a perforated sheet (issue 11, item 3): the effective membrane and
/// bending stiffness of a flat sheet carrying one stencil shape in a hexagonal lattice, as a
/// function of the fill ratio α (material area / gross area), computed with the shell's own
/// elements on a conforming mesh of the holes.
///
/// The cell problem. Stencils of one shape, angle 0, scale s with α = 1 − A_shape s² / A_cell, sit
/// on the hexagonal lattice a₁ = (1, 0), a₂ = (½, √3/2) (spacing a = 1, A_cell = √3/2; the arrangement
/// of a Poisson-disk packing, isotropic in the plane for a circle). The period cell is the rhombus
/// spanned by a₁, a₂ with the stencil at its centre: a regular triangular grid of spacing
/// 1/`resolution`, cut along the outline (host/cut) and remeshed (host/mesh/isotropic_remesh; the
/// outline and the rhombus's sides are kept, so opposite sides carry translated copies of each
/// other's vertices). The cell is tiled 3 × 3 so that every face of the centre copy has its whole
/// shape-operator patch, and the displacement of each node is u = ū(X) + ũ(class): the macroscopic
/// field at the node's true position — in-plane u = ε̄ · X for the three membrane strains
/// ε̄ = (ε_xx, ε_yy, γ_xy), out of plane w = ½ Xᵀ κ̄ X for the three curvatures κ̄ = (κ_xx, κ_yy,
/// 2κ_xy) — plus a periodic fluctuation, one unknown per vertex of the cell modulo the lattice.
/// Minimising the energy of the centre copy's elements (the Hessians of the membrane and
/// shape-operator elements at rest: stretching and bending decouple on a flat sheet) over ũ is the
/// periodic cell problem; C*_ij = (1/A_cell) Σ_e u_iᵀ K_e u_j. A solid cell returns the closed forms
/// to round-off (both elements are exact for these fields). The hole must stay inside the rhombus
/// (its bounding circle inside the inscribed circle of radius √3/4), which bounds the fill ratios a
/// shape reaches: α ≥ 0.40 for a circle.

/// Scalar ratios. g = tr(C* C⁻¹)/3, C the solid's stiffness in the same (Voigt) notation: the mean
/// of the effective-to-solid ratio over the three modes, exact (= the factor) for an isotropic C*,
/// and invariant under rotating the lattice. r = g/α is what the fill stiffness rule stores
/// (fill_stiffness_map.h). The membrane and bending ratios do not depend on E or h (flat, linear).
///
/// Units: lengths in lattice spacings internally (a = 1); stiffness matrices in N/m (membrane,
/// C = E h/(1−ν²) [1 ν 0; ν 1 0; 0 0 (1−ν)/2]) and N·m (bending, D times the same matrix).
#include <Eigen/Core>

#include "host/scene/load_case.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork::solvers {

struct CellOptions {
  double resolution = 24;  ///< target edges per lattice spacing a, in [6, 200]
  int remesh_iterations = 5;
};

struct CellStiffness {
  double fill_ratio = 0;             ///< α asked for
  double window_fill_ratio = 0;      ///< material area of the meshed cell / cell area (≈ α)
  double scale = 0;                  ///< stencil scale s (bounding radius) in lattice spacings
  Eigen::Matrix3d membrane;          ///< C* (N/m), Voigt (ε_xx, ε_yy, γ_xy)
  Eigen::Matrix3d bending;           ///< D* (N·m), Voigt (κ_xx, κ_yy, 2κ_xy)
  double membrane_factor = 0;        ///< g_m = tr(C* C⁻¹)/3
  double bending_factor = 0;         ///< g_b = tr(D* D⁻¹)/3
  int vertices = 0, faces = 0;       ///< of the patch mesh
};

/// The largest hole fraction 1 − α at which `shape` still fits the period cell: its bounding circle
/// within (1 − ligament) of the rhombus's inscribed circle.
double max_hole_fraction(const StencilShape& shape, double ligament = 0.05);

/// Homogenised stiffness of `shape` perforating a sheet of `material` down to fill ratio α ∈
/// [1 − max_hole_fraction, 1]. Throws InputError for α outside that range or bad options.
CellStiffness homogenise_cell(const StencilShape& shape, const Material& material, double fill_ratio,
                              const CellOptions& options = {});

/// Closed-form solid stiffness (Voigt) of `material`: membrane C (N/m) and bending D (N·m).
Eigen::Matrix3d solid_membrane_stiffness(const Material& material);
Eigen::Matrix3d solid_bending_stiffness(const Material& material);

}  // namespace cutwork::solvers

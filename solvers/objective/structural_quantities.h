#pragma once
/// Scalar quantities of an equilibrium and, for those that serve as objectives, their partials.
///   strain energy  Ŵ(x, α)                    (J)  — the total elastic energy (11)
///   compliance     C = f_ext(α) · (x − X)      (J)  — the work of the external loads
///   max displacement  max_v |x_v − X_v|        (m)   over vertices of material
///   W_max          max_i W_i of (16)           (J/m²) over faces of material
/// Material: faces with α > kMaterialFillRatio, and the vertices of at least one such face. Inside a
/// stencil α is clamped at 1e-4 (a filler that keeps the stiffness matrix regular); that filler sags
/// under its own stiffness and carries curvature no material has, so neither its displacement nor
/// its energy density means anything (issue 11 item 5). A face less than 5% material is mostly
/// hole: the coarse mesh cannot resolve such a sliver, and its corners move with the filler; 5% is
/// also far above the clamp (1e-4), so round-off in α cannot flip a face. When no face is material
/// (everything cut away) both maxima run over the whole mesh.
/// At a linear-elastic equilibrium C = 2Ŵ; with the geometric nonlinearity of the shell they
/// differ, which is why both are reported. x: #V×3 (m); alpha: #F.
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "solvers/objective/objective_terms.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

/// Faces with α above this are material (see above).
inline constexpr double kMaterialFillRatio = 0.05;

/// #F: α_t > kMaterialFillRatio, or all true when no face is.
std::vector<bool> material_faces(const Eigen::VectorXd& alpha);
/// #V: vertices of at least one face of `material` (faces F, #F×3).
std::vector<bool> material_vertices(const RowMatX3i& faces, int num_vertices, const std::vector<bool>& material);

/// The scalar quantities of one equilibrium (see above).
struct EquilibriumScalars {
  double strain_energy = 0;      ///< J
  double compliance = 0;         ///< J
  double max_displacement = 0;   ///< m, over vertices of material
  int max_displacement_vertex = -1;
  double W_max = 0;              ///< J/m², over faces of material
  int W_max_face = -1;
  /// max_i W_peak_i (peak_energy_density.h: W at the holes' rims, from the cell problems'
  /// concentration factors), J/m², over the same faces as W_max. NaN (face −1) when the model's
  /// mechanics carries no concentration samples (mechanics.stiffness other than homogenised).
  double W_peak_max = std::numeric_limits<double>::quiet_NaN();
  int W_peak_max_face = -1;
  /// The biaxiality ρ (peak_energy_density.h: −1 pure shear, 0 uniaxial, 1 equibiaxial) of the
  /// membrane stress and of the bending moment at W_peak_max_face, where the concentration factors
  /// are read by state; NaN otherwise (and ρ_b without a shape-operator bend).
  double W_peak_membrane_biaxiality = std::numeric_limits<double>::quiet_NaN();
  double W_peak_bending_biaxiality = std::numeric_limits<double>::quiet_NaN();
  /// ρ/h of W_peak's thick-plate transition (peak_energy_density.h "Thick plates": the stencils
  /// against the shell's thickness), 0 where it does not apply; where it does, W_peak_kirchhoff_max
  /// is max W_peak with the cells' Kirchhoff factors (what a Kirchhoff shell's own rim peak, cutwork
  /// verify's, compares with), over the same faces; NaN otherwise.
  double W_peak_thick_scale = 0;
  double W_peak_kirchhoff_max = std::numeric_limits<double>::quiet_NaN();
};

struct EquilibriumSummary : EquilibriumScalars {
  Eigen::VectorXd energy_density;  ///< #F, J/m² (every face, filler included)
  Eigen::VectorXd peak_energy_density;  ///< #F, J/m²; empty without concentration samples
  /// #F, J/m²: W_peak with Kirchhoff's factors where the thick-plate transition applies; empty otherwise.
  Eigen::VectorXd peak_energy_density_kirchhoff;
};

/// `concentration_weight` (#F, optional): peak_energy_density's weight for W_peak (the cell
/// filter's blend where there is one); `cover` (optional): the stencils' cover by shape (the
/// factors by shape and by corner, peak_energy_density.h).
EquilibriumSummary summarize_equilibrium(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                         const Eigen::VectorXd* concentration_weight = nullptr,
                                         const ShapeCover* cover = nullptr);

/// S = Ŵ(x, α): ∂S/∂x = ∂Ŵ/∂x (fixed rows zero), ∂S/∂α = ∂Ŵ/∂α.
ObjectiveTerms strain_energy_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

/// S = f_ext(α)·(x − X): ∂S/∂x = f_ext (fixed rows zero), ∂S/∂α_t = (ρ h A_t g / 3)·Σ_{v∈t} u_v.
ObjectiveTerms compliance_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha);

}  // namespace cutwork::solvers

#pragma once
/// Thickness-integrated stiffness of an isotropic Kirchhoff–Love shell, derived from a Material.
///
/// Units (SI): μ and λ are membrane (thickness-integrated) Lamé parameters in N/m, D is the plate
/// bending stiffness in N·m (= J), the areal mass ρh in kg/m².
#include "host/scene/load_case.h"

namespace cutwork::solvers {

struct ShellStiffness {
  /// μ = E h / (2(1+ν))  (N/m): membrane shear modulus × thickness.
  double mu = 0;
  /// λ = E h ν / (1−ν²)  (N/m): the plane-stress Lamé parameter × thickness. Plane stress, not the
  /// 3D λ = Eν/((1+ν)(1−2ν)), because the shell's normal stress vanishes through the thickness.
  double lambda = 0;
  /// D = E h³ / (12(1−ν²))  (N·m): Kirchhoff plate bending stiffness.
  double bending = 0;
  /// ρ h (kg/m²): mass per rest area, for self-weight.
  double areal_mass = 0;
};

/// Stiffness of `material`. Throws InputError when E ≤ 0, ν ∉ [0, 0.5), h ≤ 0, ρ < 0, or any value is
/// not finite — the message names the field and the accepted range.
ShellStiffness shell_stiffness(const Material& material);

}  // namespace cutwork::solvers

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
///
/// The isotropic split (FillStiffnessCurve::split()). A scalar ratio scales the whole constitutive
/// matrix, so the perforated sheet keeps the solid's Poisson ratio. It does not: on the hexagonal
/// lattice of circles (ν = 0.4) the bending ν* is 0.09 at α = 0.5, 0.17 at 0.67, 0.28 at 0.85 (the
/// membrane ν* stays near 0.4). An isotropic sheet has two moduli, the bulk (equibiaxial) and the
/// shear (deviatoric) one; with the split, each element's energy is the sum of its bulk and shear
/// parts,
///     Ψ = μ tr(E²) + (λ/2) tr(E)² = μ |dev E|² + ((μ + λ)/2) tr(E)²              (membrane),
///     kᵀĈk = (1 − ν) |dev k|² + ((1 + ν)/2) tr(k)²                               (bending),
/// each scaled by its own g(α) = α r(α). On a hexagonal lattice (isotropic C*, D*) this is exact;
/// on another lattice it is the isotropic projection (cell_homogenisation.h). With equal bulk and
/// shear ratios it is the scalar rule. Under the scalar rule a cantilever, which bends with free
/// anticlastic curvature (stiffness ∝ E*), is given g = tr(D* D⁻¹)/3 = E*/E · [(1−ν)/(1−ν*) +
/// 2(1+ν)/(1+ν*)]/3: 8% too stiff at α = 0.5.
///
/// The square lattice's anisotropy (FillStiffnessCurve::anisotropic(), mechanics.lattice =
/// "square"). A sheet perforated on a square lattice has two deviatoric moduli: G₁ for a deviator
/// along the lattice's axes (C11 − C12)/2 and G₂ for one at 45° (C33). With e₁ = (E₁₁ − E₂₂)/2,
/// e₂ = E₁₂ in the lattice's frame its deviatoric energy is 2G₁e₁² + 2G₂e₂² = 2G(e₁² + e₂²) +
/// 2qG(e₁² − e₂²), G = (G₁ + G₂)/2, q = (G₁ − G₂)/(G₁ + G₂). The first term is the split's shear
/// part; the second is a third part of each membrane and shape-operator bend, the anisotropic one,
///     Ψ_A = 2μ [cos 4φ (e₁² − e₂²) + 2 sin 4φ e₁e₂]                                 (membrane),
///     kᵀĈ_A k = 2(1 − ν) [cos 4φ (e₁² − e₂²) + 2 sin 4φ e₁e₂],  e₁ = (k₁₁ − k₂₂)/2, e₂ = k₁₂   (bending),
/// in the face's frame, φ the angle of the lattice's axis from the frame's first axis, scaled by
/// g_A(α) = g_G(α) q(α). It is indefinite on its own; with the shear part it is 2G₁e₁² + 2G₂e₂²
/// in the lattice's frame, positive since |q| < 1 (q is interpolated by the same monotone cubic,
/// which stays within its samples).
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

/// Which part of an element a fill factor scales: the whole of it (the scalar rule, and always for
/// hinges), or its bulk, shear or (square lattice) anisotropic part (the split above).
enum class FillPart { Whole, Bulk, Shear, Anisotropy };

class FillStiffnessMap {
 public:
  /// The linear rule.
  FillStiffnessMap() = default;
  /// The linear rule for FillStiffness::Linear; the curve's rule for Homogenised. Throws
  /// InputError for a missing or malformed curve (not increasing, ratios not in (0, 1.5], last
  /// sample not α = 1 with ratios 1).
  explicit FillStiffnessMap(const MechanicsSettings& mechanics);

  bool linear() const { return m_membrane.empty(); }
  /// True when membranes and shape-operator bends are split into bulk and shear parts.
  bool split() const { return !m_membrane_bulk.empty(); }
  /// True when membranes and shape-operator bends also have an anisotropic part (square lattice).
  bool anisotropic() const { return !m_membrane_anisotropy.empty(); }
  /// g_m(α) (membrane) and dg_m/dα into `derivative` when not null.
  double membrane(double alpha, double* derivative = nullptr) const { return apply(m_membrane, alpha, derivative); }
  /// g_b(α) (bending) and dg_b/dα.
  double bending(double alpha, double* derivative = nullptr) const { return apply(m_bending, alpha, derivative); }
  /// r = g/α and dr/dα (membrane, bending).
  double membrane_ratio(double alpha, double* derivative = nullptr) const { return ratio(m_membrane, alpha, derivative); }
  double bending_ratio(double alpha, double* derivative = nullptr) const { return ratio(m_bending, alpha, derivative); }
  /// g and r of one part (Whole: the scalar curves above; Bulk, Shear: the split's, which must be
  /// present; Anisotropy: g_G q and r_G q, present when anisotropic()) of the membrane (bending
  /// false) or the bending.
  double factor(bool bending, FillPart part, double alpha, double* derivative = nullptr) const {
    if (part == FillPart::Anisotropy) return anisotropic_part(bending, alpha, derivative, true);
    return apply(curve(bending, part), alpha, derivative);
  }
  double part_ratio(bool bending, FillPart part, double alpha, double* derivative = nullptr) const {
    if (part == FillPart::Anisotropy) return anisotropic_part(bending, alpha, derivative, false);
    return ratio(curve(bending, part), alpha, derivative);
  }
  /// q(α) of the membrane or the bending and dq/dα (0 without anisotropy).
  double anisotropy(bool bending, double alpha, double* derivative = nullptr) const;

 private:
  double anisotropic_part(bool bending, double alpha, double* derivative, bool factor) const;
  static double apply(const MonotoneCurve& r, double alpha, double* derivative);
  static double ratio(const MonotoneCurve& r, double alpha, double* derivative);
  const MonotoneCurve& curve(bool bending, FillPart part) const {
    switch (part) {
      case FillPart::Bulk: return bending ? m_bending_bulk : m_membrane_bulk;
      case FillPart::Shear: return bending ? m_bending_shear : m_membrane_shear;
      case FillPart::Whole: case FillPart::Anisotropy: break;
    }
    return bending ? m_bending : m_membrane;
  }

  MonotoneCurve m_membrane, m_bending;
  MonotoneCurve m_membrane_bulk, m_membrane_shear, m_bending_bulk, m_bending_shear;
  MonotoneCurve m_membrane_anisotropy, m_bending_anisotropy;  ///< q
};

}  // namespace cutwork::solvers

#pragma once
/// What the mechanics needs from a scene, resolved onto one (simulation) mesh: plain arrays, no
/// JSON. Built by host/scene (resolve_load_case) and consumed by solvers/.
#include <vector>

#include "host/core/types.h"

namespace cutwork {

/// Isotropic shell material, SI units.
struct Material {
  double youngs_modulus = 1.7e9;   ///< E (Pa); default: laser-sintered PA12
  double poisson_ratio = 0.4;      ///< ν, in [0, 0.5)
  double thickness = 0.003;        ///< h (m)
  double density = 1010.0;         ///< ρ (kg/m³)
};

/// How the shell is modelled (scene section "mechanics").
enum class BendingModel {
  ShapeOperator,  ///< per-face discrete shape operator, Kirchhoff's energy with the material's ν (default)
  Hinge,          ///< the paper's discrete-shell hinges (8), kept to reproduce the paper's numbers
};

struct MechanicsSettings {
  BendingModel bending = BendingModel::ShapeOperator;
};

enum class SupportKind {
  Pinned,   ///< the selected vertices cannot move
  Clamped,  ///< pinned, and the surface's tangent plane along them cannot rotate
};

/// Supports and loads on a mesh with #V vertices.
struct LoadCase {
  /// #V: vertex positions that are fixed (pinned).
  std::vector<bool> fixed;
  /// #V: vertices whose rotation is clamped as well (a subset of `fixed`). How the mechanics
  /// realises a clamp on a hinge-based shell is documented in solvers/shell.
  std::vector<bool> clamped;
  /// #V×3 dead loads (N) that do not depend on the fill ratios: point, edge and area loads.
  RowMatX3d forces;
  /// Gravitational acceleration for self-weight (m/s²); zero when the scene has none. The
  /// self-weight of face t is α_t ρ h A_t g, lumped equally to its three vertices.
  Vec3 gravity = Vec3::Zero();
};

}  // namespace cutwork

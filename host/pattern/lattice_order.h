#pragma once
/// How a set of stencils is arranged: the bond-orientational order of their centres (Nelson and
/// Halperin's ψ₆, and ψ₄ for the square lattice), the check of the scene's `mechanics.lattice`.
///
/// The homogenised stiffness is calibrated on the lattice the scene states (hexagonal, the
/// arrangement of a blue-noise packing, or square along `mechanics.lattice_axis`); the model does
/// not measure it, because a lattice read from the stencils would change discontinuously as they
/// move. This measures it once, for the report. Per stencil i with three or more neighbours —
/// the centres within 1.3 times its nearest neighbour's distance (a square lattice's four at a, not
/// its diagonals at 1.41 a; a hexagonal lattice's six at a, not the next at 1.73 a) — with θ_ij the
/// angle of the neighbour's offset, projected onto the stencil's tangent plane, from the axis
/// (projected likewise),
///     ψ₄(i) = mean_j e^{4iθ_ij},   ψ₆(i) = mean_j e^{6iθ_ij}.
/// |ψ₄| = 1 and |ψ₆| = 0 on a square lattice, |ψ₄| = 0 and |ψ₆| = 1 on a hexagonal one; a
/// blue-noise packing gives both about 0.3–0.6. arg ψ₄ / 4 is the angle of the square lattice's
/// axes from the stated axis (in (−45°, 45°]).
#include <cmath>

#include "host/core/types.h"

namespace cutwork {

struct LatticeOrder {
  int stencils = 0;            ///< stencils measured (three or more neighbours)
  double square = NAN;         ///< median |ψ₄| over them (NaN: none measured)
  double hexagonal = NAN;      ///< median |ψ₆|
  /// Median |arg ψ₄| / 4 (degrees, in [0, 45]) over the stencils with |ψ₄| ≥ 0.5 whose tangent
  /// plane the axis is not normal to: how far the square lattice's axes are from the stated
  /// axis. NaN where no stencil qualifies.
  double axis_misfit = NAN;
};

/// The order of stencils centred at `centres` (#S×3, m) on a surface of unit normals `normals`
/// (#S×3) there, with angles from `axis` (a direction, projected onto each tangent plane).
/// Throws InputError for sizes that do not match or non-finite entries.
LatticeOrder measure_lattice_order(const RowMatX3d& centres, const RowMatX3d& normals, const Vec3& axis);

}  // namespace cutwork

#pragma once
/// How a set of stencils is arranged: the bond-orientational order of their centres (Nelson and
/// Halperin's ψ₆, and ψ₄ for the square lattice), the check of the scene's `mechanics.lattice`.
///
/// The homogenised stiffness is calibrated on the lattice the stencils perforate the shell on
/// (hexagonal, the arrangement of a blue-noise packing, or square along `mechanics.lattice_axis`).
/// The scene states it, or says "auto" (the default): then it is read here, once, from stencils
/// that are fixed — simulate's and verify's, a design's layout when its structural phase starts —
/// never as stencils move (a lattice read from moving stencils would switch the model
/// discontinuously under the optimiser). The reports measure the order of the final stencils too.
///
/// Per stencil i with three or more neighbours — the centres within 1.3 times its nearest neighbour's distance (a square lattice's four at a, not
/// its diagonals at 1.41 a; a hexagonal lattice's six at a, not the next at 1.73 a) — with θ_ij the
/// angle of the neighbour's offset, projected onto the stencil's tangent plane, from the axis
/// (projected likewise),
///     ψ₄(i) = mean_j e^{4iθ_ij},   ψ₆(i) = mean_j e^{6iθ_ij}.
/// |ψ₄| = 1 and |ψ₆| = 0 on a square lattice, |ψ₄| = 0 and |ψ₆| = 1 on a hexagonal one; a
/// blue-noise packing gives both about 0.3–0.6. arg ψ₄ / 4 is the angle of the square lattice's
/// axes from the stated axis (in (−45°, 45°]).
#include <cmath>
#include <span>

#include "host/core/types.h"
#include "host/scene/load_case.h"
#include "host/stencil/frame.h"

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
/// With `axes` (#S×3), each stencil's angles are measured from its own row instead (a lattice whose
/// axis follows the orientation field).
LatticeOrder measure_lattice_order(const RowMatX3d& centres, const RowMatX3d& normals, const Vec3& axis,
                                   const RowMatX3d* axes = nullptr);

/// The lattice the stencils lie on, read from them where the scene leaves it to them
/// (`mechanics.lattice` "auto"): square along `axis`, or not (the hexagonal lattice's isotropic
/// calibration, which is also that of a blue-noise packing).
///
/// The rule. Each stencil with |ψ₄| ≥ 0.5 gives its square lattice's axis in its tangent plane,
/// arg ψ₄ / 4 from a reference axis (of x, y, z the one least normal to the stencils). Of those
/// local axes (and their quarter turns), at most 64 spread over the stencils are tried as the one
/// axis of the scene, and the one whose projection best fits every stencil's axis (the sum of
/// |ψ₄| cos 4Δ) is kept; `order` is then measured from it. The stencils are on a square lattice
/// when `order.square` ≥ 0.7 and `order.hexagonal` < 0.5 (the rule of the reports' note) and
/// that one axis fits: its median misfit `order.axis_misfit` ≤ 10°. A square lattice turning over
/// the surface has no one axis; given the orientation field's direction at each stencil
/// (`tangents`, #S×3), such a lattice may follow the field: each stencil's axes measured from its
/// own t, at a constant angle δ₀ (arg Σ ψ₄ / 4) within a median 10° — `follows_field`, `square`
/// then set. Otherwise `turning` is set and `square` is not.
struct MeasuredLattice {
  bool square = false;
  bool turning = false;           ///< square order, but neither one axis nor the field fits it
  Vec3 axis = Vec3::UnitX();      ///< the best-fitting axis (unit; x where no stencil has |ψ₄| ≥ 0.5)
  LatticeOrder order;             ///< measured from `axis`
  bool follows_field = false;     ///< the axes are the field's direction turned by field_angle
  double field_angle = 0;         ///< δ₀ (rad, in (−π/4, π/4])
  double field_misfit = NAN;      ///< median misfit from it (degrees; NaN where not measured)
};
MeasuredLattice measure_lattice(const RowMatX3d& centres, const RowMatX3d& normals,
                                const RowMatX3d* tangents = nullptr);

/// The centres, unit normals and the field's directions t (#S×3) of `stencils` at their frames on
/// the surface (`bvh`, `field`): what the two measurements above read.
void stencil_frames(const FaceBvh& bvh, const TangentField& field, std::span<const StencilParams> stencils,
                    RowMatX3d& centres, RowMatX3d& normals, RowMatX3d* tangents = nullptr);

/// Sets mechanics.lattice_axis_at where mechanics.lattice_follows_field (clears it otherwise): the
/// field's direction at the closest point of the surface, turned by lattice_field_angle about the
/// normal there. `bvh` and `field` must outlive every copy of the settings that is used.
void attach_lattice_field(MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field);

}  // namespace cutwork

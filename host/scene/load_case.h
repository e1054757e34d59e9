#pragma once
/// What the mechanics needs from a scene, resolved onto one (simulation) mesh: plain arrays, no
/// JSON. Built by host/scene (resolve_load_case) and consumed by solvers/.
#include <array>
#include <cstdint>
#include <functional>
#include <limits>
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

/// How a partly cut face is weakened (scene key "mechanics.stiffness").
enum class FillStiffness {
  Linear,       ///< the paper's (9)–(10): stiffness ∝ the fill ratio α
  Homogenised,  ///< stiffness of a periodically perforated sheet with the same α (solvers/homogenise)
};

/// Effective stiffness of perforated material against its fill ratio, as samples of the ratios
/// r(α) = g(α)/α, where g(α) is the stiffness of a sheet perforated down to fill ratio α relative
/// to the solid sheet (g(α) = α for the linear rule, so r ≡ 1). Filled in by
/// solvers/homogenise (calibrate_fill_stiffness) before a shell model is built; plain numbers here.
/// Nodes of FillStiffnessCurve's concentration by biaxiality: ρ_j = −1 + 2j/(kBiaxialityNodes − 1).
inline constexpr int kBiaxialityNodes = 9;
inline constexpr double biaxiality_node(int j) { return -1.0 + 2.0 * j / (kBiaxialityNodes - 1); }
/// Nodes of a shape's concentration by the corner rule's radius (ShapeConcentration::*_by_corner),
/// in the stencil's bounding radii: ε_c = c/(kCornerNodes − 1), 0 to 1.
inline constexpr int kCornerNodes = 9;
inline constexpr double corner_node(int c) { return double(c) / (kCornerNodes - 1); }
/// Nodes of a shape's concentration by the tool's radius (FillStiffnessCurve::tool_cut), in the
/// stencil's bounding radii: τ_c = 2^(c − 6), 1/64 to 1/2 (K of a round grows about as 1/τ: K at a
/// star's tips 294, 145, 73, 35, 16 from 1/64 to 1/4 at α = 0.75; below 1/64 W_peak goes on with
/// the first interval's power law: solvers/objective/peak_energy_density.h, "K by the tool").
inline constexpr int kToolNodes = 6;
inline constexpr double tool_node(int c) { return 1.0 / double(1 << (kToolNodes - c)); }

struct FillStiffnessCurve {
  std::vector<double> alpha;     ///< sample fill ratios, strictly increasing, in (0, 1], last = 1
  std::vector<double> membrane;  ///< r_m at each sample (membrane stiffness / (α · solid)); last = 1
  std::vector<double> bending;   ///< r_b at each sample (bending stiffness / (α · solid)); last = 1
  /// Stress concentration K = peak / mean energy density over the material of the perforated sheet
  /// (membrane, bending) at each sample, ≥ 1; the last (α = 1) holds the dilute limit. Empty when
  /// not calibrated (solvers/objective/peak_energy_density.h says how they are used).
  std::vector<double> membrane_concentration, bending_concentration;
  /// K by the state's biaxiality (optional; empty: only the worst state's K above): per sample, K at
  /// each biaxiality node ρ_j = biaxiality_node(j) — the macroscopic state's principal stresses
  /// (membrane) or moments (bending) in the ratio (1, ρ), ρ ∈ [−1, 1] the smaller one in magnitude
  /// over the larger: −1 pure shear, 0 uniaxial, 1 equibiaxial — the largest over the state's
  /// orientation. kBiaxialityNodes values per sample; the last sample holds the dilute limit.
  std::vector<std::vector<double>> membrane_concentration_by_biaxiality, bending_concentration_by_biaxiality;
  /// The factors above are the worst over the shapes of positive weight (a face's fill ratio does
  /// not say which shape cut it). Each shape's own (optional; indexed by type, an empty entry for a
  /// shape that was not calibrated): with the shapes' covered fractions of each face
  /// (FillRatioEvaluator::covered_by_shape) W_peak mixes them per face instead
  /// (solvers/objective/peak_energy_density.h).
  struct ShapeConcentration {
    std::vector<double> membrane, bending;  ///< K at each sample, as membrane_concentration
    std::vector<std::vector<double>> membrane_by_biaxiality, bending_by_biaxiality;  ///< as above
    /// K by biaxiality with the rim within ε_c = corner_node(c) bounding radii of the shape's
    /// singular corners left out (cutwork verify's corner rule at the fabrication minimum feature,
    /// MechanicsSettings::corner_radius, in the stencil's own size; optional, empty: ε = 0 only):
    /// per sample kCornerNodes × kBiaxialityNodes values, corner node major; node 0 is the table
    /// above. With tool_cut, K of the hole a tool of radius τ_c = tool_node(c) bounding radii cuts
    /// (kToolNodes × kBiaxialityNodes per sample; node 0, τ = 1/64, is then the table above).
    std::vector<std::vector<double>> membrane_by_corner, bending_by_corner;
    bool empty() const { return membrane.empty(); }
  };
  std::vector<ShapeConcentration> shape_concentration;
  /// The shapes' factors by corner are the tool's (MechanicsSettings::tool_radius > 0): K of the
  /// holes opened by a disc of τ_c bounding radii (cell_homogenisation.h, "The tool's rounds"), read
  /// at every rim point, at the nodes tool_node(c); otherwise the corner rule's at corner_node(c).
  /// The stiffness ratios are the drawn holes' either way (the coarse model's fill ratios are).
  bool tool_cut = false;
  /// The isotropic split (optional; empty: the scalar rule above scales the whole of each element):
  /// r of the bulk (equibiaxial) and shear (deviatoric) moduli separately, membrane and bending,
  /// each (effective modulus / (α · solid modulus)); last = 1. A perforation softens the two modes
  /// differently — on the hexagonal lattice of circles at α = 0.5, bending bulk 0.46 and shear 0.90
  /// — so a scalar ratio gives the perforated sheet the solid's ν, which makes a cantilever of it
  /// 8% too stiff there (solvers/shell/fill_stiffness_map.h).
  std::vector<double> membrane_bulk, membrane_shear, bending_bulk, bending_shear;
  /// The square lattice's anisotropy (optional; empty on the hexagonal lattice, whose C* and D* are
  /// isotropic): q = (G₁ − G₂)/(G₁ + G₂) at each sample, membrane and bending, with G₁ the
  /// deviatoric modulus along the lattice's axes ((C11 − C12)/2) and G₂ the one at 45° to them
  /// (C33); |q| < 1, last (α = 1) = 0. The shear part's modulus G = (G₁ + G₂)/2 is the split's;
  /// the anisotropic part adds ±q G (solvers/shell/fill_stiffness_map.h). On the square lattice of
  /// circles at α = 0.5: membrane q = +0.57 (straight ligaments along the axes), bending −0.07.
  std::vector<double> membrane_anisotropy, bending_anisotropy;
  /// The weight each of the library's shapes (by type) had in the average the ratios are
  /// (solvers/homogenise/fill_stiffness_calibration.h: its share of the design's stencils by
  /// count; equal without stencils), summing to 1.
  std::vector<double> shape_weights;
  bool empty() const { return alpha.empty(); }
  bool split() const { return !membrane_bulk.empty(); }
  bool anisotropic() const { return !membrane_anisotropy.empty(); }
};

/// The lattice the stencils perforate the shell on (scene key "mechanics.lattice"): what the
/// homogenised stiffness is calibrated on (solvers/homogenise/cell_homogenisation.h).
enum class PerforationLattice {
  Hexagonal,  ///< the arrangement of a blue-noise packing; isotropic in the plane (default)
  Square,     ///< a square grid along mechanics.lattice_axis: stiffer in stretch along its axes
};

/// Where MechanicsSettings::lattice comes from.
enum class LatticeSource {
  Scene,     ///< stated by the scene ("hexagonal" or "square")
  Auto,      ///< "auto" (the default), not yet read: hexagonal until the stencils are known
  Stencils,  ///< "auto", read from the stencils (host/pattern/lattice_order.h measure_lattice)
};

/// Which fill ratio a face's stiffness is evaluated at (scene key "mechanics.filter").
enum class FillFilter {
  None,  ///< the face's own α (the paper's)
  Cell,  ///< α averaged over the stencil's cell where triangles do not resolve the stencils
         ///< (solvers/shell/cell_filter.h)
};

/// Where the coarse model puts a load spread over the surface (scene key "mechanics.loads").
enum class LoadSpread {
  Material,  ///< each face's share in proportion to the material in it, α_t a_t (SurfaceLoad; default)
  Area,      ///< by area whatever α (the paper's model, and cutwork's before the loads went onto the material)
};

struct MechanicsSettings {
  BendingModel bending = BendingModel::ShapeOperator;
  FillStiffness stiffness = FillStiffness::Linear;
  FillFilter filter = FillFilter::None;
  LoadSpread loads = LoadSpread::Material;
  /// The perforation's lattice, and for a square one the direction of one of its axes (a unit
  /// vector, projected onto each face's tangent plane; a face it is normal to takes the isotropic
  /// part only).
  PerforationLattice lattice = PerforationLattice::Hexagonal;
  Vec3 lattice_axis = Vec3::UnitX();
  /// Scene: as stated. Auto: the scene left it to the stencils, and they are not known yet (a
  /// run without stencils, or before them): hexagonal. Stencils: `lattice` and `lattice_axis` were
  /// read from fixed stencils (solvers/report/run_report.h measured_lattice: simulate's and verify's
  /// stencils, a design's layout when its structural phase starts).
  LatticeSource lattice_source = LatticeSource::Scene;
  /// The square lattice's axes follow the orientation field (scene "lattice_axis": "field", or
  /// "auto" reading stencils whose lattice turns with it): at a point, the field's direction t
  /// turned by lattice_field_angle (rad) about the normal. The model reads it through
  /// lattice_axis_at (a tangent direction at a point of the surface), which the host attaches
  /// (it holds the field: host/pattern/lattice_order.h attach_lattice_field); lattice_axis is
  /// then unused.
  bool lattice_follows_field = false;
  double lattice_field_angle = 0;
  std::function<Vec3(const Vec3& point)> lattice_axis_at;
  /// The calibrated curve; required (non-empty) when stiffness is Homogenised.
  FillStiffnessCurve stiffness_curve;
  /// The radius (m) at a stencil's corners W_peak reads its factors by corner at (corner_radius /
  /// the stencil's scale, ShapeConcentration): without a tool the radius about singular corners
  /// within which the rim is not read — the fabrication minimum feature, copied from the scene's
  /// fabrication.min_feature by parse_scene, as cutwork verify leaves those rim points out of the
  /// conforming peak (0: every rim point); with one, the tool's radius (its rounds).
  double corner_radius = 0;
  /// The radius (m) of the tool the part is cut with (fabrication.tool_radius; 0: as drawn). When
  /// positive the homogenised curve's factors by corner are the tool's (FillStiffnessCurve::tool_cut)
  /// and corner_radius is this radius.
  double tool_radius = 0;
};

enum class SupportKind {
  Pinned,    ///< the selected vertices cannot move
  Clamped,   ///< pinned, and the surface's tangent plane along them cannot rotate
  Symmetry,  ///< the boundary on a plane of mirror symmetry: held across the plane, its slope mirrored
};

/// A load spread over the surface (an area or pressure load, or a point load's patch) as the faces
/// inside its region carry it. `LoadCase::forces` holds it spread by area, as on a surface without
/// holes; the built shell carries it on its material (docs/SCENES.md "Loads over holes": the total
/// of the uncut region, spread over the material left), so a model of fill ratios α spreads it in
/// proportion to α_t a_t with the same total (ShellModel::external_forces):
///   f(α) = (Σ_t a_t / Σ_t α_t a_t) Σ_t α_t F_t,
/// which is `forces`' share Σ_t F_t where α ≡ 1 (a mesh with the holes cut).
struct SurfaceLoad {
  std::vector<int> faces;                  ///< the faces the region covers
  std::vector<double> areas;               ///< a_t: the region's area in each (m², > 0)
  std::vector<std::array<Vec3, 3>> nodal;  ///< F_t: the force on each of the face's vertices at α ≡ 1 (N)
};

/// Bits of LoadCase::held_axes: the global axes a vertex is held along.
inline constexpr std::uint8_t kHeldX = 1, kHeldY = 2, kHeldZ = 4, kHeldAll = 7;

/// Supports and loads on a mesh with #V vertices.
struct LoadCase {
  /// #V: vertex positions that are fixed (pinned).
  std::vector<bool> fixed;
  /// #V: vertices whose rotation is clamped as well (a subset of `fixed`). How the mechanics
  /// realises a clamp on a hinge-based shell is documented in solvers/shell.
  std::vector<bool> clamped;
  /// #V or empty (none): the global axes along which a vertex that is not `fixed` is held at its
  /// rest position, a bit mask (kHeldX | kHeldY | kHeldZ) — a support that lets the vertex slide
  /// along the other axes (a roller, a diaphragm, a bearing). 0: free. ShellModel treats a mask of
  /// all three axes as `fixed`.
  std::vector<std::uint8_t> held_axes;
  /// #V or empty (none): the planes of mirror symmetry a vertex lies on, bits as held_axes (kHeldX:
  /// the plane x = symmetry_planes.x()). Such a vertex is held along the plane's normal (its
  /// held_axes bit is set too) and slides in the plane; across a boundary edge whose two vertices lie
  /// on one plane the shape-operator bend continues the surface by its mirror image (a ghost node),
  /// so the slope across the plane is the mirrored one — the structure is modelled by its half
  /// (solvers/shell/shell_model.h). The structure's loads and supports must be symmetric too.
  std::vector<std::uint8_t> symmetry_axes;
  /// The coordinate of each axis's symmetry plane (x = symmetry_planes.x(), …); NaN where none.
  Vec3 symmetry_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  /// #V×3 dead loads (N) that do not depend on the fill ratios: point, edge and area loads.
  RowMatX3d forces;
  /// The loads among `forces` that are spread over the surface, face by face: a model of fill
  /// ratios moves them onto the material (SurfaceLoad). Empty: every load stays where `forces` has it.
  std::vector<SurfaceLoad> surface_loads;
  /// Gravitational acceleration for self-weight (m/s²); zero when the scene has none. The
  /// self-weight of face t is α_t ρ h A_t g, lumped equally to its three vertices.
  Vec3 gravity = Vec3::Zero();
  /// One per entry of the scene's loads: what the load was spread over — the area (m²) or length
  /// (m) inside its region, or the number of vertices of a `nearest` point load; 0 for
  /// self-weight. Lets another mesh carry the same totals (resolve_load_case's match_totals).
  std::vector<double> load_measures;
  /// True when fixed vertices are held away from their rest positions (the peak zoom's submodel,
  /// solvers/conforming/zoom_submodel.h, holds its border where a solved shell put it): that motion
  /// drives the shell, which then needs no load of its own. The caller starts the solver from those
  /// positions (EquilibriumSolver::restore_equilibrium): Newton leaves fixed rows as they are, but a
  /// restart from rest would put them back, so the caller checks they did not move.
  bool held_motion = false;
};

/// #V: vertices that a support holds along at least one axis (fixed, clamped, or `held_axes`).
inline std::vector<bool> supported_vertices(const LoadCase& lc) {
  std::vector<bool> out = lc.fixed;
  for (std::size_t v = 0; v < out.size(); ++v)
    out[v] = out[v] || (v < lc.clamped.size() && lc.clamped[v]) || (v < lc.held_axes.size() && lc.held_axes[v] != 0);
  return out;
}

/// #V: vertices that a support other than a symmetry plane holds along at least one axis — where a
/// clamped corner or a point support can make the exact field singular (a symmetry plane's hold is
/// the mirror image's continuation, not a support's edge).
inline std::vector<bool> support_held_vertices(const LoadCase& lc) {
  std::vector<bool> out = lc.fixed;
  for (std::size_t v = 0; v < out.size(); ++v) {
    const std::uint8_t held = v < lc.held_axes.size() ? lc.held_axes[v] : 0;
    const std::uint8_t mirror = v < lc.symmetry_axes.size() ? lc.symmetry_axes[v] : 0;
    out[v] = out[v] || (v < lc.clamped.size() && lc.clamped[v]) || (held & ~mirror) != 0;
  }
  return out;
}

}  // namespace cutwork

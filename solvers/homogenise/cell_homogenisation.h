#pragma once
/// Numerical homogenisation of a perforated sheet (issue 11, item 3): the effective membrane and
/// bending stiffness of a flat sheet carrying one stencil shape in a hexagonal lattice, as a
/// function of the fill ratio α (material area / gross area), computed with the shell's own
/// elements on a conforming mesh of the holes.
///
/// The cell problem. Stencils of one shape, angle 0, scale s with α = 1 − A_shape s² / A_cell, sit
/// on the hexagonal lattice a₁ = (1, 0), a₂ = (½, √3/2) (spacing a = 1, A_cell = √3/2; the arrangement
/// of a Poisson-disk packing, isotropic in the plane for a circle; or, with CellOptions::lattice,
/// the square lattice a₂ = (0, 1), A_cell = 1, whose period cell is the unit square and whose
/// stiffness is not isotropic: the calibration of the fill stiffness rule uses the hexagonal one,
/// the square one measures what a square arrangement differs by). The period cell is the rhombus
/// spanned by a₁, a₂ with the stencil at its centre: a regular triangular grid of spacing
/// 1/`resolution`, cut along the outline (host/cut) and remeshed (host/mesh/isotropic_remesh; the
/// outline and the rhombus's sides are kept, so opposite sides carry translated copies of each
/// other's vertices). A hole larger than the rhombus's inscribed circle (radius √3/4) crosses its
/// sides: then the 3 × 3 block of cells is cut by the nine copies of the hole and the centre cell's
/// pieces kept, so that what leaves through one side comes back through the opposite one. The cell is tiled 3 × 3 so that every face of the centre copy has its whole
/// shape-operator patch, and the displacement of each node is u = ū(X) + ũ(class): the macroscopic
/// field at the node's true position — in-plane u = ε̄ · X for the three membrane strains
/// ε̄ = (ε_xx, ε_yy, γ_xy), out of plane w = ½ Xᵀ κ̄ X for the three curvatures κ̄ = (κ_xx, κ_yy,
/// 2κ_xy) — plus a periodic fluctuation, one unknown per vertex of the cell modulo the lattice.
/// Minimising the energy of the centre copy's elements (the Hessians of the membrane and
/// shape-operator elements at rest: stretching and bending decouple on a flat sheet) over ũ is the
/// periodic cell problem; C*_ij = (1/A_cell) Σ_e u_iᵀ K_e u_j. A solid cell returns the closed forms
/// to round-off (both elements are exact for these fields). The hole's bounding circle must stay
/// inside the hexagonal (Voronoi) cell's inscribed circle of radius ½ — where a packing's bounding
/// circles touch — less a 10% ligament (a tenth of a spacing between neighbouring bounding circles,
/// meshed six triangles across), which bounds the fill ratios a shape reaches: α ≥ 0.27 for a
/// circle, 0.66 for the built-in star (0.40 and 0.71 while the hole had to stay inside the rhombus).

/// Scalar ratios. g = tr(C* C⁻¹)/3, C the solid's stiffness in the same (Voigt) notation: the mean
/// of the effective-to-solid ratio over the three modes, exact (= the factor) for an isotropic C*,
/// and invariant under rotating the lattice. r = g/α is what the fill stiffness rule stores
/// (fill_stiffness_map.h). The membrane and bending ratios do not depend on E or h (flat, linear).
///
/// Units: lengths in lattice spacings internally (a = 1); stiffness matrices in N/m (membrane,
/// C = E h/(1−ν²) [1 ν 0; ν 1 0; 0 0 (1−ν)/2]) and N·m (bending, D times the same matrix).
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/scene/load_case.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork::solvers {

/// The lattice the stencils perforate the cell problem's sheet on: hexagonal (a₂ = (½, √3/2), the
/// arrangement of a Poisson-disk packing; isotropic in the plane) or square (a₂ = (0, 1); C* and D*
/// have the square's symmetry: C11 = C22, no coupling of shear to stretch along the axes, and two
/// deviatoric moduli, (C11 − C12)/2 for a shear along the axes and C33 at 45° to them).
enum class CellLattice { Hexagonal, Square };

struct CellOptions {
  /// Target edges per lattice spacing a, in [6, 200]; raised (up to 200) where the narrowest
  /// ligament, 1 − 2s spacings between neighbouring bounding circles, would get fewer than six
  /// triangles across.
  double resolution = 24;
  int remesh_iterations = 5;
  /// Target edges per stencil bounding radius, at least, in [0, 64]: the resolution is raised (up to
  /// 200 per spacing) so that the rim recovery resolves the hole ("Reading the peak" below). 0: off.
  double rim_edges = 16;
  CellLattice lattice = CellLattice::Hexagonal;
  /// The hole as a tool of this radius cuts it (stencil bounding radii, in [0, 1]; 0: as drawn):
  /// the shape's polygon opened by the disc (host/stencil/stencil_opening.h; a hole the tool
  /// cannot cut at all is no hole), at the scale of the drawn shape at the fill ratio asked, and
  /// the cell refined about the tool's rounds to `round_edges` target edges per round radius ("The
  /// tool's rounds" above).
  double tool_radius = 0;
  /// Target edges per tool radius on the rounds, in [2, 32].
  double round_edges = 12;
};

/// Stress concentration in one macroscopic state of the cell (issue 21 item 5). A state is a
/// macroscopic stress σ̄ (membrane; Voigt σ_xx, σ_yy, τ_xy) or moment M̄ (bending; M_xx, M_yy, M_xy),
/// applied as the macroscopic strain ε̄ = C*⁻¹ σ̄ (κ̄ = D*⁻¹ M̄) of the homogenised cell, so that
/// "uniaxial" means what Kirsch's far field means. States: uniaxial along θ = 0°, 15°, …, 165°
/// (σ̄ = n⊗n, n = (cos θ, sin θ)); equibiaxial (σ̄ = 1); pure shear with principal axes at θ = 0°,
/// 22.5°, 45°, 67.5° (σ̄ = n⊗n − m⊗m, m ⊥ n). K = W_peak / W_mean, where
///   W_mean = ½ ε̄ᵀ C* ε̄ / window_fill_ratio: the cell's energy per area of its material;
///   W_peak = the larger of the rim's energy density and the faces' away from the rim.
///
/// Reading the peak. The rim is read by the rim recovery of the conforming verification
/// (solvers/conforming/rim_recovery.h: per free rim vertex a least-squares cubic of the nodal
/// displacements over a patch, ε_tt, κ_tt, κ_tm at the rim, smoothed along it), run on the tiled
/// cell under each of the six unit cases; a state's rim values are the cases' combined with ε̄
/// (the recovery is linear in the displacement at the small amplitude it is read at), and its W is
/// the free edge's (free_edge_strain.h: ½ E h ε_tt² for the membrane part, ½ D (1 − ν²) κ_tt² +
/// D (1 − ν) κ_tm² for the bending part). Faces within a rim point's patch are left to the rim:
/// their constant strains and shape-operator curvatures next to a free edge scatter with the faces'
/// shapes (the largest such face read Goodier's bending peak 1.2× on a dilute circle, and it
/// jumped between neighbouring α). The cell is meshed with at least `rim_edges` (16) target edges
/// per stencil bounding radius: the recovery's rim peak converges from below as the rim is refined
/// (circle at α = 0.95, 8 / 16 / 24 edges per radius: membrane uniaxial 7.75 / 8.08 / 8.11,
/// bending uniaxial 3.04 / 3.17 / 3.28, means over θ).
///
/// Biaxial states (CellStiffness's concentration by biaxiality): principal stresses (moments) (1, ρ)
/// along θ and θ + 90°, ρ at the kBiaxialityNodes nodes in [−1, 1], θ every 7.5°; each node the
/// largest over θ. Each state costs a pass over the cell's faces and rim points (the unit cases
/// are solved once): 432 states, well under the cell solve.
///
/// Closed forms (dilute circle, α = 0.99, ν = 0.4; the test StressConcentration.DiluteCircleMatches…):
///  - membrane, Kirsch: uniaxial 9, equibiaxial 2/(1 − ν), pure shear 8/(1 + ν);
///  - bending, Goodier (Kirchhoff plate, free hole; M_nn = 0 and the Kirchhoff shear vanish at
///    the rim, M_nt does not): uniaxial ((5 + 3ν)/(3 + ν))², at the rim where M_tt peaks;
///    equibiaxial 2/(1 − ν) (M_tt = 2M); pure shear 16/(3 + ν)², at 45° to the principal axes where
///    the rim's twist peaks (M_tt peaks at 8(1 + ν)/(3 + ν)² of the far field's W there);
///    biaxial (1, ρ), ρ ≥ 0: ((1 + ρ) + c(1 − ρ))²/(1 + ρ² − 2νρ), c = 2(1 + ν)/(3 + ν) — largest,
///    4.30, at ρ = 0.48: the worst bending state is biaxial. Membrane (1, ρ): (3 − ρ)²/(1 + ρ² − 2νρ).
/// Measured at 10.5 edges per radius (the resolution cap): membrane 8.53, 3.28, 5.38 (−5.2%,
/// −1.7%, −5.8%); bending 3.25, 3.27, 1.39 (−2.3%, −1.7%, +0.5%). The face-based bending reading it
/// replaces read 3.99 there (+20%) and 2.88 at α = 0.9 (on 4 edges per radius).
///
/// Singular corners. A polygon with sharp corners turning into the material (a star's tips) has an
/// unbounded stress there; rim points at corners turning past 30° are left out, and their neighbours
/// read a peak that grows as the rim is refined (star at α = 0.75, 10 / 16 / 24 edges per radius:
/// membrane uniaxial 4.6 / 8.5 / 11.8): the rim's resolution, R/16, acts as the tip's radius. A
/// smooth shape's rounds are not singular and converge (flower at α = 0.75: 12.4 / 15.5 / 16.2 at
/// 8 / 16 / 24). `cutwork verify` leaves out the rim within the fabrication minimum feature of a
/// corner (physical: 30° within a quarter of it). The cell does not know the design's stencil
/// size, so it reads K at every corner node ε_c (the rule's radius in the stencil's bounding radii)
/// and W_peak takes the node of each face's stencils, ε = g/s (peak_energy_density.h).
///
/// The tool's rounds (CellOptions::tool_radius τ). A part is cut by a tool of radius r, which rounds
/// every corner of a hole that turns into the material to radius r (stencil_opening.h); its peak is
/// finite and converges (cutwork verify --tool-radius). The cell then carries the opened hole: the
/// drawn shape's scale s at the fill ratio asked (α names the drawn outline, as the coarse model's
/// fill ratios do; the cell's own material fraction, window_fill_ratio, is what the tool leaves),
/// its polygon opened by τ = r/s, and the faces within two round radii of the rounds halved (the
/// peak zoom's focus passes, isotropic_remesh.h refine_about; the rounds of the eight neighbouring
/// holes are centres too, so a round that crosses a side is refined on both; a side vertex the
/// refinement left without its translated copy then splits the opposite side's edge, so that the
/// sides stay copies) down to τ s / round_edges. Every rim point is read (the tool leaves no corner
/// that turns into the material), and the faces the rounds graded are left to the rim as the faces
/// within a rim point's patch are (their shape-operator curvature next to faces of half their size
/// read a star's bending K 4× the rim's). A shape without a corner sharp at τ (a circle), or one no
/// disc of τ fits in (kept as drawn, as verify keeps it), is its drawn cell. Measured on the default
/// star at α = 0.75, uniaxial K_m at τ = 1/64: 264, 294, 298 at 6, 12, 24 edges per round radius
/// (bending 49.6, 52.6, 53.9); at 1/8: 32.8, 35.1, 35.7 (bending 9.2, 9.9, 10.1). 1.7–2.1 s a cell
/// at 12 (bench BM_ToolCell; the drawn cell 0.13 s).
/// Angles of the biaxial states of CellStiffness's concentration by biaxiality, over 180°.
inline constexpr int kBiaxialityAngles = 24;

struct ConcentrationState {
  std::string state;   ///< "uniaxial", "equibiaxial" or "shear"
  double angle = 0;    ///< θ (radians from x; 0 for equibiaxial)
  double factor = 1;   ///< K
};

struct CellStiffness {
  double fill_ratio = 0;             ///< α asked for
  double window_fill_ratio = 0;      ///< material area of the meshed cell / cell area (≈ α)
  double scale = 0;                  ///< stencil scale s (bounding radius) in lattice spacings
  Eigen::Matrix3d membrane = Eigen::Matrix3d::Zero();  ///< C* (N/m), Voigt (ε_xx, ε_yy, γ_xy)
  Eigen::Matrix3d bending = Eigen::Matrix3d::Zero();   ///< D* (N·m), Voigt (κ_xx, κ_yy, 2κ_xy)
  double membrane_factor = 0;        ///< g_m = tr(C* C⁻¹)/3
  double bending_factor = 0;         ///< g_b = tr(D* D⁻¹)/3
  /// The isotropic split (fill_stiffness_map.h): bulk and shear moduli of the isotropic projection
  /// of C* (isotropic_moduli) over the solid's, membrane and bending; tr(C* C⁻¹)/3 = (g_K + 2 g_G)/3
  /// where C* is isotropic.
  double membrane_bulk_factor = 0, membrane_shear_factor = 0;
  double bending_bulk_factor = 0, bending_shear_factor = 0;
  /// The anisotropy q = (G₁ − G₂)/(G₁ + G₂) of C* and D* (membrane, bending; lattice_anisotropy):
  /// 0 on the hexagonal lattice (to the cell's discretisation), the square lattice's otherwise.
  double membrane_anisotropy = 0, bending_anisotropy = 0;
  int vertices = 0, faces = 0;       ///< of the patch mesh
  double resolution = 0;             ///< edges per spacing the cell was meshed at (CellOptions)
  /// Stress concentration (see concentration_states): K = peak W / mean W over the cell's material,
  /// max over the membrane states and over the bending states, the biaxial ones below included (1
  /// for a solid cell). In bending the worst is a biaxial state, not one of the named ones.
  double membrane_concentration = 1, bending_concentration = 1;
  std::vector<ConcentrationState> membrane_states, bending_states;
  /// K by biaxiality (FillStiffnessCurve): at each node ρ_j = biaxiality_node(j), principal stresses
  /// (moments) (1, ρ_j) along θ and θ + 90°, the largest over θ = 0°, 7.5°, …, 172.5°
  /// (kBiaxialityAngles); kBiaxialityNodes values each. The node ρ = 0 holds the uniaxial states'
  /// largest, ρ = 1 the equibiaxial, ρ = −1 pure shear's (on a finer grid of angles than the states').
  std::vector<double> membrane_concentration_by_biaxiality, bending_concentration_by_biaxiality;
  /// K by biaxiality under the corner rule (FillStiffnessCurve::ShapeConcentration): at each corner
  /// node ε_c = corner_node(c) (in bounding radii), the rim points within ε_c of a singular corner
  /// left out, the corners found as cutwork verify finds them at the fabrication minimum feature g
  /// (singular_corners with a window of g/4, here ε_c/4 bounding radii); kCornerNodes ×
  /// kBiaxialityNodes values, corner node major, the first kBiaxialityNodes the table above.
  std::vector<double> membrane_concentration_by_corner, bending_concentration_by_corner;
};

/// The largest hole fraction 1 − α at which `shape` still fits the lattice: its bounding circle
/// within (1 − ligament) of the (Voronoi) cell's inscribed circle (radius ½ spacing on both lattices).
double max_hole_fraction(const StencilShape& shape, double ligament = 0.1,
                         CellLattice lattice = CellLattice::Hexagonal);

/// Whether the cell of `shape` cut by a tool of radius `tool_radius` bounding radii differs from its
/// drawn cell ("The tool's rounds": some point of the opening lies farther than τ/20 from the drawn
/// outline); when not, homogenise_cell with that tool is the drawn cell.
bool tool_changes_cell(const StencilShape& shape, double tool_radius);

/// Homogenised stiffness of `shape` perforating a sheet of `material` down to fill ratio α ∈
/// [1 − max_hole_fraction, 1]. Throws InputError for α outside that range or bad options.
CellStiffness homogenise_cell(const StencilShape& shape, const Material& material, double fill_ratio,
                              const CellOptions& options = {});

/// The bulk and shear moduli (K, G) of the isotropic projection of a Voigt stiffness C (strains
/// (e_xx, e_yy, γ_xy), or curvatures (κ_xx, κ_yy, 2κ_xy)): K = (C11 + C22 + 2 C12)/4, the
/// equibiaxial modulus, and G = [(C11 + C22 − 2 C12)/4 + C33]/2, the mean of the two deviatoric
/// moduli (equal for an isotropic C, and both invariant under rotating the lattice: a square
/// lattice's two differ, and G averages them). For the solid membrane K = μ + λ, G = μ
/// (shell_material.h); for the solid plate K = D (1 + ν)/2, G = D (1 − ν)/2.
Eigen::Vector2d isotropic_moduli(const Eigen::Matrix3d& C);

/// q = (G₁ − G₂)/(G₁ + G₂) of a Voigt stiffness C with the square's symmetry (axes along x and y):
/// G₁ = (C11 + C22 − 2 C12)/4, the modulus of a deviator along the axes, G₂ = C33, the one at 45°
/// (their mean is isotropic_moduli's G). 0 for an isotropic C.
double lattice_anisotropy(const Eigen::Matrix3d& C);

/// Closed-form solid stiffness (Voigt) of `material`: membrane C (N/m) and bending D (N·m).
Eigen::Matrix3d solid_membrane_stiffness(const Material& material);
Eigen::Matrix3d solid_bending_stiffness(const Material& material);

}  // namespace cutwork::solvers

#pragma once
/// A 3-D linear-elastic reference for a flat plate with holes: the stress at the holes' rims on the
/// plate's face, to check the shell model's peak factors where Kirchhoff's plate is not the part.
///
/// Why. The shell model is Kirchhoff's; its peak factors are read at holes of 1.5–100 mm and at a
/// tool's 0.5 mm rounds in shells 3–30 mm thick. Where a hole is not large against the thickness the
/// bending factor moves towards the membrane one of the same hole (Reissner's circle in bending:
/// Goodier's 1.79 for 2a ≫ t, about 3 for 2a ≪ t), which W_peak's thick-plate rule takes from
/// Roark's fit (solvers/objective/peak_energy_density.h "Thick plates"). This solver gives the
/// factor without a plate theory — quadratic tetrahedra through the thickness — and showed which
/// length the rule must read: the hole's size, not its rounds' radius (docs/DESIGN.md "Thick plates").
///
/// What.
///  - Mesh: CGAL's constrained Delaunay mesher on the plate's outline and holes, graded in plane
///    (edge `rim_edge` at the focus, growing by `growth` per unit distance to `max_edge`), extruded
///    into `layers` layers over half the thickness (thinner towards the face z = t/2 by
///    `layer_ratio`), each prism split into three tetrahedra by the smallest-global-index rule (the
///    diagonal of every quadrilateral side from its smallest vertex, so neighbouring prisms agree),
///    10-node tetrahedra with straight edges (mid-edge nodes shared between elements).
///  - Far field: a uniform membrane stress or a uniform moment state, imposed on the outer lateral
///    boundary as the exact 3-D solution of the solid plate under it (plate_exact_displacement), all
///    three components. Half the thickness is modelled, z ∈ [0, t/2]: bending is antisymmetric in z
///    (u_x = u_y = 0 on z = 0, u_z free), membrane symmetric (u_z = 0 on z = 0). The outer boundary
///    holds every rigid motion.
///  - Solve: isotropic elasticity, the element stiffness by the 4-point rule (exact for BᵀDB of a
///    straight quadratic tetrahedron, which is quadratic in the barycentrics), assembled in parallel
///    into the free unknowns' upper triangle (Dirichlet values eliminated into the right-hand side),
///    CHOLMOD's supernodal Cholesky (CholmodSolver).
///  - Output: at every rim node on the face z = t/2 the stress tensor averaged over the tetrahedra
///    at the node (each evaluated at the node: a quadratic element's stress is linear), the rim
///    tangent and σ_tt; the largest σ_tt on the face and through the thickness.
///
/// The exact far field. A uniform moment state gives σ_αβ(z) = z s_αβ with s = 12 M / t³ (a
/// surface stress ±6M/t² at z = ±t/2), σ_iz = 0: equilibrium holds (the stress does not vary in x, y
/// and has no z components) and the faces z = ±t/2 are traction free. Its strains are linear in z
/// (ε_αβ = z k_αβ, ε_zz = z k_3, k = the plane-stress compliance of s, k_3 = −ν (s_xx + s_yy)/E),
/// compatible, and integrate to
///     u_x = z (k_xx x + k_xy y),  u_y = z (k_xy x + k_yy y),
///     u_z = −(k_xx x² + 2 k_xy x y + k_yy y²)/2 + k_3 z²/2,
/// quadratic: the elements hold it exactly (the patch test in tests/solvers/solid). A membrane stress
/// σ gives u_α = e_αβ x_β, u_z = e_zz z (e its plane-stress strain).
///
/// Measured (tests/solvers/solid/solid_plate_test.cpp, ν = 0.3, a hole of radius a = 1 in a square
/// plate of half-width 12–15, rims at a/12 unless said):
///  - no hole: the exact membrane and bending fields to 1e-14 of the largest displacement;
///  - tension, t = a/10: k = 2.990 (Kirsch 3; 40k unknowns, 0.8 s);
///  - bending, 2a/t = 4: 1.859 (Roark's fit of Reissner 1.891, −1.7%; 1.879 at rims a/20);
///  - bending, 2a/t = 0.5: 2.22–2.24 on the face over meshes of 6–10 layers and rims a/10–a/20 (Roark
///    2.49: −10%); the largest σ_tt (2.25–2.26) lies just below the face. The same plate in tension
///    reads 2.56 on the face and 3.07 on the mid-plane: the free face lowers a hole's peak where the
///    plate is thick, which plate theories (Reissner's included) do not see.
/// The value on the face converges slowly (the hole's wall meets the face at a right-angled edge,
/// where the field is bounded but not smooth): thinner top layers lower it by about 1%, finer rims
/// raise it by about 1%.
///
/// Units are the caller's, consistently (lengths, stresses): the concentration factor k is a ratio.
#include <vector>

#include <Eigen/Core>

#include "host/core/types.h"

namespace cutwork::solvers {

enum class PlateLoadKind {
  Membrane,  ///< uniform in-plane stress through the thickness
  Bending,   ///< uniform moments: stress linear in z, zero on the mid-plane
};

/// The far-field state. Membrane: the in-plane stress σ_xx, σ_yy, σ_xy (stress units). Bending: the
/// moments per unit width M_xx, M_yy, M_xy (stress × length²), the face z = t/2 then carrying the
/// stress 6M/t². (One kind at a time: the half model uses the kind's symmetry; superpose solutions
/// for a mixed state.)
struct PlateLoad {
  PlateLoadKind kind = PlateLoadKind::Bending;
  double xx = 0, yy = 0, xy = 0;
};

/// Mesh controls (lengths in the plate's units).
struct SolidPlateMeshOptions {
  double rim_edge = 0;    ///< in-plane edge length at the focus (the rims); > 0
  double max_edge = 0;    ///< largest in-plane edge length; ≥ rim_edge
  double growth = 0.3;    ///< in-plane edge length h = rim_edge + growth · distance to the focus; > 0
  int layers = 4;         ///< tetrahedra layers over the half thickness; in [1, 64]
  double layer_ratio = 1; ///< each layer this times as thick as the one below it (< 1: thinner
                          ///< towards the face z = t/2, where the rims' peak is); in (0, 1]
  /// Points where the in-plane mesh is finest (e.g. a star's rounded tips); empty: the holes' rims.
  /// The holes' rims are written with edges of the size field there (their sharp corners kept).
  std::vector<Vec2> focus;
  /// A hole vertex turning by more than this (radians) is a corner the rim's resampling keeps.
  double corner_turn = 0.35;
};

struct SolidPlateInput {
  std::vector<Vec2> outer;               ///< the plate's outline: closed polygon, counter-clockwise
  std::vector<std::vector<Vec2>> holes;  ///< closed polylines (either orientation), inside `outer`,
                                         ///< disjoint; written as finely as their shape asks (they are
                                         ///< resampled along their length at the mesh's edge size)
  double thickness = 0;                  ///< t > 0; the plate is z ∈ [−t/2, t/2]
  double young = 1;                      ///< E > 0
  double poisson = 0.3;                  ///< ν in (−1, 0.5)
  PlateLoad load;
  SolidPlateMeshOptions mesh;
};

/// The stress at one rim node (a 2-D mesh vertex on a hole), on the face z = t/2.
struct RimStress {
  Vec2 position = Vec2::Zero();
  Vec2 tangent = Vec2::Zero();                      ///< unit, along the rim (counter-clockwise about the hole)
  Eigen::Matrix3d stress = Eigen::Matrix3d::Zero(); ///< averaged over the node's tetrahedra
  double sigma_tt = 0;                              ///< tangentᵀ σ tangent
};

struct SolidPlateResult {
  /// Per hole (input order), its rim nodes in order along the rim, on the face z = t/2.
  std::vector<std::vector<RimStress>> rims;
  double peak_sigma_tt = 0;              ///< the largest σ_tt on the face z = t/2
  int peak_hole = -1;                    ///< … on this hole
  Vec2 peak_position = Vec2::Zero();     ///< … here
  double peak_sigma_tt_any_z = 0;        ///< the largest σ_tt at any rim node of any layer
  double peak_z = 0;                     ///< … at this z (a membrane's 3-D peak may be inside)
  /// The far field's stress on the face z = t/2: its largest principal value (membrane: of σ;
  /// bending: of 6M/t²). k = peak_sigma_tt / nominal.
  double nominal = 0;
  double k = 0;

  // The discretisation and its cost.
  int vertices_2d = 0, triangles_2d = 0, tetrahedra = 0, nodes = 0;
  int dofs = 0;        ///< 3 × nodes
  int free_dofs = 0;   ///< the unknowns of the solve
  long factor_nonzeros = 0;
  double mesh_seconds = 0, assembly_seconds = 0, solve_seconds = 0;

  /// Every node's position (x, y, z ∈ [0, t/2]) and displacement: for checks against exact fields.
  std::vector<Vec3> node_positions, displacements;
};

/// Solves the half plate. Throws InputError for invalid input (see the fields' ranges; outlines of
/// fewer than 3 points, a hole outside the plate), SolveError when the stiffness is not positive
/// definite or the mesher fails.
SolidPlateResult solve_solid_plate(const SolidPlateInput& input);

/// The exact 3-D displacement of the solid plate (no holes) under `input.load` at `p` (see above);
/// zero at the origin, with zero rotation there.
Vec3 plate_exact_displacement(const SolidPlateInput& input, const Vec3& p);

/// The exact 3-D stress of the solid plate under `input.load` at height z.
Eigen::Matrix3d plate_exact_stress(const SolidPlateInput& input, double z);

/// A circle of `segments` points about `centre`, counter-clockwise.
std::vector<Vec2> circle_polyline(const Vec2& centre, double radius, int segments);

}  // namespace cutwork::solvers

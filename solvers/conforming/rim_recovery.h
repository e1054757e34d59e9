#pragma once
/// The energy density at the free rims of a conforming shell — the holes' outlines and the free
/// border — recovered from the faces around each rim vertex (issue 21 item 5: the peak at the
/// ligaments, converged).
///
/// Why. The elements hold constant membrane strain and constant curvature per face, each the mean
/// over the face (or over its edge-neighbour patch), so the largest face energy density next to a
/// rim lags the rim's own value by the gradient times the face's depth, and it scatters with the
/// shapes of the faces that happen to touch the rim: on the plate clamped on one side with one hole,
/// the largest face W read 0.580, 0.692, 0.674, 0.837 J/m² on four levels, each half the last
/// (vertex-averaged: 0.579, 0.685, 0.592, 0.694). A peak that jumps like that is no reference.
///
/// What. At every free rim vertex v (on a boundary loop, not supported):
///  1. Frame: the rest tangent t of the rim at v (along the loop, (X_next − X_prev) projected on
///     the vertex's tangent plane), the rest vertex normal n and the in-plane normal m = n × t.
///  2. Patch: the vertices within r of X_v reached from v through faces; r = `patch_radius` × the
///     mean length of v's edges, doubled until the patch holds four more vertices than the fit has
///     coefficients. Supported vertices take part with their zero displacement.
///  3. Fit: the rest positions X and the displacements u = x − X of the patch's vertices, component
///     by component, by the complete polynomial of degree `degree` in the rest tangent coordinates
///     (s, q) = ((X − X_v)·t, (X − X_v)·m) (least squares; the degree drops where the vertices
///     cannot determine it). The nodal positions are the accurate part of the solution; its
///     per-face strains and curvatures are not, next to a free edge (measured below).
///  4. Read at the vertex (s, q) = (0, 0), with x_,α = X_,α + u_,α:
///         ε_tt = ½ (|x_,s|² − |X_,s|²) / |X_,s|²                (Green–Lagrange, along t)
///         κ_tt = (n · x_,ss − n̄ · X_,ss) / |X_,s|²,   κ_tm = (n · x_,sq − n̄ · X_,sq) / (|X_,s| |X_,q|)
///     with n̄, n the unit normals X_,s × X_,q and x_,s × x_,q: the changes of the metric and of
///     the second fundamental form, as the elements measure them, exact under rigid motions of any
///     size (the solve is geometrically nonlinear: a linear t·u_,s reads −θ²/2 for a rotation θ).
///     On a flat rim of a hole κ_tt is the polar κ_θθ = w_,r / r + w_,θθ / r² (tᵀ ∇∇w t).
///  5. Free edge: a free rim carries no normal or shear traction and no normal moment
///     (σ_mm = σ_tm = 0, M_mm = 0), so only ε_tt, κ_tt and κ_tm are kept and the rest follows from
///     those conditions:
///         W = ½ E h ε_tt² + ½ D (1 − ν²) κ_tt² + D (1 − ν) κ_tm²     (J/m², D = E h³ / (12(1 − ν²)))
///     — the membrane part a uniaxial stress E ε_tt, the bending part Kirchhoff's energy with
///     κ_mm = −ν κ_tt, whose twist term Kirchhoff's free edge keeps (Goodier's hole in bending has
///     M_tm = −2 M₀ sin 2θ / (3 + ν) at the rim).
///
/// Measured (tests/solvers/conforming/rim_recovery_test.cpp: a hole of radius a in a 20a plate,
/// graded levels L = a, a/2, a/4 with rims at L/4; smoothed):
///  - tension: the recovered rim stress peaks at 0.83, 0.91, 0.986 × Howland's Kt_g, its RMS
///    against Kirsch along the rim 0.16, 0.056, 0.0055 of the peak; the largest face W next to the
///    rim reads 0.91, 1.06, 1.08 × the closed-form peak W;
///  - bending: the recovered M_tt is low by 18.9%, 9.8%, 3.1% on average against Goodier (first
///    order and better), the twist's RMS 1–5% of the peak, and the peak W reads 0.66, 0.83, 0.97 ×
///    the closed form, where the largest face W reads 1.63, 1.77, 1.48 × (the faces' own
///    curvatures next to a free edge scatter by 12% at every level).
/// Larger patches (three vertices per coefficient) bias the peaks low by 3–8% more; a quadratic
/// fit instead of the cubic, by 2–4% more.
/// A patch needs twice as many vertices as the fit has coefficients: with four more than that, a
/// one-sided cubic fit of 14 vertices read a twist 6× the closed form at one rim point in 60.
///
/// Singular points. Where the material's angle at a rim vertex (the sum of its faces' angles there)
/// exceeds 180° + `corner_angle` degrees, the rim turns into the material — a stencil's sharp tip,
/// a re-entrant corner — and linear elasticity's stress there is unbounded: a recovered value grows
/// without limit under refinement. Where a support ends along a free edge (a clamp's last vertex
/// next to a free one) the field may be singular too, depending on the corner's angle and the
/// support, and a clamp's root is not a ligament either. Rim points within `corner_radius` of such a
/// corner or `support_radius` of a support's end (m, fixed by the caller across refinement levels)
/// are marked `singular` and left out of the peak. `cutwork verify` takes the fabrication minimum
/// feature for corners (a printed tip is rounded at about that size; the level-0 edge length left
/// 85% of the chair's rim points out, its stars being a few edge lengths across) and the level-0
/// edge length for supports.
///
/// Outline segments. A smooth outline (a circle, a flower, the free arch of a vault) reaches the
/// conforming mesh as a polygon: a stencil's 64-gon, the base mesh's boundary. Each of its vertices
/// turns into the material by a few degrees, a re-entrant corner whose stress is weakly singular:
/// once the rim's triangles are finer than the polygon's segments, a reading over the mesh alone
/// grows at every vertex with every refinement (a 16-gon hole in tension: 2.80, 3.03, 3.54 σ∞ with
/// rims at a/8, a/16, a/32; on the default sheet's 0.2 m hole, whose 64-gon has 20 mm sides, the
/// peak grew 7–8% per halving below 1.5 mm). The shell the polygon stands for has no such corners,
/// so the patch radius r is at least `outline_radius` (1) × the outline's own segment about the
/// vertex: the arc length between the outline vertices on either side (vertices turning by more
/// than 1° and less than corner_angle; the mean of the two segments at an outline vertex; none
/// where either side ends at a corner or a support, or where the turns of the vertices between,
/// summed from the point, pass 1° first: a curve sampled finer than 1° per vertex, such as a
/// circle of 1024 segments after the remesher's collapses, has no corners to reach over). The
/// 16-gon then reads 2.907, 2.935, 2.950 σ∞
/// (RMS against Kirsch's circle 3.0%, 1.6%, 1.2%) and the sheet's peak settles (0.0626, 0.0630,
/// 0.0630 J/m² over the peak zoom's steps). Where the mesh is coarser than the outline (the usual
/// case on the levels: rims at L/4 against a 64-gon of a small stencil), nothing changes.
///
/// Smoothing (step 6). The values of neighbouring rim points scatter with the shapes of the faces
/// around them (on the table's default design, 1.5–2× between neighbours where a 1.2 mm ligament is
/// a few triangles wide). Each point's ε_tt, κ_tt, κ_tm are replaced by the value at its own arc
/// position of a quadratic least-squares fit, in arc length, through the rim points within its
/// patch radius (at least two on each side), along runs of free points that end at supports and
/// at corners turning by more than `corner_angle` either way (a corner's two sides differ). A
/// quadratic keeps a smooth peak; on the closed forms the smoothing moves the peak by −1 to −4%.
///
#include <vector>

#include "host/core/types.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

struct RimRecoveryOptions {
  int degree = 3;             ///< of the displacement fit; in [2, 4]
  double patch_radius = 2.5;  ///< r in units of the mean edge length at the vertex; > 0
  /// r is at least this many of the outline's own segments about the vertex (see "Outline
  /// segments" above); 0: the mesh alone sets r. In [0, 4].
  double outline_radius = 1.0;
  bool smoothing = true;      ///< the rim's quadratic fit in arc length (step 6)
  double nodes_per_coefficient = 2;  ///< a patch holds at least this many vertices per coefficient; [1.5, 10]
  double corner_angle = 30;   ///< degrees past 180° at which a rim vertex is a singular corner
  double corner_radius = 0;   ///< m: rim points this close to a singular corner are `singular`
  double support_radius = 0;  ///< m: … and this close to a support's end
  /// The singular corners, when the caller knows them better than the mesh does (the design's
  /// outline before remeshing: a coarse level turns a small circle into a hexagon, whose 60° turns
  /// are the mesh's, not the shell's); null: the mesh's own boundary vertices past corner_angle.
  const std::vector<Vec3>* corners = nullptr;
};

/// One free rim vertex and what was recovered there.
struct RimPoint {
  int vertex = -1;
  Vec3 position = Vec3::Zero();  ///< rest (m)
  Vec3 tangent = Vec3::Zero();   ///< unit rest tangent t
  double strain = 0;             ///< ε_tt (dimensionless)
  double curvature = 0;          ///< κ_tt (1/m; 0 where the fit fell to degree 1)
  double twist = 0;              ///< κ_tm (1/m)
  double energy_density = 0;     ///< W (J/m²)
  double material_angle = 0;     ///< degrees: the sum of the vertex's face angles
  bool singular = false;         ///< near a corner past corner_angle or a support's end
  bool at_corner = false;        ///< singular for a corner: within corner_radius of one
  int patch_nodes = 0;           ///< vertices in the fit
  int fit_degree = 0;            ///< the degree the fit used
  double patch_radius = 0;       ///< r of the patch (m)
};

/// The free rim points of `model` at positions x (#V×3, m), in boundary-loop order, for uncut
/// material (a conforming mesh: fill ratios 1). Whatever the bending element: only the nodal
/// positions are read. Throws InputError for bad options or positions.
std::vector<RimPoint> recover_rim(const ShellModel& model, const RowMatX3d& x, const RimRecoveryOptions& options = {});

/// The boundary vertices of (V, F) (#V×3 m, #F×3) where the material's angle (the sum of the face
/// angles there) exceeds 180° + corner_angle degrees — corners that turn into the material — or
/// where the turns into the material summed over the boundary vertices within `window` (m) of arc
/// centred there exceed corner_angle: an outline turning by that much within the window is, at that
/// scale, a corner (30° within 0.25 mm: a radius below about 0.48 mm; the bowl design's flower
/// petals end in tips of 0.39 mm radius, turning 15° per 0.1 mm segment, each segment alone below
/// corner_angle: a coarse level's remeshing merged them into vertices of 35–45°, and the peak zoom
/// read their stress rising 9%, then 22% per halving). 0: each vertex's own turn only.
std::vector<Vec3> singular_corners(const RowMatX3d& V, const RowMatX3i& F, double corner_angle, double window = 0);

/// The largest W over the rim points that are not singular (NaN with none), and its index in
/// `rim` (−1 with none).
struct RimPeak {
  double energy_density = NAN;
  int index = -1;
};
RimPeak rim_peak(const std::vector<RimPoint>& rim);

/// The same over the non-singular points within `radius` of any of `centres` (m).
RimPeak rim_peak_near(const std::vector<RimPoint>& rim, const std::vector<Vec3>& centres, double radius);

/// Where the rim peak may be: the non-singular points with W at least `fraction` of the rim peak,
/// largest first, each farther than `separation` (m) from those taken before; at most `count`.
std::vector<Vec3> rim_peak_candidates(const std::vector<RimPoint>& rim, double fraction, double separation, int count);

}  // namespace cutwork::solvers

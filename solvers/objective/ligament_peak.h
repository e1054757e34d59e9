#pragma once
/// The peak energy density at a narrow ligament between two holes (issue 21 item 5), which the
/// per-face W_peak (peak_energy_density.h) cannot see.
///
/// Why. W_peak's factors K(α) come from periodic cells: a lattice of one shape at the face's fill
/// ratio α, whose ligaments are as wide as that lattice's. A design's stencils are not a lattice: two
/// neighbours may leave a ligament far narrower than the lattice at the face's α would. On the
/// table's default design the conforming peak (57.0 J/m², settled) sits in a 1.16 mm ligament
/// between two circles of 26.9 mm radius on a leg, where W_peak reads 11.2: 5.1× low, on the unsafe
/// side. W_lig reads 60.5 there (docs/DESIGN.md "Narrow ligaments" has the six designs).
///
/// Two holes. A neck between two circular holes of radius R, w wide at its narrowest, widens as
/// w + s²/R along it; pulled along the neck (the tension perpendicular to the line of centres) it
/// carries a share of the load that the holes turn aside, and its rim stress grows without bound as
/// w → 0, as √(R/w) (the neck's compliance ∫ ds/(w + s²/R) = π√(R/w) sets its share; Callias and
/// Markenscoff's asymptotics of a narrow ligament). Measured on conforming meshes
/// (tests/solvers/conforming/ligament_test.cpp builds them: two holes in a 24R-wide plate, the
/// neck graded to w/20 and finer, the rim's energy density recovered as verify recovers it and, in
/// tension, also from the free rim edges' strains; converged to 0.5% between focus levels), the
/// neck's rim stress over the far field's, K(x), x = R/w, in tension (K_m: σ_tt/σ∞, 1024-gons) and
/// in bending (K_b: M_tt/M∞ from √(W/W∞), the plate bent about the line of centres by an edge load
/// on a cantilever, 240-gons; ν = 0.4):
///     x     0      1      2      4      8      16     32     64
///     K_m   3.00   3.39   4.20   5.71   8.08   11.59  16.80  24.34
///     K_b   1.82   2.47   3.06   4.08   5.53   7.62   10.71  14.84
/// (x = 0: Kirsch's and Goodier's single hole; the plate's finite width raises K by 1–4%). Beyond
/// x = 64 the tables go on as √x (16.80 → 24.34 is √2.10 per doubling, 10.71 → 14.84 √1.92).
/// Relative to its own single hole a bent neck concentrates more at moderate x (K_b/1.82 = 2.24 at
/// x = 4 against K_m/3 = 1.90) and about as much at large x (8.2 and 8.1 at x = 64).
///
/// Two holes of different radii ρ_a, ρ_b. The neck widens as w + s²/R_h, 1/R_h = (1/ρ_a + 1/ρ_b)/2
/// (the harmonic mean), and the two holes turn aside load in proportion to the pair's size S. The
/// asymptotics K ∝ S/√(R_h w) reduce to √(R/w) for equal holes, so the tables are read at
///     x = S²/(R_h w),   S = (ρ_a² + ρ_b²)/(ρ_a + ρ_b)   (the contraharmonic mean)
/// — S fitted, as a mean of the two radii, to conforming pairs in tension (the same meshes with
/// 240-gons, w = R/8 unless said): ρ_b/ρ_a = 0.5, 1.5, 2, 3 (w = R/16), 4 measured K_m = 8.29,
/// 10.73, 13.13, 25.75, 22.92, and this x reads 8.25, 9.64, 11.84, 24.84, 23.16 from the table:
/// −0.5%, −10%, −10%, −3.5%, +1% (the 4:1 pair, 8R across in a 24R plate, is raised by the
/// plate's finite width; read at x = R_h/w instead, the 2:1 pair gives 9.37, −29%).
///
/// Bent, the neck's shape alone sets it: the bending table is read at x_b = R_h/w. The same pairs
/// bent about the line of centres (M_tt/M∞; w = R/8, 3:1 at R/16) measured K_b = 4.64, 6.11, 6.52,
/// 9.84, 7.89 for ρ_b/ρ_a = 0.5, 1.5, 2, 3, 4, and 5.57 for the equal pair; x_b reads 4.62, 6.01,
/// 6.30, 9.30, 6.86 (−0.3%, −1.6%, −3.4%, −5.5%, −13%, the large pairs again near the plate's
/// width), where the membrane's x would read 5.63, 6.47, 7.77, 15.1, 14.2 (+21% to +81%). A hole
/// turns aside a plate's moments over a shorter reach than its membrane forces (Goodier's 1.82
/// against Kirsch's 3), so the second hole's size adds little to the neck's. The radii are the
/// rims' own about the closest points (host/export/min_feature.h's Ligament, each capped at its
/// hole's size), so a star's tip or a flower's petal counts by its own curvature.
///
/// The rule. A lattice of circles at fill ratio α on the hexagonal lattice of the cell problems
/// (cell_homogenisation.h) has ligaments of w_lat = p − 2R, 1 − α = (2π/√3)(R/p)², so
///     x_lat(α) = R/w_lat = (R/p)/(1 − 2R/p),   R/p = √((1 − α)√3/(2π))
/// (0 at α = 1; 3.6 at α = 0.3). The cell's K(α) already holds that lattice's ligament. A ligament
/// whose x exceeds x_lat(α) concentrates more, by the two-hole factors' ratio:
///     W_lig = max over the coarse faces t about the ligament of  W_peak_t · f_t,
///     f_t = max(1, (K_m(x)/K_m(x_lat))², (K_b(x_b)/K_b(x_lat))²),   x_lat = x_lat(α̃_t)
/// with α̃_t = α_t clamped to the calibrated curve's lowest sample (below it K(α) is held, so the
/// lattice it holds is the one at that sample), and "about the ligament" the
/// faces whose centroid lies within S of its midpoint (and the face nearest it). An uncut face
/// (α = 1, W_peak = W) gives the two holes' own K² × W: the far field times the pair's
/// concentration. The larger of the membrane and the bending ratio is taken (W_peak is not split
/// into its parts here): where the face's energy is the other part's, the estimate errs high.
/// The ratio takes the two holes' stress relative to their far field as the ligament's stress
/// relative to the lattice's: the rest of the lattice around the pair is taken as it is.
///
/// What it does not know.
///  - Direction: K is for the worst load, along the neck; a neck loaded across (the tension along
///    the line of centres) carries far less. The rule takes the worst, as the cell factors do.
///  - Thickness: a ligament narrower than the shell is thick is no plate (it twists as a beam);
///    neither this estimate nor a conforming Kirchhoff shell describes it. Reports count them.
/// It is a report quantity (design, verify), not an objective: its derivatives are not formed.
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "host/cut/cut_surface.h"
#include "host/export/min_feature.h"
#include "host/mesh/surface_mesh.h"
#include "host/scene/load_case.h"

namespace cutwork::solvers {

/// The rule above in a line, for reports.
inline constexpr const char* kLigamentPeakRule =
    "W_ligament = max over the coarse faces within S of a ligament's midpoint of W_peak_t (K(x)/K(x_lat(alpha_t)))^2 "
    "(at least W_peak_t; the larger of the membrane and the bending ratio), K the neck's rim factor of two "
    "circular holes measured on conforming meshes, "
    "x = S^2/(R_h w) in tension and R_h/w in bending (w the ligament's width, R_h and S the harmonic and "
    "contraharmonic means of the rims' radii of curvature there), x_lat(alpha) = R/w of the calibration's lattice of "
    "circles (mechanics.lattice: hexagonal or square) at the face's fill ratio; worst load direction";

/// K_m(x) and K_b(x) of the tables above (x ≥ 0; √x growth beyond 64).
double two_hole_concentration(double x);
double two_hole_bending_concentration(double x);

/// x = S²/(R_h w) of a ligament (+inf for w = 0): where the membrane table is read.
double pair_parameter(const Ligament& ligament);
/// x_b = R_h/w of a ligament (+inf for w = 0): where the bending table is read.
double bending_pair_parameter(const Ligament& ligament);

/// x_lat(α) = R/w_lat of the lattice of circles at fill ratio α (0 at α ≥ 1; +inf at or below the
/// touching fill ratio): hexagonal, R/a = √((1 − α)√3/(2π)), touching at 1 − π/(2√3); square,
/// R/a = √((1 − α)/π), touching at 1 − π/4 (its cell holds more hole at the same α, so its
/// ligaments are narrower). W_peak's concentration factors are the calibration lattice's, so the
/// lattice's own ligament is the one a pair's is compared with.
double lattice_ligament_parameter(double alpha, PerforationLattice lattice = PerforationLattice::Hexagonal);

/// One ligament's estimate.
struct LigamentPeak {
  int ligament = -1;         ///< index into the ligaments given
  double W = 0;              ///< J/m², the estimate W_lig
  double factor = 1;         ///< f_t at the face it was read on (≥ 1)
  double x = 0;              ///< S²/(R_h w) (membrane)
  double x_bending = 0;      ///< R_h/w (bending)
  double x_lattice = 0;      ///< x_lat(α̃) at that face
  double neck_radius = 0;    ///< R_h (m)
  double pair_radius = 0;    ///< S (m)
  int face = -1;             ///< the coarse face it was read on
  double W_peak_face = 0;    ///< W_peak there (J/m²)
  double alpha = 1;          ///< α there
};

/// The estimate of each ligament (same order), on the coarse mesh `sim` with per-face fill ratios
/// `alpha` and W_peak `W_peak` (#F each). `alpha_floor`: the lowest fill ratio the concentration
/// samples hold (0: none). Throws InputError for sizes that do not match.
std::vector<LigamentPeak> ligament_peaks(const SurfaceMesh& sim, const Eigen::VectorXd& alpha,
                                         const Eigen::VectorXd& W_peak, std::span<const Ligament> ligaments,
                                         double alpha_floor,
                                         PerforationLattice lattice = PerforationLattice::Hexagonal);

/// The ligaments searched: narrower than this × the smaller hole's size (find_ligaments), x ≥ 0.5
/// for two equal circles, where K_m is within 4% of Kirsch's 3. A dilute face (α → 1, x_lat → 0)
/// is raised by any second hole close by; a face at α = 0.3 only where x > x_lat = 3.6.
inline constexpr double kLigamentSearchWidth = 2.0;

/// A design's ligaments and their estimates.
struct LigamentPeakSummary {
  std::vector<Ligament> ligaments;  ///< narrowest first (find_ligaments)
  std::vector<LigamentPeak> peaks;  ///< one per ligament
  double W_max = std::numeric_limits<double>::quiet_NaN();  ///< the largest W_lig (NaN: no ligament)
  int worst = -1;                   ///< its index
  int narrower_than_thickness = 0;  ///< ligaments narrower than the shell is thick (no plate there)
};

/// find_ligaments on the cut surface `cut` of `base`, then ligament_peaks on the coarse mesh.
/// `thickness` (m) only counts the ligaments narrower than it. `mirror_planes`: the symmetry planes
/// (find_ligaments), so that a hole's ligament to its own image across one is looked at.
LigamentPeakSummary summarize_ligament_peaks(const CutSurface& cut, const SurfaceMesh& base, const SurfaceMesh& sim,
                                             const Eigen::VectorXd& alpha, const Eigen::VectorXd& W_peak,
                                             double alpha_floor, double thickness,
                                             PerforationLattice lattice = PerforationLattice::Hexagonal,
                                             const Vec3& mirror_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN()));

}  // namespace cutwork::solvers

#pragma once
/// Pattern objective terms of §4.2 on plain arrays: collision (1), boundary collision (2),
/// repulsion (3), growth (4) and their sum, the packing objective (5).
///
/// Arrays: positions #S×3 (m) — stencil centres; scales #S (m) — bounding-circle radii
/// r_i = s_i (a stencil shape has bounding radius 1). Gradients are ACCUMULATED (+=) into
/// #S×3 / #S arrays of the same shapes (pass nullptr to skip).
///
/// Units. The paper's terms are written in the units of its models; cutwork evaluates them in
/// units of a reference length ℓ (`unit`, m: the nominal stencil scale), i.e. every length is
/// divided by ℓ first. This makes P dimensionless and the same design in millimetres or metres
/// gives the same pattern; otherwise the formulas are the paper's:
///   (1) O_ij^coll  = ((1+s)(r_i+r_j) − d_ij)²            when positive part > 0
///   (2) O_i^bcoll  = ((1+s) r_i − d_ik)²                  when (1+s) r_i > d_ik
///   (3) O_ij^rep   = w_ij / d_ij² − w(ε)/ε²,  w = (ε√(2π))⁻¹ exp(−d²/(2ε²)),  d_ij < ε
///   (4) O_i^growth = −s_i
/// (3) is shifted by its value at the cut-off so that the term is continuous when a pair
/// crosses d = ε (the paper's hard cut-off would make P jump there, which breaks a line
/// search); the shift does not change any gradient inside the cut-off. Pairs are unordered
/// (each counted once). d_ik in (2) is the signed distance to the nearest open-boundary point
/// (negative outside), see boundary_distance.h.
#include <vector>

#include "host/core/types.h"
#include "host/pattern/boundary_distance.h"
#include "host/pattern/pattern_mirror.h"
#include "host/pattern/point_grid.h"

namespace cutwork {

/// Weights of the packing terms. The paper weighs them equally; cutwork defaults the collision
/// terms to 100 so that the growth term (a constant push of 1 per stencil) settles at an
/// overlap of ~1e-3 ℓ instead of ~1e-1 ℓ (balance: 2·w_coll·(1+s)·overlap·#contacts = 1);
/// the small residue is removed exactly by resolve_overlaps() after optimisation.
struct PackingWeights {
  double collision = 100.0;
  double repulsion = 1.0;
  double growth = 1.0;
};

/// Collision (1) over candidate pairs (a superset of the colliding pairs is fine: inactive
/// pairs contribute 0). Value in ℓ² units. `gap` (m, default 0): an absolute width of material
/// the pair must keep beyond its enlarged circles, Σ ((1+s)(r_i + r_j) + gap − d)₊² / ℓ² (the
/// structural phase's minimum feature, host/pattern/overlaps.h); the candidates must then reach
/// (1+s)·2·max r + gap.
double collision_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                           double safety, double unit, const std::vector<PointPair>& candidates,
                           RowMatX3d* d_positions, Eigen::VectorXd* d_scales, double gap = 0);

/// Boundary collision (2). The nearest boundary point of stencil i is searched within
/// (1+s) r_i + slack_i (slack: the distance by which an unprojected position may sit off the
/// surface; nullptr = 0), which finds it whenever the term is active for a point on the
/// surface or beyond its boundary.
/// With `gap` (m): ((1+s) r_i + gap − d_i)₊², searched within (1+s) r_i + gap + slack_i.
double boundary_collision_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                                    double safety, double unit, const BoundaryPolylines& boundary,
                                    const Eigen::VectorXd* slack, RowMatX3d* d_positions,
                                    Eigen::VectorXd* d_scales, double gap = 0);

/// Repulsion (3) over candidate pairs (pairs with d ≥ ε contribute 0). `epsilon` in m.
double repulsion_objective(const RowMatX3d& positions, double epsilon, double unit,
                           const std::vector<PointPair>& candidates, RowMatX3d* d_positions);

/// Collision (1) between the stencils and the mirror images of the others across symmetry planes
/// (pattern_mirror.h): ½ Σ over `pairs` of ((1+s)(r_i + r_j) + gap − |c_i − g_k c_j|)₊² / ℓ², the
/// gradient taken back through the reflection to c_j. A stencil's pair with its own image in a
/// single plane is skipped (plane_collision_objective's, signed); with a composition of planes it
/// is counted here. `pairs` from image_pairs at the candidate cut-off.
double image_collision_objective(const PatternMirror& mirror, const RowMatX3d& positions,
                                 const Eigen::VectorXd& scales, double safety, double unit,
                                 const std::vector<ImagePair>& pairs, RowMatX3d* d_positions,
                                 Eigen::VectorXd* d_scales, double gap = 0);

/// Each stencil against its own image in each single plane, with the signed distance δ to the
/// plane (negative beyond it, so an unprojected position that left the model is pushed back, as
/// the boundary term does): Σ 2 ((1+s) r_i + gap/2 − δ_i)₊² / ℓ², which is ½ of the pair term at
/// the distance 2δ.
double plane_collision_objective(const PatternMirror& mirror, const RowMatX3d& positions,
                                 const Eigen::VectorXd& scales, double safety, double unit,
                                 RowMatX3d* d_positions, Eigen::VectorXd* d_scales, double gap = 0);

/// Repulsion (3) between the stencils and the images, ½ per pair (own images included).
double image_repulsion_objective(const PatternMirror& mirror, const RowMatX3d& positions, double epsilon,
                                 double unit, const std::vector<ImagePair>& pairs, RowMatX3d* d_positions);

/// Growth (4): −Σ s_i / ℓ.
double growth_objective(const Eigen::VectorXd& scales, double unit, Eigen::VectorXd* d_scales);

/// The candidates' cut-off: max(ε, (1+s)·2·max r + gap).
double packing_cutoff(const Eigen::VectorXd& scales, double safety, double epsilon, double gap = 0);

/// Candidate pairs for (1) and (3): all pairs closer than packing_cutoff, from a uniform grid. The
/// twin below scans all pairs.
std::vector<PointPair> packing_candidates(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                                          double safety, double epsilon, double gap = 0);
std::vector<PointPair> packing_candidates_brute_force(const RowMatX3d& positions,
                                                      const Eigen::VectorXd& scales, double safety,
                                                      double epsilon, double gap = 0);

/// Parameters of the packing objective (5).
struct PackingSettings {
  double safety = 0.2;     ///< s
  double epsilon = 0.05;   ///< ε (m)
  double unit = 0.01;      ///< ℓ (m)
  PackingWeights weights;
};

/// Breakdown of one evaluation, in the same units as the total.
struct PackingTerms {
  double collision = 0, boundary = 0, repulsion = 0, growth = 0;
  double total() const { return collision + boundary + repulsion + growth; }
};

/// P^pack (5) with the weights: w_c (Σ O^coll + Σ O^bcoll) + w_r Σ O^rep + w_g Σ O^growth.
/// `boundary` may be empty (closed surface). Returns the total; `terms` (nullable) the parts.
/// With symmetry planes (`mirror`, nullable) the collision and repulsion add the images' terms
/// and the boundary the planes' (pattern_mirror.h): the whole's P divided by |G|.
double packing_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                         const PackingSettings& settings, const BoundaryPolylines& boundary,
                         const Eigen::VectorXd* slack, RowMatX3d* d_positions,
                         Eigen::VectorXd* d_scales, PackingTerms* terms = nullptr,
                         const PatternMirror* mirror = nullptr);

}  // namespace cutwork

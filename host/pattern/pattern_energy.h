#pragma once
/// The pattern objective P(p) of §4.2 as one function of the optimiser's variables: the
/// packing objective (5) or the DET objective (6) with its collision terms, evaluated at the
/// stencils' surface points c_i = Π(q_i), with the exact chain rule through the closest-point
/// projection. Used by the pattern-only phase and by the joint optimiser (19).
///
/// Variables: unprojected positions q (#S×3, m) and scales s (#S, m); angles do not enter P.
/// Terms:
///   packing:  w_c (Σ O^coll(c) + Σ O^bcoll(q)) + w_r Σ O^rep(c) + w_g Σ O^growth
///   exemplar: E^DET(c) + w_c (Σ O^coll(c) + Σ O^bcoll(q))        ("we augment the DET
///             objective by a term that explicitly penalizes collisions", §4.2)
///   both:     + w_t Σ |q_i − c_i|² / ℓ²   (projection tether)
/// On a surface with symmetry planes (PatternSurface::mirror) O^coll and O^rep add the pairs with
/// the stencils' mirror images and O^bcoll each stencil's pair with its own image in a plane, at q
/// (packing_objective.h): P is then the whole's divided by the number of its copies.
/// The boundary term is evaluated at the unprojected q with the signed distance, so a stencil
/// pushed beyond an open boundary during a line search is pulled back instead of sticking to
/// the boundary, where Π would hide the excursion. The tether keeps q near the surface (where
/// the excursion is invisible to Π otherwise); it vanishes whenever q lies on the surface,
/// which is the case at the start of every optimiser run and in every reported value.
#include <vector>

#include "host/pattern/det.h"
#include "host/pattern/packing_objective.h"
#include "host/pattern/pattern_surface.h"

namespace cutwork {

enum class PatternKind { Packing, Exemplar };

struct PatternEnergySettings {
  PatternKind kind = PatternKind::Packing;
  double safety = 0.2;       ///< s
  double epsilon = 0.05;     ///< ε (m), packing only
  double unit = 0.01;        ///< ℓ (m)
  PackingWeights weights;    ///< collision (both kinds), repulsion and growth (packing)
  double tether = 100.0;     ///< w_t
  /// Multiplies the collision, boundary and tether weights: the terms that keep a layout
  /// admissible rather than pleasing. The joint optimiser divides P by the stencil count and
  /// raises this by the same factor, so admissibility keeps its strength (structure_phase.h).
  double admissibility = 1.0;
  /// Material (m) the collision terms keep beyond the enlarged circles (packing_objective.h's
  /// gap): the structural phase sets fabrication.min_feature here while it runs, so that the
  /// optimiser already respects what the final overlap resolution enforces. 0 in the pattern phase.
  double gap = 0.0;
};

/// Values of the parts of one evaluation (same units as the total).
struct PatternTerms {
  double det = 0, collision = 0, boundary = 0, repulsion = 0, growth = 0, tether = 0;
  double total() const { return det + collision + boundary + repulsion + growth + tether; }
};

class PatternEnergy {
 public:
  /// `exemplar` is required for PatternKind::Exemplar and must outlive the energy.
  PatternEnergy(const PatternSurface& surface, const PatternEnergySettings& settings,
                const DetExemplar* exemplar = nullptr);

  const PatternEnergySettings& settings() const { return m_settings; }
  /// See PatternEnergySettings::admissibility.
  void set_admissibility(double factor) { m_settings.admissibility = factor; }
  /// See PatternEnergySettings::gap.
  void set_gap(double gap) { m_settings.gap = gap; }
  /// DET: matches every stencil of `layout` and freezes the neighbourhoods and frames used by
  /// evaluate() until the next call (the alternation of §4.2/MWT11). Packing: nothing. On symmetry
  /// planes a neighbourhood holds the mirror images within its radius too (their indices follow the
  /// layout's: S + n for image_sources()[n]), so that the half matches as its whole does.
  void rematch(const StencilLayout& layout);
  const std::vector<DetNeighborhood>& neighborhoods() const { return m_hoods; }
  /// The images the neighbourhoods hold: (stencil, reflection) per index S + n.
  const std::vector<std::pair<int, int>>& image_sources() const { return m_image_sources; }
  /// DET's type vote (det_vote_types) with a vote for an image counted for its stencil (in the whole,
  /// the image's neighbourhoods vote for the stencil as the stencil's vote for the image). Returns
  /// the number of changes.
  int vote_types(StencilLayout& layout) const;

  /// P at unprojected positions q (#S×3) and scales (#S), types (#S; DET type terms).
  /// Gradients are written (not accumulated) into d_q (#S×3) and d_scales (#S) when not null.
  double evaluate(const RowMatX3d& q, const Eigen::VectorXd& scales, const Eigen::VectorXi& types,
                  RowMatX3d* d_q, Eigen::VectorXd* d_scales, PatternTerms* terms = nullptr) const;

  /// P of a layout (positions already on the surface).
  double evaluate(const StencilLayout& layout, PatternTerms* terms = nullptr) const;

 private:
  const PatternSurface* m_surface;
  PatternEnergySettings m_settings;
  const DetExemplar* m_exemplar;
  std::vector<DetNeighborhood> m_hoods;
  int m_matched = 0;  ///< the layout's size at the last rematch
  std::vector<std::pair<int, int>> m_image_sources;
};

}  // namespace cutwork

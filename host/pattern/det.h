#pragma once
/// Discrete element textures on a surface (§4.2 eq. (6), §4.3; after Ma, Wei, Tong 2011).
///
/// Matching. For output stencil i, its neighbourhood N(i) holds the stencils j ≠ i within
/// R_i = r_N · size(exemplar) · σ_i of its centre, where σ_i = σ_0 · sizing(c_i) maps exemplar
/// units to metres (σ_0: the exemplar's scale on the surface, §4.4). Each c_j is brought into
/// the tangent plane of i by the distance-preserving projection q̂_j (§4.1), expressed in the
/// frame (t_i, b_i) of the orientation field — turned by 2πk/N for the rotation k being tried,
/// since an N-RoSy field defines t only up to 2π/N — and divided by σ_i. It is compared with
/// the neighbourhood of every exemplar element e whose neighbourhood disk lies inside the
/// exemplar's domain (patches touching the domain's boundary are never matched, §4.3): output
/// neighbours are assigned one-to-one to exemplar neighbours greedily by increasing cost
///   |u_j − (x_m − x_e)|² + (r_j/σ_i − r'_m)²  (in units of ℓ²)  + ξ [t_j ≠ t'_m],
/// pairs farther apart than one exemplar spacing left unassigned (an output neighbour without
/// a counterpart pays one spacing² in the match cost and exerts no force). The match is
/// one-way: exemplar elements without an output counterpart cost nothing (§4.3) — they are
/// what the incremental growth inserts. The best (e, k) wins; ties go to the lower index.
///
/// Energy (6), with the matches and frames frozen between matching steps (MWT11's alternation):
///   E = Σ_i Σ_{(j,m) matched in N(i)} |q̂_j − q_i − T_i(x_m − x_e)|²/ℓ² + (r_j − σ_i r'_m)²/ℓ²
///       + Σ_i (r_i − σ_i r'_e)²/ℓ² + ξ · #(type mismatches)
/// with T_i(v) = σ_i (v_x t_i + v_y b_i). The paper's (6) prints the position term as a
/// difference of a norm and a vector; this is the vector form of MWT11 that it abbreviates.
/// Lengths are in units of ℓ (see packing_objective.h). Positions are the stencil centres on
/// the surface; the type term is constant between matchings (types change by vote).
#include <vector>

#include "host/pattern/exemplar.h"
#include "host/pattern/pattern_surface.h"
#include "host/pattern/point_grid.h"

namespace cutwork {

struct DetSettings {
  double r_N = 0.3;        ///< neighbourhood radius, relative to the exemplar's size
  double xi = 1.0;         ///< type mismatch penalty ξ
  double sigma = 1.0;      ///< σ_0: metres per exemplar unit where sizing = 1
  double unit = 0.01;      ///< ℓ (m)
  int symmetry = 1;        ///< N of the orientation field: matching tries N rotations
  double safety = 0.2;     ///< s, for the growth's overlap test
};

/// Exemplar-side data for matching, precomputed once.
class DetExemplar {
 public:
  /// `stencil_types[t]` is the stencil type of exemplar type t (map_exemplar_types).
  /// Throws InputError when no element lies r_N·size inside the domain (no neighbourhood can
  /// be matched), naming the values and what to change.
  DetExemplar(Exemplar exemplar, std::vector<int> stencil_types, const DetSettings& settings);

  const Exemplar& exemplar() const { return m_ex; }
  const DetSettings& settings() const { return m_settings; }
  int num_elements() const { return int(m_ex.elements.size()); }
  /// Stencil type of element m.
  int stencil_type(int m) const { return m_types[size_t(m_ex.elements[size_t(m)].type)]; }
  /// Elements whose neighbourhood disk lies inside the domain (the matchable centres).
  const std::vector<int>& centers() const { return m_centers; }
  /// Elements m ≠ e within 1.25 R of centre e (matching candidates), by increasing distance.
  const std::vector<int>& neighbors(int e) const { return m_neighbors[size_t(e)]; }
  /// R = r_N · size (exemplar units).
  double radius() const { return m_radius; }
  /// Mean nearest-neighbour distance of the elements (exemplar units).
  double spacing() const { return m_spacing; }
  /// Distance from element m to its nearest other element (exemplar units).
  double nearest_distance(int m) const { return m_nearest[size_t(m)]; }
  /// Largest distance from a point of the domain's interior (one spacing inside its boundary)
  /// to the nearest element (exemplar units): a surface point farther than this from every
  /// stencil is "not covered".
  double covering_radius() const { return m_covering; }
  /// Elements per unit area.
  double density() const { return double(m_ex.elements.size()) / m_ex.area(); }

 private:
  Exemplar m_ex;
  std::vector<int> m_types;
  DetSettings m_settings;
  std::vector<int> m_centers;
  std::vector<std::vector<int>> m_neighbors;
  std::vector<double> m_nearest;
  double m_radius = 0, m_spacing = 0, m_covering = 0;
};

/// The frozen match of one output stencil's neighbourhood.
struct DetNeighborhood {
  int stencil = -1;                 ///< i
  int center = -1;                  ///< matched exemplar element e (-1: nothing matched)
  int rotation = 0;                 ///< k: the field frame turned by 2πk/N
  Vec3 normal = Vec3::UnitZ();      ///< frame at c_i (frozen)
  Vec3 tangent = Vec3::UnitX();
  Vec3 bitangent = Vec3::UnitY();
  double sigma = 1;                 ///< σ_i (frozen)
  std::vector<int> outputs;         ///< j ∈ N(i), ascending
  std::vector<int> matches;         ///< exemplar element of each j, −1 when unassigned
  double cost = 0;                  ///< match cost (ℓ² units, with ξ terms)
};

/// Matches stencil i given its neighbour ids (j ≠ i, within R_i; the caller queries them).
DetNeighborhood det_match_one(const DetExemplar& ex, const PatternSurface& surface,
                              const StencilLayout& layout, int i, const std::vector<int>& neighbors);

/// Matches every stencil (TBB-parallel over stencils; the result does not depend on threads).
/// With `centres` ≥ 0 only the first `centres` stencils are matched (one neighbourhood each); the
/// rest of `layout` are neighbours only (the mirror images across symmetry planes, pattern_energy.h).
std::vector<DetNeighborhood> det_match(const DetExemplar& ex, const PatternSurface& surface,
                                       const StencilLayout& layout, int centres = -1);

/// The DET energy (6) for frozen neighbourhoods at `positions` (#S×3, on the surface) and
/// `scales` (#S); gradients accumulated (+=) into d_positions (#S×3) and d_scales (#S)
/// (nullable). `types` (#S) counts the ξ mismatches.
double det_objective(const DetExemplar& ex, const std::vector<DetNeighborhood>& hoods,
                     const RowMatX3d& positions, const Eigen::VectorXd& scales,
                     const Eigen::VectorXi& types, RowMatX3d* d_positions,
                     Eigen::VectorXd* d_scales);

/// The distance-preserving projection of v = c_j − c_i into the tangent plane with normal n:
/// v_t |v| / |v_t| (v_t = v − (v·n) n), and its Jacobian w.r.t. v (nullable). v_t = 0 maps to 0.
Vec3 equidistant_offset(const Vec3& v, const Vec3& n, Eigen::Matrix3d* jacobian);

/// Type update by majority vote [MWT11]: every neighbourhood votes for the type of the
/// exemplar element matched to each of its members (and to its centre). Ties keep the current
/// type when it is among the winners, else the lowest type. Returns the number of changes.
int det_vote_types(const DetExemplar& ex, const std::vector<DetNeighborhood>& hoods,
                   StencilLayout& layout);

struct DetGrowthOptions {
  /// An exemplar element m is inserted when its distance to every stencil j is at least
  /// overlap_factor·(1+s)(r + r_j) and to the boundary overlap_factor·(1+s)·r ("the overlap
  /// with existing stencils is not significantly larger than our threshold", §4.3) ...
  double overlap_factor = 1.0;
  /// ... and at least spacing_factor·σ·(m's nearest-neighbour distance in the exemplar), so
  /// that where two grown patches meet out of phase the seam is not packed denser than the
  /// exemplar (the collision test alone would admit up to ~(1.3/0.8)² times its density).
  double spacing_factor = 0.9;
  /// Stop when the layout would exceed this many stencils (0: 4× the count the exemplar's
  /// density predicts, plus 100) — a guard against a degenerate exemplar.
  int max_stencils = 0;
};

struct DetGrowthReport {
  int added = 0;     ///< stencils inserted
  int seeds = 0;     ///< exemplar patches copied to uncovered places
  bool capped = false;
};

/// Incremental growth (§4.3): copies an exemplar patch to an uncovered place, then repeatedly
/// matches the stencils' neighbourhoods and inserts the unmatched exemplar elements that do not
/// collide, until no insertion is possible; a new patch is seeded wherever a point of the
/// surface (face centroids, in a seeded random order) is farther than h = 1.5·σ·covering_radius
/// from every stencil and from the open boundary (a gap along the boundary is where the
/// pattern ends), until none is. On an existing layout this fills holes (§6.3).
DetGrowthReport det_grow(const DetExemplar& ex, const PatternSurface& surface,
                         StencilLayout& layout, PatternRng& rng, const DetGrowthOptions& options);

}  // namespace cutwork

#pragma once
/// Broad phase of the fill-ratio pipeline: the candidate (stencil, triangle) pairs, from FaceBvh
/// ball queries, sorted by triangle, rebuilt incrementally as stencils move.
///
/// Why a 3-D ball suffices. The equidistant projection maps each triangle corner v to a point
/// at distance |v − c| from the stencil centre c, and the stencil lies inside its bounding
/// circle of radius s. A triangle whose corners and edges all stay far from c in 3-D therefore
/// projects far from the circle — up to the difference between the straight projected edge and
/// the projected straight edge. Precisely: if every point of a triangle is farther than R from
/// c and its corners lie within H of the stencil's tangent plane, its projection stays at
/// least sqrt(R² − H²) − H²/R from the centre. With R = s (1 + margin), margin = 0.1, that is
/// > s for H < 0.25 s: the candidate set is complete whenever the surface deviates from the
/// stencil's tangent plane by less than a quarter of the stencil radius near the boundary of
/// its ball — true for any stencil small against the surface's curvature radius. Extra pairs
/// cost one early exit in the clip kernel and contribute exactly zero.
///
/// Incremental rebuild: each stencil's query is made with slack, radius
/// R_q = s (1 + margin)(1 + slack), and reused while the ball it must cover, centre c and
/// radius s (1 + margin), stays inside the queried ball: |c − c_q| + s (1 + margin) ≤ R_q.
/// Only stencils that moved or grew beyond that are re-queried (in parallel).
#include <cstdint>
#include <span>
#include <vector>

#include "host/mesh/bvh.h"
#include "kernels/clip/clip.h"

namespace cutwork {

struct BroadPhaseOptions {
  double margin = 0.1;  ///< ball radius = s (1 + margin)
  double slack = 0.2;   ///< extra query radius, fraction of s (1 + margin); 0: exact queries
};

class BroadPhase {
 public:
  /// The BVH (and its mesh) must outlive the broad phase. Throws InputError for a negative or
  /// non-finite margin or slack.
  explicit BroadPhase(const FaceBvh& bvh, BroadPhaseOptions options = {});

  /// Brings the pairs up to date for stencils with surface centres `centers` and scales
  /// `scales` (m, bounding radii), both #S. A change in #S re-queries every stencil.
  /// Returns the number of stencils re-queried.
  int update(std::span<const Vec3> centers, std::span<const double> scales);
  /// Forgets every cached query (the next update re-queries all stencils).
  void clear();

  /// #P pairs sorted by (face, stencil).
  const std::vector<kernels::ClipPair>& pairs() const { return m_pairs; }
  /// #F+1: face f owns pairs [face_offsets[f], face_offsets[f+1]).
  const std::vector<int32_t>& face_offsets() const { return m_face_offsets; }
  /// #P: pair indices grouped by stencil (ascending stencil, then ascending face).
  const std::vector<int32_t>& stencil_pairs() const { return m_stencil_pairs; }
  /// #S+1: stencil s owns stencil_pairs[stencil_offsets[s] .. stencil_offsets[s+1]).
  const std::vector<int32_t>& stencil_offsets() const { return m_stencil_offsets; }
  const BroadPhaseOptions& options() const { return m_options; }

 private:
  void assemble();

  const FaceBvh* m_bvh;
  BroadPhaseOptions m_options;
  std::vector<std::vector<int>> m_faces_of;  ///< per stencil, ascending
  std::vector<Vec3> m_query_center;
  std::vector<double> m_query_radius;
  std::vector<kernels::ClipPair> m_pairs;
  std::vector<int32_t> m_face_offsets, m_stencil_pairs, m_stencil_offsets;
  std::vector<int> m_stale;        ///< scratch, kept to avoid reallocating per update
  std::vector<int32_t> m_cursor;   ///< scratch of the counting sort
};

/// Brute-force twin (every face against every stencil): the pairs (sorted by face, stencil)
/// whose face is within s (1 + margin) of the centre.
std::vector<kernels::ClipPair> candidate_pairs_brute_force(const SurfaceMesh& mesh,
                                                           std::span<const Vec3> centers,
                                                           std::span<const double> scales,
                                                           double margin);

}  // namespace cutwork

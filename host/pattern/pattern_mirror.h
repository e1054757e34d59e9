#pragma once
/// The symmetry planes a pattern's surface is the half (quarter, eighth) of: the stencils of the
/// whole are the layout's and their mirror images, so the pattern must see the images where a
/// boundary would otherwise stop it (a seam down the middle of the built shell).
///
/// The rule. A model on symmetry planes x_a = c_a (LoadCase::symmetry_planes, scene supports of type
/// "symmetry") stands for the whole: the layout and its images under the group G of reflections the
/// planes generate (|G| = 2, 4, 8; the planes are perpendicular, so the reflections commute and each
/// is its own inverse). A term of the pattern objective that sums over stencils or pairs of the whole
/// is |G| times one over the layout, where a pair of the whole between stencil i and the image g(c_j)
/// of stencil j counts ½ (for i ≠ j the pairs (i, g j) and (j, g i) are one pair of the whole seen from
/// both sides; for i = j the pair of i with its own image is shared by i and g(i)):
///     P_whole / |G| = P_layout + ½ Σ_{g ≠ e} Σ_{i, j} O(c_i, g c_j).
/// The open boundary of the layout then excludes the planes (they are no edge of the whole), and a
/// stencil keeps from a single plane what it keeps from its image: 2δ ≥ 2(1+s) r + gap, that is
/// δ ≥ (1+s) r + gap/2 — half the material a boundary asks for, since the ligament across the plane is
/// shared with the image. No stencil of an admissible layout crosses a plane, so the fill ratios of
/// the half need no images.
///
/// Here: the reflections and the image pairs; the objectives' image terms are in
/// packing_objective.h, the admissibility in overlaps.h, the initialisations in poisson_disk.cpp and
/// det.cpp. Not here: a DET neighbourhood does not reach across a plane (its one-way match leaves
/// the exemplar elements beyond the plane unmatched, which costs nothing).
#include <limits>
#include <vector>

#include "host/core/types.h"

namespace cutwork {

class PatternMirror {
 public:
  /// No planes.
  PatternMirror() = default;
  /// `planes`: x = planes.x(), …, NaN where none. `inside`: a point of the model, off every plane
  /// (it tells the model's side of each).
  PatternMirror(const Vec3& planes, const Vec3& inside);

  bool any() const { return !m_flips.empty(); }
  const Vec3& planes() const { return m_planes; }
  bool has_plane(int axis) const { return m_side[axis] != 0; }
  /// +1 when the model lies on the side x_axis ≥ c of plane `axis`, −1 when on x_axis ≤ c; 0: no plane.
  int side(int axis) const { return m_side[axis]; }
  /// The reflections other than the identity: one per plane and their compositions (1, 3 or 7).
  int num_reflections() const { return int(m_flips.size()); }
  /// The linear part of reflection k: diag(flip(k)), entries ±1.
  const Vec3& flip(int k) const { return m_flips[size_t(k)]; }
  /// Reflection k is one plane's (not a composition of two or three).
  bool single(int k) const { return (m_flips[size_t(k)].array() < 0).count() == 1; }
  /// The image of p under reflection k.
  Vec3 image(const Vec3& p, int k) const;
  /// Distance from p to plane `axis` (which must exist), positive on the model's side.
  double side_distance(const Vec3& p, int axis) const { return m_side[axis] * (p[axis] - m_planes[axis]); }
  /// The largest over reflection k's planes of side_distance: its image of p lies at least this far
  /// beyond one of them.
  double reach_of_image(const Vec3& p, int k) const;
  /// p lies on one of the planes within `tolerance` (m).
  bool on_a_plane(const Vec3& p, double tolerance) const;

 private:
  Vec3 m_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3i m_side = Eigen::Vector3i::Zero();  ///< +1 / −1: the model's side; 0: no plane
  std::vector<Vec3> m_flips;
};

/// Stencil i and the image of stencil j under reflection k, `distance` (m) apart.
struct ImagePair {
  int i = -1;
  int j = -1;
  int k = -1;
  double distance = 0;
};

/// Every (i, j, k) with |c_i − g_k(c_j)| ≤ cutoff, ordered ((i, g j) and (j, g i) both listed) and
/// with i = j (a stencil and its own image), sorted by (k, j, i). A uniform grid over the positions
/// (#S×3); the twin below scans all triples.
std::vector<ImagePair> image_pairs(const PatternMirror& mirror, const RowMatX3d& positions, double cutoff);
std::vector<ImagePair> image_pairs_brute_force(const PatternMirror& mirror, const RowMatX3d& positions,
                                               double cutoff);

}  // namespace cutwork

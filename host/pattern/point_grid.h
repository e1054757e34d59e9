#pragma once
/// Uniform-grid neighbourhood queries over a static point set (stencil centres): ball queries
/// and all pairs closer than a cutoff, without an all-pairs loop. Each query has a brute-force
/// twin (`*_brute_force`) used by the tests and by tiny inputs.
///
/// The grid is dense over the points' bounding box; when the box divided by the requested cell
/// size would give far more cells than points (a huge box with a tiny cutoff), the cell size is
/// enlarged so that the cell count stays O(#points) — queries stay exact, only slower.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "host/core/types.h"

namespace cutwork {

/// An unordered pair (i < j) of point indices and their distance (m).
struct PointPair {
  int i = -1;
  int j = -1;
  double distance = 0;
};

class PointGrid {
 public:
  PointGrid() = default;
  /// Builds the grid over `points` (#P×3, finite) with cells of edge ≥ `cell_size` (> 0, m).
  /// The points are copied.
  PointGrid(const RowMatX3d& points, double cell_size);

  int num_points() const { return int(m_points.rows()); }
  double cell_size() const { return m_cell; }

  /// Indices of the points with |p − center| ≤ radius, ascending. `out` is cleared first.
  void in_ball(const Vec3& center, double radius, std::vector<int>& out) const;

  /// All pairs (i < j) with |p_i − p_j| ≤ cutoff, sorted by (i, j).
  std::vector<PointPair> pairs_within(double cutoff) const;

 private:
  int64_t cell_index(int64_t x, int64_t y, int64_t z) const {
    return (z * m_dims[1] + y) * m_dims[0] + x;
  }
  void cell_coords(const Vec3& p, int64_t c[3]) const;

  RowMatX3d m_points;
  Vec3 m_origin = Vec3::Zero();
  double m_cell = 1;
  int64_t m_dims[3] = {1, 1, 1};
  std::vector<int> m_cell_start;  ///< #cells + 1 offsets into m_sorted (CSR)
  std::vector<int> m_sorted;      ///< point indices grouped by cell, ascending within a cell
};

/// A hash grid that grows by insertion (the initialisations add stencils one at a time).
/// Lookups only, never iteration over the hash map, so results do not depend on hashing.
class DynamicPointGrid {
 public:
  explicit DynamicPointGrid(double cell_size);
  /// Adds point `p` with id = the number of points inserted before it.
  int insert(const Vec3& p);
  int size() const { return int(m_points.size()); }
  const Vec3& point(int id) const { return m_points[size_t(id)]; }
  /// Ids of the points with |p − center| ≤ radius, ascending. `out` is cleared first.
  void in_ball(const Vec3& center, double radius, std::vector<int>& out) const;

 private:
  uint64_t key_of(const Vec3& p) const;
  double m_cell;
  std::vector<Vec3> m_points;
  std::unordered_map<uint64_t, std::vector<int>> m_buckets;
};

/// Brute-force twins (all pairs).
void in_ball_brute_force(const RowMatX3d& points, const Vec3& center, double radius,
                         std::vector<int>& out);
std::vector<PointPair> pairs_within_brute_force(const RowMatX3d& points, double cutoff);

}  // namespace cutwork

#include "host/pattern/point_grid.h"

#include <algorithm>
#include <cmath>

namespace cutwork {

PointGrid::PointGrid(const RowMatX3d& points, double cell_size) : m_points(points) {
  const int n = int(points.rows());
  m_cell = cell_size > 0 && std::isfinite(cell_size) ? cell_size : 1.0;
  if (n == 0) {
    m_cell_start.assign(2, 0);
    return;
  }
  const Vec3 lo = points.colwise().minCoeff().transpose();
  const Vec3 hi = points.colwise().maxCoeff().transpose();
  m_origin = lo;
  const Vec3 extent = hi - lo;
  // Keep the dense grid at O(#points) cells: enlarge the cells when the box is huge relative
  // to the requested size (queries stay exact).
  const double max_cells = 8.0 * n + 64.0;
  for (;;) {
    double cells = 1;
    for (int k = 0; k < 3; ++k) cells *= std::floor(extent[k] / m_cell) + 1;
    if (cells <= max_cells) break;
    m_cell *= std::cbrt(cells / max_cells) * 1.01;
  }
  for (int k = 0; k < 3; ++k) m_dims[k] = int64_t(std::floor(extent[k] / m_cell)) + 1;
  const int64_t num_cells = m_dims[0] * m_dims[1] * m_dims[2];

  std::vector<int64_t> key(n);
  for (int i = 0; i < n; ++i) {
    int64_t c[3];
    cell_coords(points.row(i).transpose(), c);
    key[i] = cell_index(c[0], c[1], c[2]);
  }
  m_cell_start.assign(size_t(num_cells) + 1, 0);
  for (int i = 0; i < n; ++i) ++m_cell_start[size_t(key[i]) + 1];
  for (int64_t c = 0; c < num_cells; ++c) m_cell_start[size_t(c) + 1] += m_cell_start[size_t(c)];
  m_sorted.resize(n);
  std::vector<int> fill(m_cell_start.begin(), m_cell_start.end() - 1);
  // Ascending point order inside each cell follows from visiting points in index order.
  for (int i = 0; i < n; ++i) m_sorted[fill[size_t(key[i])]++] = i;
}

void PointGrid::cell_coords(const Vec3& p, int64_t c[3]) const {
  for (int k = 0; k < 3; ++k) {
    const double t = std::floor((p[k] - m_origin[k]) / m_cell);
    c[k] = std::clamp<int64_t>(int64_t(std::clamp(t, -1e15, 1e15)), 0, m_dims[k] - 1);
  }
}

void PointGrid::in_ball(const Vec3& center, double radius, std::vector<int>& out) const {
  out.clear();
  if (m_points.rows() == 0 || !(radius >= 0)) return;
  int64_t lo[3], hi[3];
  cell_coords(center - Vec3::Constant(radius), lo);
  cell_coords(center + Vec3::Constant(radius), hi);
  const double r2 = radius * radius;
  for (int64_t z = lo[2]; z <= hi[2]; ++z)
    for (int64_t y = lo[1]; y <= hi[1]; ++y)
      for (int64_t x = lo[0]; x <= hi[0]; ++x) {
        const int64_t c = cell_index(x, y, z);
        for (int k = m_cell_start[size_t(c)]; k < m_cell_start[size_t(c) + 1]; ++k) {
          const int i = m_sorted[size_t(k)];
          if ((m_points.row(i).transpose() - center).squaredNorm() <= r2) out.push_back(i);
        }
      }
  std::sort(out.begin(), out.end());
}

std::vector<PointPair> PointGrid::pairs_within(double cutoff) const {
  std::vector<PointPair> pairs;
  std::vector<int> near;
  for (int i = 0; i < m_points.rows(); ++i) {
    const Vec3 p = m_points.row(i).transpose();
    in_ball(p, cutoff, near);
    for (int j : near)
      if (j > i) pairs.push_back({i, j, (m_points.row(j).transpose() - p).norm()});
  }
  return pairs;
}

namespace {
int64_t grid_coord(double x, double cell) {
  return int64_t(std::floor(std::clamp(x / cell, -1e15, 1e15)));
}
uint64_t grid_key(int64_t x, int64_t y, int64_t z) {
  // 21 bits per axis (wrapping): a collision merges two buckets, it never loses a point.
  const uint64_t m = (uint64_t(1) << 21) - 1;
  return (uint64_t(x) & m) | ((uint64_t(y) & m) << 21) | ((uint64_t(z) & m) << 42);
}
}  // namespace

DynamicPointGrid::DynamicPointGrid(double cell_size)
    : m_cell(cell_size > 0 && std::isfinite(cell_size) ? cell_size : 1.0) {}

uint64_t DynamicPointGrid::key_of(const Vec3& p) const {
  return grid_key(grid_coord(p.x(), m_cell), grid_coord(p.y(), m_cell), grid_coord(p.z(), m_cell));
}

int DynamicPointGrid::insert(const Vec3& p) {
  const int id = int(m_points.size());
  m_points.push_back(p);
  m_buckets[key_of(p)].push_back(id);
  return id;
}

void DynamicPointGrid::in_ball(const Vec3& c, double radius, std::vector<int>& out) const {
  out.clear();
  if (!(radius >= 0)) return;
  const int64_t x0 = grid_coord(c.x() - radius, m_cell), x1 = grid_coord(c.x() + radius, m_cell);
  const int64_t y0 = grid_coord(c.y() - radius, m_cell), y1 = grid_coord(c.y() + radius, m_cell);
  const int64_t z0 = grid_coord(c.z() - radius, m_cell), z1 = grid_coord(c.z() + radius, m_cell);
  const double cells = double(x1 - x0 + 1) * double(y1 - y0 + 1) * double(z1 - z0 + 1);
  const double r2 = radius * radius;
  if (cells > 4.0 * double(m_points.size()) + 64) {  // a huge ball: scanning is cheaper
    for (int i = 0; i < int(m_points.size()); ++i)
      if ((m_points[size_t(i)] - c).squaredNorm() <= r2) out.push_back(i);
    return;
  }
  for (int64_t z = z0; z <= z1; ++z)
    for (int64_t y = y0; y <= y1; ++y)
      for (int64_t x = x0; x <= x1; ++x) {
        auto it = m_buckets.find(grid_key(x, y, z));
        if (it == m_buckets.end()) continue;
        for (int i : it->second)
          if ((m_points[size_t(i)] - c).squaredNorm() <= r2) out.push_back(i);
      }
  std::sort(out.begin(), out.end());
  // Wrapped keys can list a bucket twice only if two cells of the ball share a key, which
  // needs a ball 2²¹ cells wide; the scan above covers that case.
}

void in_ball_brute_force(const RowMatX3d& points, const Vec3& center, double radius,
                         std::vector<int>& out) {
  out.clear();
  for (int i = 0; i < points.rows(); ++i)
    if ((points.row(i).transpose() - center).squaredNorm() <= radius * radius) out.push_back(i);
}

std::vector<PointPair> pairs_within_brute_force(const RowMatX3d& points, double cutoff) {
  std::vector<PointPair> pairs;
  for (int i = 0; i < points.rows(); ++i)
    for (int j = i + 1; j < points.rows(); ++j) {
      if ((points.row(j) - points.row(i)).squaredNorm() <= cutoff * cutoff)
        pairs.push_back({i, j, (points.row(j) - points.row(i)).norm()});
    }
  return pairs;
}

}  // namespace cutwork

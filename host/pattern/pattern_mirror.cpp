#include "host/pattern/pattern_mirror.h"

#include <algorithm>
#include <cmath>

#include "host/pattern/point_grid.h"

namespace cutwork {

PatternMirror::PatternMirror(const Vec3& planes, const Vec3& inside) : m_planes(planes) {
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (std::isfinite(planes[a])) {
      m_side[a] = inside[a] >= planes[a] ? 1 : -1;
      axes.push_back(a);
    }
  // Every non-empty subset of the planes' axes, by bit mask.
  const int n = int(axes.size());
  for (int mask = 1; mask < (1 << n); ++mask) {
    Vec3 f = Vec3::Ones();
    for (int b = 0; b < n; ++b)
      if (mask & (1 << b)) f[axes[size_t(b)]] = -1;
    m_flips.push_back(f);
  }
}

Vec3 PatternMirror::image(const Vec3& p, int k) const {
  Vec3 out = p;
  const Vec3& f = m_flips[size_t(k)];
  for (int a = 0; a < 3; ++a)
    if (f[a] < 0) out[a] = 2 * m_planes[a] - p[a];
  return out;
}

double PatternMirror::reach_of_image(const Vec3& p, int k) const {
  double r = -INFINITY;
  const Vec3& f = m_flips[size_t(k)];
  for (int a = 0; a < 3; ++a)
    if (f[a] < 0) r = std::max(r, side_distance(p, a));
  return r;
}

bool PatternMirror::on_a_plane(const Vec3& p, double tolerance) const {
  for (int a = 0; a < 3; ++a)
    if (m_side[a] != 0 && std::abs(p[a] - m_planes[a]) <= tolerance) return true;
  return false;
}

std::vector<ImagePair> image_pairs(const PatternMirror& mirror, const RowMatX3d& positions, double cutoff) {
  std::vector<ImagePair> out;
  const int S = int(positions.rows());
  if (!mirror.any() || S == 0 || !(cutoff > 0)) return out;
  const PointGrid grid(positions, cutoff);
  std::vector<int> near;
  for (int k = 0; k < mirror.num_reflections(); ++k)
    for (int j = 0; j < S; ++j) {
      const Vec3 cj = positions.row(j).transpose();
      // The image lies beyond a plane by at least this: no stencil of the model is nearer.
      if (mirror.reach_of_image(cj, k) > cutoff) continue;
      const Vec3 y = mirror.image(cj, k);
      grid.in_ball(y, cutoff, near);
      for (int i : near) out.push_back({i, j, k, (positions.row(i).transpose() - y).norm()});
    }
  return out;
}

std::vector<ImagePair> image_pairs_brute_force(const PatternMirror& mirror, const RowMatX3d& positions,
                                               double cutoff) {
  std::vector<ImagePair> out;
  const int S = int(positions.rows());
  for (int k = 0; k < mirror.num_reflections(); ++k)
    for (int j = 0; j < S; ++j) {
      const Vec3 y = mirror.image(positions.row(j).transpose(), k);
      for (int i = 0; i < S; ++i) {
        const double d = (positions.row(i).transpose() - y).norm();
        if (d <= cutoff) out.push_back({i, j, k, d});
      }
    }
  return out;
}

}  // namespace cutwork

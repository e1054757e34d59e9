#include "solvers/shell/cell_filter.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "host/core/error.h"

namespace cutwork::solvers {

double cell_filter_blend(double edge_over_diameter) {
  const double t = std::clamp((edge_over_diameter - 0.25) / 0.75, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

CellFilter::CellFilter(const SurfaceMesh& mesh, const Eigen::VectorXd& spacing, const Eigen::VectorXd& diameter,
                       const std::vector<bool>* keep_own, const Vec3& mirror_planes) {
  const int nf = mesh.num_faces();
  if (spacing.size() != nf || diameter.size() != nf || (keep_own && int(keep_own->size()) != nf))
    throw InputError(fmt::format("cell filter: {} spacings, {} diameters and {} marks for {} faces", spacing.size(),
                                 diameter.size(), keep_own ? keep_own->size() : size_t(nf), nf));
  for (int t = 0; t < nf; ++t)
    if (!(std::isfinite(spacing[t]) && spacing[t] > 0 && std::isfinite(diameter[t]) && diameter[t] > 0))
      throw InputError(fmt::format("cell filter: face {}: spacing {} and diameter {} must be finite and positive", t,
                                   spacing[t], diameter[t]));

  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  const Eigen::VectorXd& area = mesh.face_areas();
  RowMatX3d centroid(nf, 3);
  for (int t = 0; t < nf; ++t) centroid.row(t) = (V.row(F(t, 0)) + V.row(F(t, 1)) + V.row(F(t, 2))) / 3.0;
  const RowMatX3i& face_edges = mesh.face_edges();
  const RowMatX2i& edge_faces = mesh.edge_faces();

  m_blend.resize(nf);
  m_resolution.resize(nf);
  std::vector<std::vector<std::pair<int, double>>> rows(static_cast<size_t>(nf));
  // Per thread: the faces a row has marked (`seen`, unmarked through `visited` after each row).
  tbb::enumerable_thread_specific<std::vector<char>> marks(size_t(nf), char(0));
  tbb::parallel_for(tbb::blocked_range<int>(0, nf, 64), [&](const tbb::blocked_range<int>& range) {
    std::vector<int> stack;
    std::vector<int> visited;
    std::vector<char>& seen = marks.local();
    for (int t = range.begin(); t != range.end(); ++t) {
      const double h = std::sqrt(4 * area[t] / std::sqrt(3.0));
      const double blend = cell_filter_blend(h / diameter[t]);
      m_resolution[t] = 1 - blend;
      const double b = keep_own && (*keep_own)[size_t(t)] ? 0.0 : blend;
      m_blend[t] = b;
      auto& row = rows[size_t(t)];
      if (b == 0) {
        row.emplace_back(t, 1.0);
        continue;
      }
      const double R = std::max(spacing[t], h);
      const Vec3 ct = centroid.row(t).transpose();
      // The cone's centre and its images in the symmetry planes (every combination of them: a
      // quarter's corner has three), where they come within R of the half.
      std::array<Vec3, 8> centres;
      centres[0] = ct;
      int num_centres = 1;
      for (int a = 0; a < 3; ++a) {
        if (!std::isfinite(mirror_planes[a]) || std::abs(ct[a] - mirror_planes[a]) >= R) continue;
        for (int i = 0, n = num_centres; i < n; ++i) {
          centres[size_t(num_centres)] = centres[size_t(i)];
          centres[size_t(num_centres)][a] = 2 * mirror_planes[a] - centres[size_t(i)][a];
          ++num_centres;
        }
      }
      const auto within = [&](const Vec3& c) {
        for (int i = 0; i < num_centres; ++i)
          if ((c - centres[size_t(i)]).norm() < R) return true;
        return false;
      };
      // Faces reached across edges whose centroids lie within R (a connected neighbourhood).
      stack.assign(1, t);
      visited.assign(1, t);
      seen[size_t(t)] = 1;
      double total = 0;
      std::vector<std::pair<int, double>> weights;
      while (!stack.empty()) {
        const int s = stack.back();
        stack.pop_back();
        // A marked face's material is its own: no other face's cell counts it (the file comment).
        if (s == t || !(keep_own && (*keep_own)[size_t(s)])) {
          double w = 0;
          for (int i = 0; i < num_centres; ++i)
            w += area[s] * std::max(0.0, 1 - (centroid.row(s).transpose() - centres[size_t(i)]).norm() / R);
          weights.emplace_back(s, w);
          total += w;
        }
        for (int k = 0; k < 3; ++k) {
          const int e = face_edges(s, k);
          for (int side = 0; side < 2; ++side) {
            const int n = edge_faces(e, side);
            if (n < 0 || seen[size_t(n)]) continue;
            seen[size_t(n)] = 1;
            visited.push_back(n);
            if (within(centroid.row(n).transpose())) stack.push_back(n);
          }
        }
      }
      for (int v : visited) seen[size_t(v)] = 0;
      std::sort(weights.begin(), weights.end());
      for (auto& [s, w] : weights) row.emplace_back(s, b * w / total + (s == t ? 1 - b : 0.0));
    }
  });

  std::vector<Eigen::Triplet<double>> triplets;
  for (int t = 0; t < nf; ++t)
    for (const auto& [s, w] : rows[size_t(t)]) triplets.emplace_back(t, s, w);
  m_matrix.resize(nf, nf);
  m_matrix.setFromTriplets(triplets.begin(), triplets.end());
  m_transpose = m_matrix.transpose();
}

Eigen::VectorXd CellFilter::apply(const Eigen::VectorXd& alpha) const {
  if (identity()) return alpha;
  if (alpha.size() != m_matrix.cols())
    throw InputError(fmt::format("cell filter: {} fill ratios for {} faces", alpha.size(), m_matrix.cols()));
  return m_matrix * alpha;
}

Eigen::VectorXd CellFilter::pull_back(const Eigen::VectorXd& gradient) const {
  if (identity()) return gradient;
  if (gradient.size() != m_matrix.rows())
    throw InputError(fmt::format("cell filter: {} gradient entries for {} faces", gradient.size(), m_matrix.rows()));
  return m_transpose * gradient;
}

double CellFilter::mean_row_size() const {
  if (identity() || m_matrix.rows() == 0) return 1;
  return double(m_matrix.nonZeros()) / double(m_matrix.rows());
}

}  // namespace cutwork::solvers

#include "solvers/objective/shape_cover.h"

#include <vector>

namespace cutwork::solvers {

namespace {

/// ε_i = r / s_i and dε_i/ds_i = −ε_i / s_i.
void corner_radii(std::span<const StencilParams> stencils, double corner_radius, std::vector<double>& epsilon,
                  std::vector<double>* slope = nullptr) {
  epsilon.resize(stencils.size());
  if (slope) slope->resize(stencils.size());
  for (size_t i = 0; i < stencils.size(); ++i) {
    epsilon[i] = corner_radius / stencils[i].scale;
    if (slope) (*slope)[i] = -epsilon[i] / stencils[i].scale;
  }
}

Eigen::MatrixXd filtered(const CellFilter& filter, Eigen::MatrixXd m, bool transpose) {
  if (filter.identity()) return m;
  for (Eigen::Index k = 0; k < m.cols(); ++k)
    m.col(k) = transpose ? filter.pull_back(m.col(k)) : filter.apply(m.col(k));
  return m;
}

}  // namespace

ShapeCover shape_cover(const FillRatioEvaluator& evaluator, std::span<const StencilParams> stencils,
                       double corner_radius, const CellFilter& filter) {
  ShapeCover cover;
  cover.covered = filtered(filter, evaluator.covered_by_shape(), false);
  if (corner_radius > 0) {
    std::vector<double> epsilon;
    corner_radii(stencils, corner_radius, epsilon);
    cover.corner = filtered(filter, evaluator.covered_by_shape(epsilon), false);
  }
  return cover;
}

void shape_cover_pullback(const FillRatioEvaluator& evaluator, std::span<const StencilParams> stencils,
                          double corner_radius, const CellFilter& filter, const ShapeCover& d_cover,
                          Eigen::VectorXd& d_params) {
  d_params.setZero(5 * Eigen::Index(stencils.size()));
  if (d_cover.covered.size() > 0) evaluator.pullback_by_shape(filtered(filter, d_cover.covered, true), d_params);
  if (d_cover.corner.size() > 0 && corner_radius > 0) {
    std::vector<double> epsilon, slope;
    corner_radii(stencils, corner_radius, epsilon, &slope);
    Eigen::VectorXd corner;
    evaluator.pullback_by_shape(filtered(filter, d_cover.corner, true), corner, epsilon, slope);
    d_params += corner;
  }
}

}  // namespace cutwork::solvers

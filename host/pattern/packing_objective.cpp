#include "host/pattern/packing_objective.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cutwork {

double collision_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                           double safety, double unit, const std::vector<PointPair>& candidates,
                           RowMatX3d* d_positions, Eigen::VectorXd* d_scales, double gap) {
  const double inv = 1.0 / unit;
  double value = 0;
  for (const PointPair& pr : candidates) {
    const Vec3 dq = (positions.row(pr.i) - positions.row(pr.j)).transpose();
    const double d = dq.norm();
    const double g = ((1 + safety) * (scales[pr.i] + scales[pr.j]) + gap - d) * inv;
    if (!(g > 0)) continue;
    value += g * g;
    // ∂O/∂r_i = 2g(1+s)/ℓ, ∂O/∂q_i = −2g/ℓ · (q_i − q_j)/d.
    if (d_scales) {
      (*d_scales)[pr.i] += 2 * g * (1 + safety) * inv;
      (*d_scales)[pr.j] += 2 * g * (1 + safety) * inv;
    }
    if (d_positions && d > 0) {
      const Vec3 gq = (-2 * g * inv / d) * dq;
      d_positions->row(pr.i) += gq.transpose();
      d_positions->row(pr.j) -= gq.transpose();
    }
  }
  return value;
}

double boundary_collision_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                                    double safety, double unit, const BoundaryPolylines& boundary,
                                    const Eigen::VectorXd* slack, RowMatX3d* d_positions,
                                    Eigen::VectorXd* d_scales, double gap) {
  if (boundary.empty()) return 0.0;
  const double inv = 1.0 / unit;
  double value = 0;
  for (int i = 0; i < positions.rows(); ++i) {
    const Vec3 q = positions.row(i).transpose();
    const double reach = (1 + safety) * scales[i] + gap + (slack ? (*slack)[i] : 0.0);
    const auto bp = boundary.nearest(q, reach);
    if (!bp) continue;
    const double g = ((1 + safety) * scales[i] + gap - bp->signed_distance) * inv;
    if (!(g > 0)) continue;
    value += g * g;
    if (d_scales) (*d_scales)[i] += 2 * g * (1 + safety) * inv;
    if (d_positions) d_positions->row(i) += (-2 * g * inv) * bp->gradient.transpose();
  }
  return value;
}

double repulsion_objective(const RowMatX3d& positions, double epsilon, double unit,
                           const std::vector<PointPair>& candidates, RowMatX3d* d_positions) {
  const double inv = 1.0 / unit;
  const double eps = epsilon * inv;
  const double c = 1.0 / (eps * std::sqrt(2 * std::numbers::pi));
  const double shift = c * std::exp(-0.5) / (eps * eps);  // w(ε)/ε²
  double value = 0;
  for (const PointPair& pr : candidates) {
    const Vec3 dq = (positions.row(pr.i) - positions.row(pr.j)).transpose() * inv;
    const double d = dq.norm();
    if (!(d < eps) || !(d > 0)) continue;
    const double w = c * std::exp(-d * d / (2 * eps * eps));
    value += w / (d * d) - shift;
    if (d_positions) {
      // dO/dd = w'/d² − 2w/d³ with w' = −d w / ε².
      const double dOdd = -w / (eps * eps * d) - 2 * w / (d * d * d);
      const Vec3 g = (dOdd * inv / d) * dq;  // ∂O/∂q_i (dq already in ℓ units)
      d_positions->row(pr.i) += g.transpose();
      d_positions->row(pr.j) -= g.transpose();
    }
  }
  return value;
}

double growth_objective(const Eigen::VectorXd& scales, double unit, Eigen::VectorXd* d_scales) {
  if (d_scales) d_scales->array() -= 1.0 / unit;
  return -scales.sum() / unit;
}

namespace {
double candidate_cutoff(const Eigen::VectorXd& scales, double safety, double epsilon, double gap) {
  const double rmax = scales.size() ? scales.maxCoeff() : 0.0;
  return std::max(epsilon, (1 + safety) * 2 * rmax + gap);
}
}  // namespace

std::vector<PointPair> packing_candidates(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                                          double safety, double epsilon, double gap) {
  const double cutoff = candidate_cutoff(scales, safety, epsilon, gap);
  return PointGrid(positions, cutoff).pairs_within(cutoff);
}

std::vector<PointPair> packing_candidates_brute_force(const RowMatX3d& positions,
                                                      const Eigen::VectorXd& scales, double safety,
                                                      double epsilon, double gap) {
  return pairs_within_brute_force(positions, candidate_cutoff(scales, safety, epsilon, gap));
}

double packing_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                         const PackingSettings& st, const BoundaryPolylines& boundary,
                         const Eigen::VectorXd* slack, RowMatX3d* d_positions,
                         Eigen::VectorXd* d_scales, PackingTerms* terms) {
  const int n = int(positions.rows());
  RowMatX3d gq;
  Eigen::VectorXd gs;
  RowMatX3d* pq = nullptr;
  Eigen::VectorXd* ps = nullptr;
  if (d_positions) {
    gq = RowMatX3d::Zero(n, 3);
    pq = &gq;
  }
  if (d_scales) {
    gs = Eigen::VectorXd::Zero(n);
    ps = &gs;
  }
  const std::vector<PointPair> cand = packing_candidates(positions, scales, st.safety, st.epsilon);
  PackingTerms t;
  auto weighted = [&](double w, auto&& term) {
    if (pq) gq.setZero();
    if (ps) gs.setZero();
    const double v = term();
    if (pq) *d_positions += w * gq;
    if (ps) *d_scales += w * gs;
    return w * v;
  };
  t.collision = weighted(st.weights.collision, [&] {
    return collision_objective(positions, scales, st.safety, st.unit, cand, pq, ps);
  });
  t.boundary = weighted(st.weights.collision, [&] {
    return boundary_collision_objective(positions, scales, st.safety, st.unit, boundary, slack, pq, ps);
  });
  t.repulsion = weighted(st.weights.repulsion, [&] {
    return repulsion_objective(positions, st.epsilon, st.unit, cand, pq);
  });
  t.growth = weighted(st.weights.growth, [&] { return growth_objective(scales, st.unit, ps); });
  if (terms) *terms = t;
  return t.total();
}

}  // namespace cutwork

#include "host/pattern/packing_objective.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cutwork {

namespace {

/// One pair's collision (1) at centre distance d (m) and radii sum: the value (ℓ² units) and its
/// derivatives by d and by either radius.
struct PairTerm {
  double value = 0, d_distance = 0, d_radius = 0;
};

PairTerm collision_pair(double d, double radii, double safety, double gap, double inv) {
  const double g = ((1 + safety) * radii + gap - d) * inv;
  if (!(g > 0)) return {};
  // ∂O/∂r = 2g(1+s)/ℓ, ∂O/∂d = −2g/ℓ.
  return {g * g, -2 * g * inv, 2 * g * (1 + safety) * inv};
}

/// Repulsion (3) between points a and b (m): the value, and its gradient by a (m⁻¹) into `d_a`;
/// zero at and beyond ε and at a = b. The distance is taken in ℓ units (the difference scaled before
/// its norm: the order of the operations every design so far was computed with).
double repulsion_pair(const Vec3& a, const Vec3& b, double epsilon, double inv, Vec3& d_a) {
  const double eps = epsilon * inv;
  const Vec3 dq = (a - b) * inv;
  const double d = dq.norm();
  d_a.setZero();
  if (!(d < eps) || !(d > 0)) return 0.0;
  const double c = 1.0 / (eps * std::sqrt(2 * std::numbers::pi));
  const double shift = c * std::exp(-0.5) / (eps * eps);  // w(ε)/ε²
  const double w = c * std::exp(-d * d / (2 * eps * eps));
  // dO/dd = w'/d² − 2w/d³ with w' = −d w / ε² (d in ℓ units).
  const double dOdd = -w / (eps * eps * d) - 2 * w / (d * d * d);
  d_a = (dOdd * inv / d) * dq;
  return w / (d * d) - shift;
}

/// Adds the gradient `ga` of a pair term by its point a (stencil i's c_i) to stencils i and j, where
/// the term's other point is b = F c_j + const (F = diag(flip): ∂/∂c_j = −F ga), times `weight`.
void add_pair_gradient(const Vec3& ga, const Vec3& flip, int i, int j, double weight, RowMatX3d* d_positions) {
  if (!d_positions) return;
  d_positions->row(i) += (weight * ga).transpose();
  d_positions->row(j) -= (weight * flip.cwiseProduct(ga)).transpose();
}

/// The same for a collision term (and its radii).
void add_pair(const PairTerm& t, const Vec3& a, const Vec3& b, const Vec3& flip, int i, int j, double weight,
              RowMatX3d* d_positions, Eigen::VectorXd* d_scales) {
  if (d_scales && t.d_radius != 0) {
    (*d_scales)[i] += weight * t.d_radius;
    (*d_scales)[j] += weight * t.d_radius;
  }
  const Vec3 ab = a - b;
  const double d = ab.norm();
  if (d > 0 && t.d_distance != 0) add_pair_gradient((t.d_distance / d) * ab, flip, i, j, weight, d_positions);
}

}  // namespace

double collision_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                           double safety, double unit, const std::vector<PointPair>& candidates,
                           RowMatX3d* d_positions, Eigen::VectorXd* d_scales, double gap) {
  const double inv = 1.0 / unit;
  double value = 0;
  for (const PointPair& pr : candidates) {
    const Vec3 a = positions.row(pr.i).transpose(), b = positions.row(pr.j).transpose();
    const PairTerm t = collision_pair((a - b).norm(), scales[pr.i] + scales[pr.j], safety, gap, inv);
    value += t.value;
    add_pair(t, a, b, Vec3::Ones(), pr.i, pr.j, 1.0, d_positions, d_scales);
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
  double value = 0;
  for (const PointPair& pr : candidates) {
    Vec3 ga;
    value += repulsion_pair(positions.row(pr.i).transpose(), positions.row(pr.j).transpose(), epsilon, inv, ga);
    add_pair_gradient(ga, Vec3::Ones(), pr.i, pr.j, 1.0, d_positions);
  }
  return value;
}

double image_collision_objective(const PatternMirror& mirror, const RowMatX3d& positions,
                                 const Eigen::VectorXd& scales, double safety, double unit,
                                 const std::vector<ImagePair>& pairs, RowMatX3d* d_positions,
                                 Eigen::VectorXd* d_scales, double gap) {
  const double inv = 1.0 / unit;
  double value = 0;
  for (const ImagePair& p : pairs) {
    if (p.i == p.j && mirror.single(p.k)) continue;  // plane_collision_objective's
    const Vec3 a = positions.row(p.i).transpose();
    const Vec3 b = mirror.image(positions.row(p.j).transpose(), p.k);
    const PairTerm t = collision_pair((a - b).norm(), scales[p.i] + scales[p.j], safety, gap, inv);
    value += 0.5 * t.value;
    add_pair(t, a, b, mirror.flip(p.k), p.i, p.j, 0.5, d_positions, d_scales);
  }
  return value;
}

double plane_collision_objective(const PatternMirror& mirror, const RowMatX3d& positions,
                                 const Eigen::VectorXd& scales, double safety, double unit,
                                 RowMatX3d* d_positions, Eigen::VectorXd* d_scales, double gap) {
  const double inv = 1.0 / unit;
  double value = 0;
  for (int a = 0; a < 3; ++a) {
    if (!mirror.has_plane(a)) continue;
    const double side = mirror.side(a);
    for (int i = 0; i < positions.rows(); ++i) {
      // ½ ((1+s) 2r + gap − 2δ)² = 2 ((1+s) r + gap/2 − δ)²: the pair of i and its image.
      const double delta = mirror.side_distance(positions.row(i).transpose(), a);
      const double g = ((1 + safety) * scales[i] + 0.5 * gap - delta) * inv;
      if (!(g > 0)) continue;
      value += 2 * g * g;
      if (d_scales) (*d_scales)[i] += 4 * g * (1 + safety) * inv;
      if (d_positions) (*d_positions)(i, a) -= 4 * g * inv * side;
    }
  }
  return value;
}

double image_repulsion_objective(const PatternMirror& mirror, const RowMatX3d& positions, double epsilon,
                                 double unit, const std::vector<ImagePair>& pairs, RowMatX3d* d_positions) {
  const double inv = 1.0 / unit;
  double value = 0;
  for (const ImagePair& p : pairs) {
    Vec3 ga;
    value += 0.5 * repulsion_pair(positions.row(p.i).transpose(), mirror.image(positions.row(p.j).transpose(), p.k),
                                  epsilon, inv, ga);
    add_pair_gradient(ga, mirror.flip(p.k), p.i, p.j, 0.5, d_positions);
  }
  return value;
}

double growth_objective(const Eigen::VectorXd& scales, double unit, Eigen::VectorXd* d_scales) {
  if (d_scales) d_scales->array() -= 1.0 / unit;
  return -scales.sum() / unit;
}

double packing_cutoff(const Eigen::VectorXd& scales, double safety, double epsilon, double gap) {
  const double rmax = scales.size() ? scales.maxCoeff() : 0.0;
  return std::max(epsilon, (1 + safety) * 2 * rmax + gap);
}

std::vector<PointPair> packing_candidates(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                                          double safety, double epsilon, double gap) {
  const double cutoff = packing_cutoff(scales, safety, epsilon, gap);
  return PointGrid(positions, cutoff).pairs_within(cutoff);
}

std::vector<PointPair> packing_candidates_brute_force(const RowMatX3d& positions,
                                                      const Eigen::VectorXd& scales, double safety,
                                                      double epsilon, double gap) {
  return pairs_within_brute_force(positions, packing_cutoff(scales, safety, epsilon, gap));
}

double packing_objective(const RowMatX3d& positions, const Eigen::VectorXd& scales,
                         const PackingSettings& st, const BoundaryPolylines& boundary,
                         const Eigen::VectorXd* slack, RowMatX3d* d_positions,
                         Eigen::VectorXd* d_scales, PackingTerms* terms, const PatternMirror* mirror) {
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
  const bool images = mirror && mirror->any();
  const std::vector<ImagePair> image_cand =
      images ? image_pairs(*mirror, positions, packing_cutoff(scales, st.safety, st.epsilon)) : std::vector<ImagePair>{};
  t.collision = weighted(st.weights.collision, [&] {
    double v = collision_objective(positions, scales, st.safety, st.unit, cand, pq, ps);
    if (images) v += image_collision_objective(*mirror, positions, scales, st.safety, st.unit, image_cand, pq, ps);
    return v;
  });
  t.boundary = weighted(st.weights.collision, [&] {
    double v = boundary_collision_objective(positions, scales, st.safety, st.unit, boundary, slack, pq, ps);
    if (images) v += plane_collision_objective(*mirror, positions, scales, st.safety, st.unit, pq, ps);
    return v;
  });
  t.repulsion = weighted(st.weights.repulsion, [&] {
    double v = repulsion_objective(positions, st.epsilon, st.unit, cand, pq);
    if (images) v += image_repulsion_objective(*mirror, positions, st.epsilon, st.unit, image_cand, pq);
    return v;
  });
  t.growth = weighted(st.weights.growth, [&] { return growth_objective(scales, st.unit, ps); });
  if (terms) *terms = t;
  return t.total();
}

}  // namespace cutwork

#include "solvers/shell/shape_operator_energy.h"

#include <cmath>

#include <Eigen/Dense>
#include <Eigen/Geometry>

#include "host/core/error.h"

namespace cutwork::solvers {

namespace {

Eigen::Matrix3d cross_matrix(const Vec3& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

/// Voigt curvature (∂²/∂ξ1², ∂²/∂ξ2², ∂²/∂ξ1∂ξ2) of the quadratic with monomial coefficients c over
/// the basis (1, ζ1, ζ2, ζ1², ζ1ζ2, ζ2²), ζ = (ξ − centre)/L.
Vec3 voigt_curvature(const Eigen::Matrix<double, 6, 1>& c, double L) {
  return Vec3(2 * c[3], 2 * c[5], c[4]) / (L * L);
}

}  // namespace

Eigen::Matrix3d bending_constitutive(double nu) {
  Eigen::Matrix3d C;
  C << 1, nu, 0, nu, 1, 0, 0, 0, 2 * (1 - nu);
  return C;
}

Vec3 ghost_point(const Vec3& a, const Vec3& b, const Vec3& opposite) {
  const Vec3 e = b - a;
  const Vec3 foot = a + e * ((opposite - a).dot(e) / e.squaredNorm());
  return 2.0 * foot - opposite;
}

ShapeOperatorRest shape_operator_rest(const std::array<Vec3, 6>& X, const std::array<PatchNode, 3>& across,
                                      double nu, const std::array<Vec3, 3>* mirror) {
  // 1. Orthonormal rest frame of the face.
  const Vec3 e1 = X[1] - X[0], e2 = X[2] - X[0];
  const Vec3 m = e1.cross(e2);
  ShapeOperatorRest rest;
  rest.area = 0.5 * m.norm();
  if (!(rest.area > 1e-14 * e1.squaredNorm()) || !std::isfinite(rest.area))
    throw SolveError("bending element: degenerate (zero-area) triangle");
  const Vec3 normal = m.normalized();
  const Vec3 u1 = e1.normalized(), u2 = normal.cross(u1);
  auto planar = [&](const Vec3& p) { return Eigen::Vector2d((p - X[0]).dot(u1), (p - X[0]).dot(u2)); };

  // 2. Rest layout of the patch: the face's own vertices, each neighbour unfolded about its edge;
  //    a ghost at rest is the mirror image of the opposite vertex across its edge.
  rest.across = across;
  std::array<Vec3, 6> Xp = X;
  for (int i = 0; i < 3; ++i) {
    if (across[i] != PatchNode::Ghost) continue;
    const Vec3& a = X[(i + 1) % 3];
    const Vec3 t = (X[(i + 2) % 3] - a).normalized();
    rest.ghost_anchor[i] = a;
    if (mirror && (*mirror)[i].squaredNorm() > 0) {  // a symmetry plane's mirror image
      const Vec3 n = (*mirror)[i].normalized();
      rest.ghost_conormal[i] = n;
      Xp[3 + i] = X[i] - 2.0 * n * n.dot(X[i] - a);
    } else {
      rest.ghost_conormal[i] = normal.cross(t);
      Xp[3 + i] = ghost_point(a, X[(i + 2) % 3], X[i]);
    }
  }
  std::array<Eigen::Vector2d, 6> xi;
  for (int k = 0; k < 3; ++k) xi[k] = planar(X[k]);
  std::array<bool, 6> present = {true, true, true, false, false, false};
  for (int i = 0; i < 3; ++i) {
    if (across[i] == PatchNode::Free) continue;
    present[3 + i] = true;
    const int a = (i + 1) % 3, b = (i + 2) % 3;
    const Vec3 edge = X[b] - X[a];
    const double len = edge.norm();
    const Vec3 dir = edge / len;
    const Vec3 d = Xp[3 + i] - X[a];
    const double t = d.dot(dir), h = (d - t * dir).norm();
    const Eigen::Vector2d e2d = (xi[b] - xi[a]) / len;
    Eigen::Vector2d out(e2d.y(), -e2d.x());  // in-plane normal of the edge, away from vertex i
    if (out.dot(xi[i] - xi[a]) > 0) out = -out;
    xi[3 + i] = xi[a] + t * e2d + h * out;
  }

  // 3. Quadratic interpolation over the present nodes, scaled and centred for conditioning.
  const Eigen::Vector2d centre = (xi[0] + xi[1] + xi[2]) / 3.0;
  const double L = std::sqrt(rest.area);
  std::vector<int> nodes;
  for (int a = 0; a < 6; ++a)
    if (present[a]) nodes.push_back(a);
  const int n = int(nodes.size());
  Eigen::MatrixXd V(n, 6);
  for (int r = 0; r < n; ++r) {
    const Eigen::Vector2d z = (xi[nodes[r]] - centre) / L;
    V.row(r) << 1, z.x(), z.y(), z.x() * z.x(), z.x() * z.y(), z.y() * z.y();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(V, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  // Modes the nodes barely determine are condensed like a free edge's (see the header: a rim patch
  // with four nearly collinear nodes would otherwise read the across-rim curvature off the rim's
  // in-plane wiggle, with weights and stiffness amplified by 1/σ and 1/σ²).
  const double cutoff = kShapeOperatorModeCutoff * sigma[0];
  int rank = 0;
  while (rank < sigma.size() && sigma[rank] > cutoff) ++rank;
  // Pseudo-inverse over the well-determined modes: coefficients c = V⁺ x.
  Eigen::MatrixXd pinv = Eigen::MatrixXd::Zero(6, n);
  for (int k = 0; k < rank; ++k) pinv += svd.matrixV().col(k) * svd.matrixU().col(k).transpose() / sigma[k];
  Mat3x6 Qp = Mat3x6::Zero();
  for (int r = 0; r < n; ++r) Qp.col(nodes[r]) = voigt_curvature(pinv.col(r), L);

  // 4. Condense the undetermined modes (null space of V: free edges, degenerate patches).
  const Eigen::Matrix3d C = bending_constitutive(nu);
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  if (rank < 6) {
    Eigen::MatrixXd H(3, 6 - rank);
    for (int k = rank; k < 6; ++k) H.col(k - rank) = voigt_curvature(svd.matrixV().col(k), L);
    const Eigen::MatrixXd G = H.transpose() * C * H;
    P -= H * G.completeOrthogonalDecomposition().solve(H.transpose() * C);
  }
  rest.weights = P * Qp;
  // Second derivatives of a constant vanish: make the weights sum to zero exactly, so that the
  // element may work with positions relative to x0 (no cancellation of absolute coordinates).
  rest.weights.col(0) = -rest.weights.rightCols<5>().rowwise().sum();

  // 5. Rest curvature.
  Eigen::Matrix3d q = Eigen::Matrix3d::Zero();  // columns: Σ_a Q(r, a) X_a = Σ_a Q(r, a) (X_a − X_0)
  for (int a = 1; a < 6; ++a)
    if (present[a]) q += (Xp[a] - X[0]) * rest.weights.col(a).transpose();
  rest.rest_curvature = q.transpose() * normal;
  return rest;
}

namespace {

/// The patch positions the element sees: x with every ghost slot set from its opposite vertex, and
/// unused slots zeroed (their weights are zero).
Vec18 patch_positions(const Vec18& x_in, const ShapeOperatorRest& rest) {
  Vec18 x = x_in;
  for (int i = 0; i < 3; ++i) {
    if (rest.across[i] == PatchNode::Vertex) continue;
    if (rest.across[i] == PatchNode::Free) {
      x.segment<3>(9 + 3 * i).setZero();
      continue;
    }
    const Vec3& m = rest.ghost_conormal[i];
    const Vec3 xi = x.segment<3>(3 * i);
    x.segment<3>(9 + 3 * i) = xi - 2.0 * m * m.dot(xi - rest.ghost_anchor[i]);
  }
  return x;
}

/// Chain rule through the ghosts: slot 3+i depends on node i by g = R x_i + const (R = I − 2m̄m̄ᵀ,
/// symmetric), so its gradient and Hessian rows and columns fold into node i's and are cleared.
void fold_ghosts(const ShapeOperatorRest& rest, Vec18* gradient, Mat18* hessian) {
  for (int i = 0; i < 3; ++i) {
    const int s = 3 + i;
    if (rest.across[i] == PatchNode::Vertex) continue;
    if (rest.across[i] == PatchNode::Free) {
      if (gradient) gradient->segment<3>(3 * s).setZero();
      if (hessian) {
        hessian->block<3, 18>(3 * s, 0).setZero();
        hessian->block<18, 3>(0, 3 * s).setZero();
      }
      continue;
    }
    const Vec3& m = rest.ghost_conormal[i];
    const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() - 2.0 * m * m.transpose();
    if (gradient) {
      gradient->segment<3>(3 * i) += R * gradient->segment<3>(3 * s);
      gradient->segment<3>(3 * s).setZero();
    }
    if (hessian) {
      Mat18& H = *hessian;
      H.block<3, 18>(3 * i, 0) += R * H.block<3, 18>(3 * s, 0);
      H.block<18, 3>(0, 3 * i) += H.block<18, 3>(0, 3 * s) * R;
      H.block<3, 18>(3 * s, 0).setZero();
      H.block<18, 3>(0, 3 * s).setZero();
    }
  }
}

}  // namespace

namespace {

/// What energy, gradient and Hessian share: the deformed face's unit normal n and |m̂| = r
/// (m̂ = (x1 − x0) × (x2 − x0)), q (column j: Σ_a Q(j, a) x_a = Σ_a Q(j, a) (x_a − x0)), the second
/// fundamental form b = qᵀ n, and (derivatives only: set by with_edges) the face edges
/// ε_a = x(a+2) − x(a+1).
struct DeformedPatch {
  Vec3 n;
  double r = 0;
  Eigen::Matrix3d q;
  Vec3 b;
  std::array<Vec3, 3> eps;

  void with_edges(const Vec18& x) {
    for (int a = 0; a < 3; ++a) eps[a] = x.segment<3>(3 * ((a + 2) % 3)) - x.segment<3>(3 * ((a + 1) % 3));
  }
};

[[gnu::always_inline]] inline DeformedPatch deformed_patch(const Vec18& x, const Mat3x6& Q) {
  DeformedPatch p;
  const Vec3 x0 = x.segment<3>(0);
  const Vec3 normal_raw = (x.segment<3>(3) - x0).cross(x.segment<3>(6) - x0);
  p.r = normal_raw.norm();
  p.n = normal_raw / p.r;
  p.q.setZero();
  for (int a = 1; a < 6; ++a) p.q.noalias() += (x.segment<3>(3 * a) - x0) * Q.col(a).transpose();
  p.b = p.q.transpose() * p.n;
  return p;
}

/// w·∂²(½ kᵀ C k)/∂x², exactly symmetric, written block by block: with μ = C k, c = Qᵀ μ, v = q μ,
///   ∂n/∂x_a = P_n [ε_a]× / r = ([ε_a]× − n β_aᵀ) / r,  β_a = n × ε_a   (face vertices a < 3; 0 else),
///   J_a = ∂k/∂x_a = Q_a nᵀ + qᵀ ∂n/∂x_a,
///   H_ab = J_aᵀ C J_b + c_a ∂n/∂x_b + c_b (∂n/∂x_a)ᵀ + [a, b < 3] (∂²(v·n)/∂x_a∂x_b at fixed v).
/// Across the patch J_b = Q_b nᵀ for b ≥ 3, so those blocks are rank one: (J_aᵀ C Q_b) nᵀ and
/// (Q_aᵀ C Q_b) n nᵀ. The last term: ∇_m̂(v·n) = g = P_n v / r, ∇²_m̂ = −(v nᵀ + n vᵀ + (v·n)(I − 3 n nᵀ)) / r²
/// through ∂m̂/∂x_a = [ε_a]×, whose products with [ε]× reduce to the outer products of
/// α_a = v × ε_a and β_a ([ε_a]×ᵀ[ε_b]× = (ε_a·ε_b) I − ε_b ε_aᵀ), plus the bilinear part of m̂:
/// −[g]× in block (a, a+1), +[g]× in block (a+1, a).
void hessian_blocks(const DeformedPatch& p, const Mat3x6& Q, const Eigen::Matrix3d& C, const Vec3& mu,
                    const Eigen::Matrix<double, 6, 1>& c, double w, Mat18& H) {
  const Vec3& n = p.n;
  const double ir = 1.0 / p.r;
  const Vec3 v = p.q * mu;
  const Vec3 g = (v - n * n.dot(v)) * ir;
  const double vn = v.dot(n);
  const Eigen::Matrix3d G = cross_matrix(g);
  const Mat3x6 CQ = C * Q;
  std::array<Vec3, 3> alpha, beta;
  std::array<Eigen::Matrix3d, 3> dn, J;
  for (int a = 0; a < 3; ++a) {
    alpha[a] = v.cross(p.eps[a]);
    beta[a] = n.cross(p.eps[a]);
    dn[a] = (cross_matrix(p.eps[a]) - n * beta[a].transpose()) * ir;
    J[a].noalias() = Q.col(a) * n.transpose();
    J[a].noalias() += p.q.transpose() * dn[a];
  }
  for (int a = 0; a < 3; ++a) {
    for (int b = a; b < 3; ++b) {
      Eigen::Matrix3d blk;
      blk.noalias() = J[a].transpose() * (C * J[b]);
      blk += c[a] * dn[b] + c[b] * dn[a].transpose();
      blk -= ir * ir *
             (alpha[a] * beta[b].transpose() + beta[a] * alpha[b].transpose() +
              vn * (p.eps[a].dot(p.eps[b]) * Eigen::Matrix3d::Identity() - p.eps[b] * p.eps[a].transpose() -
                    3.0 * beta[a] * beta[b].transpose()));
      if (b == (a + 1) % 3) blk -= G;
      if (a == (b + 1) % 3) blk += G;
      H.block<3, 3>(3 * a, 3 * b) = w * blk;
    }
    for (int b = 3; b < 6; ++b)
      H.block<3, 3>(3 * a, 3 * b) = w * ((J[a].transpose() * CQ.col(b)) * n.transpose() + c[b] * dn[a].transpose());
  }
  const Eigen::Matrix3d nn = n * n.transpose();
  for (int a = 3; a < 6; ++a)
    for (int b = a; b < 6; ++b) H.block<3, 3>(3 * a, 3 * b) = (w * Q.col(a).dot(CQ.col(b))) * nn;
  // Lower blocks mirror the upper ones; diagonal blocks are symmetrised (their two halves are
  // computed in different orders).
  for (int a = 0; a < 6; ++a) {
    const Eigen::Matrix3d d = H.block<3, 3>(3 * a, 3 * a);
    H.block<3, 3>(3 * a, 3 * a) = 0.5 * (d + d.transpose());
    for (int b = a + 1; b < 6; ++b) H.block<3, 3>(3 * b, 3 * a) = H.block<3, 3>(3 * a, 3 * b).transpose();
  }
}

}  // namespace

Vec3 shape_operator_strain(const Vec18& x_in, const ShapeOperatorRest& rest) {
  const DeformedPatch p = deformed_patch(patch_positions(x_in, rest), rest.weights);
  return p.b - rest.rest_curvature;
}

double shape_operator_energy(const Vec18& x, const ShapeOperatorRest& rest, const Eigen::Matrix3d& C, double scale) {
  const Vec3 k = shape_operator_strain(x, rest);
  return 0.5 * scale * rest.area * k.dot(C * k);
}

void shape_operator_energy_gradient_hessian(const Vec18& x_in, const ShapeOperatorRest& rest,
                                            const Eigen::Matrix3d& C, double scale, double* energy,
                                            Vec18* gradient, Mat18* hessian) {
  const Mat3x6& Q = rest.weights;
  const Vec18 x = patch_positions(x_in, rest);
  DeformedPatch p = deformed_patch(x, Q);
  const Vec3 k = p.b - rest.rest_curvature;
  const Vec3 mu = C * k;
  const double w = scale * rest.area;
  if (energy) *energy = 0.5 * w * k.dot(mu);
  if (!gradient && !hessian) return;
  p.with_edges(x);

  const Eigen::Matrix<double, 6, 1> c = Q.transpose() * mu;  // c_a = Σ_j μ_j Q(j, a)
  if (gradient) {
    // ∂k_j/∂x_a = Q(j, a) n + [a < 3] (∂n/∂x_a)ᵀ q_j, and (∂n/∂x_a)ᵀ v = g × ε_a.
    const Vec3 v = p.q * mu;
    const Vec3 g = (v - p.n * p.n.dot(v)) / p.r;
    for (int a = 0; a < 6; ++a) {
      Vec3 ga = c[a] * p.n;
      if (a < 3) ga += g.cross(p.eps[a]);
      gradient->segment<3>(3 * a) = w * ga;
    }
  }
  if (!hessian) {
    fold_ghosts(rest, gradient, nullptr);
    return;
  }
  hessian_blocks(p, Q, C, mu, c, w, *hessian);
  const bool ghosts = rest.across[0] == PatchNode::Ghost || rest.across[1] == PatchNode::Ghost ||
                      rest.across[2] == PatchNode::Ghost;
  fold_ghosts(rest, gradient, hessian);
  if (ghosts) *hessian = 0.5 * (*hessian + hessian->transpose()).eval();  // the fold sums in two orders
}

}  // namespace cutwork::solvers

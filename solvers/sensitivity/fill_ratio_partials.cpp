#include "solvers/sensitivity/fill_ratio_partials.h"

#include <vector>

#include <tbb/parallel_for.h>

#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

/// Calls visit(element, face, dscale) for every (element, face it depends on) pair, where dscale is
/// ∂(fill factor)/∂α_face, in a fixed order: membranes, hinges (face 0, face 1), clamp hinges.
template <typename Visit>
void for_each_alpha_dependence(const ShellModel& model, const Eigen::VectorXd& alpha, Visit&& visit) {
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  for (int f = 0; f < nf; ++f) visit(f, f, 1.0);
  for (int h = 0; h < nh; ++h) {
    const ShellHinge& sh = model.hinges()[h];
    const double s = hinge_fill_factor(sh, alpha);
    visit(nf + h, sh.face[0], s / (2.0 * alpha[sh.face[0]]));
    visit(nf + h, sh.face[1], s / (2.0 * alpha[sh.face[1]]));
  }
  for (int c = 0; c < int(model.clamp_hinges().size()); ++c)
    visit(nf + nh + c, model.clamp_hinges()[c].face, 1.0);
}

/// Unit-fill-ratio gradient of element e (local DOF order) and its vertices (−1: ghost / unused).
struct LocalGradient {
  Vec12 g = Vec12::Zero();
  int vertex[4] = {-1, -1, -1, -1};
};

LocalGradient unit_gradient(const ShellModel& model, const RowMatX3d& x, int e) {
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  const ShellStiffness& k = model.stiffness();
  LocalGradient out;
  if (e < nf) {
    Vec9 g;
    membrane_energy_gradient_hessian(membrane_positions(model, x, e), model.membranes()[e], k.mu, k.lambda,
                                     1.0, nullptr, &g, nullptr);
    out.g.head<9>() = g;
    for (int i = 0; i < 3; ++i) out.vertex[i] = model.mesh().faces()(e, i);
  } else if (e < nf + nh) {
    const ShellHinge& h = model.hinges()[e - nf];
    hinge_energy_gradient_hessian(hinge_positions(h, x), h.rest, 1.0, nullptr, &out.g, nullptr);
    for (int i = 0; i < 4; ++i) out.vertex[i] = h.v[i];
  } else {
    const ClampHinge& c = model.clamp_hinges()[e - nf - nh];
    hinge_energy_gradient_hessian(clamp_positions(c, x), c.rest, 1.0, nullptr, &out.g, nullptr);
    for (int i = 0; i < 3; ++i) out.vertex[i] = c.v[i];
  }
  return out;
}

}  // namespace

Eigen::VectorXd energy_alpha_gradient(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  Eigen::VectorXd out = Eigen::VectorXd::Zero(nf);
  for_each_alpha_dependence(model, alpha, [&](int e, int face, double dscale) {
    const double u = e < nf ? unit.membrane[e] : e < nf + nh ? unit.hinge[e - nf] : unit.clamp[e - nf - nh];
    out[face] += dscale * u;
  });
  return out;
}

Eigen::VectorXd force_alpha_product(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const Eigen::VectorXd& lambda) {
  const std::vector<int>& node = model.vertex_node();
  const int ne = model.num_elements();
  // λ · (unit element gradient), per element, in parallel.
  std::vector<double> lg(std::size_t(ne), 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ne, 512), [&](const tbb::blocked_range<int>& r) {
    for (int e = r.begin(); e < r.end(); ++e) {
      const LocalGradient l = unit_gradient(model, x, e);
      double s = 0;
      for (int i = 0; i < 4; ++i) {
        if (l.vertex[i] < 0 || node[l.vertex[i]] < 0) continue;
        s += lambda.segment<3>(3 * node[l.vertex[i]]).dot(l.g.segment<3>(3 * i));
      }
      lg[e] = s;
    }
  });
  Eigen::VectorXd out = Eigen::VectorXd::Zero(model.num_faces());
  // f = −∂Ŵ/∂x + f_ext: the elastic part enters with a minus sign.
  for_each_alpha_dependence(model, alpha, [&](int e, int face, double dscale) { out[face] -= dscale * lg[e]; });
  const RowMatX3i& F = model.mesh().faces();
  for (int t = 0; t < model.num_faces(); ++t) {
    const Vec3 w = model.self_weight_per_vertex_and_alpha(t);
    if (w.squaredNorm() == 0) continue;
    for (int k = 0; k < 3; ++k) {
      const int n = node[F(t, k)];
      if (n >= 0) out[t] += lambda.segment<3>(3 * n).dot(w);
    }
  }
  return out;
}

Eigen::SparseMatrix<double> force_alpha_jacobian(const ShellModel& model, const RowMatX3d& x,
                                                 const Eigen::VectorXd& alpha) {
  const std::vector<int>& node = model.vertex_node();
  std::vector<Eigen::Triplet<double>> triplets;
  for_each_alpha_dependence(model, alpha, [&](int e, int face, double dscale) {
    const LocalGradient l = unit_gradient(model, x, e);
    for (int i = 0; i < 4; ++i) {
      if (l.vertex[i] < 0 || node[l.vertex[i]] < 0) continue;
      for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * node[l.vertex[i]] + c, face, -dscale * l.g[3 * i + c]);
    }
  });
  const RowMatX3i& F = model.mesh().faces();
  for (int t = 0; t < model.num_faces(); ++t) {
    const Vec3 w = model.self_weight_per_vertex_and_alpha(t);
    for (int k = 0; k < 3; ++k) {
      const int n = node[F(t, k)];
      if (n < 0) continue;
      for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * n + c, t, w[c]);
    }
  }
  Eigen::SparseMatrix<double> J(model.num_dofs(), model.num_faces());
  J.setFromTriplets(triplets.begin(), triplets.end());
  return J;
}

}  // namespace cutwork::solvers

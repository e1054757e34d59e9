#include "solvers/shell/fill_ratio_partials.h"

#include <algorithm>
#include <vector>

#include <tbb/parallel_for.h>

#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

/// λ · ∂U_e/∂x over the free DOFs of element e (unit fill ratio).
double lambda_dot_unit_gradient(const ShellModel& model, const RowMatX3d& x, int e, const Eigen::VectorXd& lambda) {
  const std::vector<int>& node = model.vertex_node();
  double s = 0;
  visit_element(model, x, e, 1.0, ElementNeed::Gradient, [&](const auto& l) {
    for (std::size_t a = 0; a < l.vertex.size(); ++a) {
      if (l.vertex[a] < 0 || node[l.vertex[a]] < 0) continue;
      s += lambda.segment<3>(3 * node[l.vertex[a]]).dot(l.gradient.template segment<3>(3 * a));
    }
  });
  return s;
}

}  // namespace

Eigen::VectorXd energy_alpha_gradient(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ElementEnergies unit;
  shell_energy(model, x, alpha, &unit);
  Eigen::VectorXd out = Eigen::VectorXd::Zero(model.num_faces());
  for (int e = 0; e < model.num_elements(); ++e)
    for_each_fill_dependence(model, alpha, e, [&](int face, double dscale) { out[face] += dscale * unit[e]; });
  return out;
}

Eigen::VectorXd force_alpha_product(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                    const Eigen::VectorXd& lambda) {
  const int ne = model.num_elements();
  // The held DOFs' rows of f are the supports' reactions, not forces on the shell: zero.
  Eigen::VectorXd held_free_lambda = lambda;
  model.zero_held(held_free_lambda);
  const Eigen::VectorXd& lambda_free = held_free_lambda;
  // λ · (unit element gradient), per element, in parallel.
  std::vector<double> lg(std::size_t(ne), 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, ne, 512), [&](const tbb::blocked_range<int>& r) {
    for (int e = r.begin(); e < r.end(); ++e) lg[e] = lambda_dot_unit_gradient(model, x, e, lambda_free);
  });
  Eigen::VectorXd out = Eigen::VectorXd::Zero(model.num_faces());
  // f = −∂Ŵ/∂x + f_ext: the elastic part enters with a minus sign.
  for (int e = 0; e < ne; ++e)
    for_each_fill_dependence(model, alpha, e, [&](int face, double dscale) { out[face] -= dscale * lg[e]; });
  // The external forces' part: self-weight and the surface loads (λ is zero on fixed vertices).
  RowMatX3d lambda_v = RowMatX3d::Zero(model.num_vertices(), 3);
  model.scatter_free(lambda_free, lambda_v);
  model.add_load_alpha_product(lambda_v, alpha, out);
  return out;
}

Eigen::SparseMatrix<double> force_alpha_jacobian(const ShellModel& model, const RowMatX3d& x,
                                                 const Eigen::VectorXd& alpha) {
  const std::vector<int>& node = model.vertex_node();
  std::vector<Eigen::Triplet<double>> triplets;
  for (int e = 0; e < model.num_elements(); ++e) {
    visit_element(model, x, e, 1.0, ElementNeed::Gradient, [&](const auto& l) {
      for_each_fill_dependence(model, alpha, e, [&](int face, double dscale) {
        for (std::size_t a = 0; a < l.vertex.size(); ++a) {
          if (l.vertex[a] < 0 || node[l.vertex[a]] < 0) continue;
          for (int c = 0; c < 3; ++c)
            triplets.emplace_back(3 * node[l.vertex[a]] + c, face, -dscale * l.gradient[3 * a + c]);
        }
      });
    });
  }
  const RowMatX3i& F = model.mesh().faces();
  for (int t = 0; t < model.num_faces(); ++t) {
    const Vec3 w = model.self_weight_per_vertex_and_alpha(t);
    for (int k = 0; k < 3; ++k) {
      const int n = node[F(t, k)];
      if (n < 0) continue;
      for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * n + c, t, w[c]);
    }
  }
  // Surface loads: ∂f/∂α_t = s F_t − (a_t / Σ α a) f, dense over the load's faces and vertices.
  for (const SurfaceLoad& sl : model.load_case().surface_loads) {
    const double s = ShellModel::surface_load_scale(sl, alpha);
    double material = 0;
    RowMatX3d f = RowMatX3d::Zero(model.num_vertices(), 3);
    std::vector<int> loaded;
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      const int t = sl.faces[i];
      material += alpha[t] * sl.areas[i];
      for (int k = 0; k < 3; ++k) {
        f.row(F(t, k)) += s * alpha[t] * sl.nodal[i][std::size_t(k)].transpose();
        loaded.push_back(F(t, k));
      }
    }
    std::sort(loaded.begin(), loaded.end());
    loaded.erase(std::unique(loaded.begin(), loaded.end()), loaded.end());
    for (std::size_t i = 0; i < sl.faces.size(); ++i) {
      const int t = sl.faces[i];
      for (int k = 0; k < 3; ++k) {
        const int n = node[F(t, k)];
        if (n < 0) continue;
        for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * n + c, t, s * sl.nodal[i][std::size_t(k)][c]);
      }
      for (int v : loaded) {
        const int n = node[v];
        if (n < 0) continue;
        for (int c = 0; c < 3; ++c) triplets.emplace_back(3 * n + c, t, -sl.areas[i] / material * f(v, c));
      }
    }
  }
  // The held DOFs' rows are the supports' reactions: zero, as the solver's residual has them.
  std::vector<bool> held(std::size_t(model.num_dofs()), false);
  for (int d : model.held_dofs()) held[std::size_t(d)] = true;
  std::erase_if(triplets, [&](const Eigen::Triplet<double>& t) { return held[std::size_t(t.row())]; });
  Eigen::SparseMatrix<double> J(model.num_dofs(), model.num_faces());
  J.setFromTriplets(triplets.begin(), triplets.end());
  return J;
}

}  // namespace cutwork::solvers

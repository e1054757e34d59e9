#include "solvers/shell/shell_energy.h"

#include <cmath>

#include <tbb/parallel_for.h>

namespace cutwork::solvers {

Vec9 membrane_positions(const ShellModel& model, const RowMatX3d& x, int face) {
  const RowMatX3i& F = model.mesh().faces();
  Vec9 v;
  for (int k = 0; k < 3; ++k) v.segment<3>(3 * k) = x.row(F(face, k)).transpose();
  return v;
}

Vec12 hinge_positions(const ShellHinge& hinge, const RowMatX3d& x) {
  Vec12 v;
  for (int k = 0; k < 4; ++k) v.segment<3>(3 * k) = x.row(hinge.v[k]).transpose();
  return v;
}

Vec12 clamp_positions(const ClampHinge& clamp, const RowMatX3d& x) {
  Vec12 v;
  for (int k = 0; k < 3; ++k) v.segment<3>(3 * k) = x.row(clamp.v[k]).transpose();
  v.segment<3>(9) = clamp.ghost;
  return v;
}

double hinge_fill_factor(const ShellHinge& hinge, const Eigen::VectorXd& alpha) {
  return std::sqrt(alpha[hinge.face[0]] * alpha[hinge.face[1]]);
}

namespace {

/// Deterministic sum (fixed order), so the energy does not depend on scheduling.
double ordered_sum(const std::vector<double>& v) {
  double s = 0;
  for (double e : v) s += e;
  return s;
}

double finite_or_inf(double e) { return std::isfinite(e) ? e : INFINITY; }

}  // namespace

double shell_energy(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    ElementEnergies* unit) {
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  const int nc = int(model.clamp_hinges().size());
  const ShellStiffness& k = model.stiffness();
  std::vector<double> energy(std::size_t(nf + nh + nc));
  if (unit) {
    unit->membrane.resize(nf);
    unit->hinge.resize(nh);
    unit->clamp.resize(nc);
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, nf + nh + nc, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int e = r.begin(); e < r.end(); ++e) {
      double u = 0, s = 1;
      if (e < nf) {
        u = membrane_energy(membrane_positions(model, x, e), model.membranes()[e], k.mu, k.lambda, 1.0);
        s = alpha[e];
        if (unit) unit->membrane[e] = u;
      } else if (e < nf + nh) {
        const ShellHinge& h = model.hinges()[e - nf];
        u = hinge_energy(hinge_positions(h, x), h.rest, 1.0);
        s = hinge_fill_factor(h, alpha);
        if (unit) unit->hinge[e - nf] = u;
      } else {
        const ClampHinge& c = model.clamp_hinges()[e - nf - nh];
        u = hinge_energy(clamp_positions(c, x), c.rest, 1.0);
        s = alpha[c.face];
        if (unit) unit->clamp[e - nf - nh] = u;
      }
      energy[e] = finite_or_inf(s * u);
    }
  });
  return ordered_sum(energy);
}

void assemble_shell(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    bool with_hessian, ShellAssembly& out) {
  const BlockAssembly& asmb = model.assembly();
  const int nf = model.num_faces();
  const int nh = int(model.hinges().size());
  const ShellStiffness& k = model.stiffness();
  out.gradient.setZero(asmb.num_dofs());
  if (with_hessian) out.hessian.assign(std::size_t(asmb.num_nonzeros()), 0.0);
  out.element_energy.assign(std::size_t(asmb.num_elements()), 0.0);
  double* hess = with_hessian ? out.hessian.data() : nullptr;
  double* grad = out.gradient.data();

  auto evaluate = [&](int e, bool scatter) {
    double energy = 0;
    if (e < nf) {
      Vec9 g;
      Mat9 h;
      membrane_energy_gradient_hessian(membrane_positions(model, x, e), model.membranes()[e], k.mu,
                                       k.lambda, alpha[e], &energy, scatter ? &g : nullptr,
                                       scatter && hess ? &h : nullptr);
      if (scatter) {
        asmb.scatter_vector<3>(e, g, grad);
        if (hess) asmb.scatter_matrix<3>(e, h, hess);
      }
    } else {
      Vec12 xe;
      HingeRest rest;
      double s;
      if (e < nf + nh) {
        const ShellHinge& sh = model.hinges()[e - nf];
        xe = hinge_positions(sh, x);
        rest = sh.rest;
        s = hinge_fill_factor(sh, alpha);
      } else {
        const ClampHinge& c = model.clamp_hinges()[e - nf - nh];
        xe = clamp_positions(c, x);
        rest = c.rest;
        s = alpha[c.face];
      }
      Vec12 g;
      Mat12 h;
      hinge_energy_gradient_hessian(xe, rest, s, &energy, scatter ? &g : nullptr,
                                    scatter && hess ? &h : nullptr);
      if (scatter) {
        asmb.scatter_vector<4>(e, g, grad);
        if (hess) asmb.scatter_matrix<4>(e, h, hess);
      }
    }
    out.element_energy[e] = finite_or_inf(energy);
  };

  // One colour at a time: elements of one colour share no node, so their scatters never collide,
  // and every slot receives its contributions in colour order whatever the thread count.
  for (const std::vector<int>& colour : asmb.colours()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), 256),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i) evaluate(colour[i], true);
                      });
  }
  for (int e : asmb.uncoloured()) evaluate(e, false);
  out.energy = ordered_sum(out.element_energy);
}

}  // namespace cutwork::solvers

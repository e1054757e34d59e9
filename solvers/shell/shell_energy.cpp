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

Vec18 bend_positions(const ShellBend& bend, const RowMatX3d& x) {
  Vec18 v;
  for (int a = 0; a < 6; ++a) {
    if (bend.v[a] >= 0)
      v.segment<3>(3 * a) = x.row(bend.v[a]).transpose();
    else
      v.segment<3>(3 * a).setZero();  // a ghost (set by the element from its opposite vertex) or unused
  }
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

double hinge_fill_factor(const ShellModel& model, const ShellHinge& hinge, const Eigen::VectorXd& alpha) {
  const FillStiffnessMap& g = model.fill_stiffness();
  return std::sqrt(g.bending(alpha[hinge.face[0]]) * g.bending(alpha[hinge.face[1]]));
}

double element_fill_factor(const ShellModel& model, const Eigen::VectorXd& alpha, int e) {
  const ElementRef ref = model.element(e);
  const FillStiffnessMap& g = model.fill_stiffness();
  switch (ref.kind) {
    case ElementKind::Membrane: return g.factor(false, ref.part, alpha[ref.index]);
    case ElementKind::Bend: return g.factor(true, ref.part, alpha[model.bends()[ref.index].face]);
    case ElementKind::Hinge: return hinge_fill_factor(model, model.hinges()[ref.index], alpha);
    case ElementKind::Clamp: return g.bending(alpha[model.clamp_hinges()[ref.index].face]);
  }
  return 0;
}

namespace {

/// Deterministic sum (fixed order), so the energy does not depend on scheduling.
double ordered_sum(const std::vector<double>& v) {
  double s = 0;
  for (double e : v) s += e;
  return s;
}

double finite_or_inf(double e) { return std::isfinite(e) ? e : INFINITY; }

/// Chunks per TBB task (≈ 1,000 elements, 0.1–0.6 ms of work): a colour of a small model runs on
/// the calling thread, without waking workers that would only spin and sleep again.
constexpr std::size_t kChunksPerTask = 16;
/// Elements per TBB task of the energy-only loop (tens of nanoseconds each).
constexpr int kEnergyElementsPerTask = 4096;

/// Runs body(e) for every element, one colour of chunks at a time (BlockAssembly::chunk_colours):
/// chunks of one colour share no node, so their scatters never collide, and every slot receives its
/// contributions in the same order whatever the thread count.
template <typename Body>
void for_each_element_by_colour(const BlockAssembly& asmb, Body&& body) {
  for (const std::vector<BlockAssembly::Chunk>& colour : asmb.chunk_colours()) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, colour.size(), kChunksPerTask),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i < r.end(); ++i)
                          for (int e = colour[i].begin; e < colour[i].end; ++e) body(e);
                      });
  }
}

}  // namespace

double shell_energy(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    ElementEnergies* unit) {
  const int ne = model.num_elements();
  std::vector<double> energy(std::size_t(ne), 0.0);
  if (unit) unit->resize(ne);
  tbb::parallel_for(tbb::blocked_range<int>(0, ne, kEnergyElementsPerTask), [&](const tbb::blocked_range<int>& r) {
    for (int e = r.begin(); e < r.end(); ++e) {
      const ElementRef ref = model.element(e);
      if (!unit && ref.part != FillPart::Whole) {
        // Without unit energies to return, both parts of a split element in one evaluation.
        if (ref.part == FillPart::Bulk)
          visit_split_element(model, x, alpha, e, ElementNeed::Energy,
                              [&](const auto& l) { energy[e] = finite_or_inf(l.energy); });
        continue;
      }
      double u = 0;
      visit_element(model, x, e, 1.0, ElementNeed::Energy, [&](const auto& l) { u = l.energy; });
      if (unit) (*unit)[e] = u;
      energy[e] = finite_or_inf(element_fill_factor(model, alpha, e) * u);
    }
  });
  return ordered_sum(energy);
}

void assemble_shell(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                    bool with_hessian, ShellAssembly& out) {
  const BlockAssembly& asmb = model.assembly();
  out.gradient.setZero(asmb.num_dofs());
  if (with_hessian) out.hessian.assign(std::size_t(asmb.num_nonzeros()), 0.0);
  out.element_energy.assign(std::size_t(asmb.num_elements()), 0.0);
  double* hess = with_hessian ? out.hessian.data() : nullptr;
  double* grad = out.gradient.data();
  const ElementNeed need = with_hessian ? ElementNeed::Hessian : ElementNeed::Gradient;

  const auto scatter = [&](int e) {
    return [&, e](const auto& l) {
      constexpr int K = int(std::tuple_size_v<std::decay_t<decltype(l.vertex)>>);
      asmb.scatter_vector<K>(e, l.gradient, grad);
      if (hess) asmb.scatter_matrix<K>(e, l.hessian, hess);
      out.element_energy[e] = finite_or_inf(l.energy);
    };
  };
  for_each_element_by_colour(asmb, [&](int e) {
    switch (model.element(e).part) {
      case FillPart::Whole: visit_element(model, x, e, element_fill_factor(model, alpha, e), need, scatter(e)); return;
      case FillPart::Bulk: visit_split_element(model, x, alpha, e, need, scatter(e)); return;
      case FillPart::Shear:
      case FillPart::Anisotropy: return;  // evaluated with its bulk part, which has the same nodes
    }
  });
  out.energy = ordered_sum(out.element_energy);
  model.zero_held(out.gradient);
  if (hess) model.hold_in_hessian(out.hessian);
}

Eigen::VectorXd weighted_element_gradient(const ShellModel& model, const RowMatX3d& x,
                                          const Eigen::VectorXd& weight) {
  const BlockAssembly& asmb = model.assembly();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(asmb.num_dofs());
  for_each_element_by_colour(asmb, [&](int e) {
    if (weight[e] == 0) return;
    visit_element(model, x, e, weight[e], ElementNeed::Gradient, [&](const auto& l) {
      constexpr int K = int(std::tuple_size_v<std::decay_t<decltype(l.vertex)>>);
      asmb.scatter_vector<K>(e, l.gradient, g.data());
    });
  });
  model.zero_held(g);
  return g;
}

}  // namespace cutwork::solvers

#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/optimize/stencilled_shell.h"

#include "host/core/internal_error.h"
#include "host/core/timer.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/objective/shape_cover.h"
#include "solvers/sensitivity/adjoint.h"

namespace cutwork::solvers {

StencilledShell::StencilledShell(const SurfaceMesh& sim, const FaceBvh& surface_bvh, const Material& material,
                                 const MechanicsSettings& mechanics, const LoadCase& load_case, const StencilLibrary& shapes,
                                 const TangentField& field, FillRatioOptions fill_options, NewtonSettings newton)
    : m_sim(&sim), m_sim_bvh(sim), m_mechanics(mechanics), m_shapes(&shapes), m_material(material) {
  // A homogenised fill stiffness is calibrated for these shapes (memoised: once per process),
  // equally weighted until stencils say otherwise (set_stencils).
  m_model = std::make_unique<ShellModel>(sim, material, load_case, resolve_fill_stiffness(mechanics, shapes, material));
  m_solver = std::make_unique<EquilibriumSolver>(*m_model, std::move(newton));
  // W_peak by shape reads the clip results after every evaluation (covered_by_shape): on a device,
  // download them with it rather than run the clip a second time.
  m_by_shape = concentration_by_shape(m_model->mechanics(), m_model->material());
  if (m_by_shape) fill_options.download_overlaps = true;
  m_fill = std::make_unique<FillRatioEvaluator>(surface_bvh, m_sim_bvh, shapes, &field, fill_options);
  m_alpha = Eigen::VectorXd::Ones(sim.num_faces());
}

void StencilledShell::set_cell_filter(CellFilter filter) {
  if (!filter.identity() && filter.matrix().rows() != m_sim->num_faces())
    throw InternalError("StencilledShell::set_cell_filter: the filter is not built on the simulation mesh");
  m_filter = std::move(filter);
  if (m_filter.identity()) m_face_alpha.resize(0);
}

const Eigen::VectorXd& StencilledShell::set_stencils(std::span<const StencilParams> stencils) {
  m_num_stencils = int(stencils.size());
  m_stencils.assign(stencils.begin(), stencils.end());
  m_derivatives = m_fill->options().derivatives && !stencils.empty();
  if (stencils.empty()) {
    m_alpha.setOnes(m_sim->num_faces());
    if (!m_filter.identity()) m_face_alpha = m_alpha;
    m_cover = ShapeCover{};
    return m_alpha;
  }
  Stopwatch sw;
  m_fill->evaluate(stencils);  // validates them
  // The curve weighted by these stencils' shapes (only a calibrated curve of several shapes).
  if (m_mechanics.stiffness == FillStiffness::Homogenised && m_mechanics.stiffness_curve.empty() &&
      m_shapes->size() > 1) {
    std::vector<double> weights = shape_weights(*m_shapes, stencils);
    if (weights != m_weights) {
      m_model->set_stiffness_curve(
          resolve_fill_stiffness(m_mechanics, *m_shapes, m_material, stencils).stiffness_curve);
      m_by_shape = concentration_by_shape(m_model->mechanics(), m_model->material());
      m_weights = std::move(weights);
    }
  }
  if (m_filter.identity()) {
    m_alpha = m_fill->alpha();
  } else {
    m_face_alpha = m_fill->alpha();
    m_alpha = m_filter.apply(m_face_alpha);
  }
  // The cover by shape, where W_peak reads its factors by shape and by corner.
  m_cover = ShapeCover{};
  if (m_by_shape) m_cover = shape_cover(*m_fill, stencils, m_model->mechanics().corner_radius, m_filter);
  m_times.fill += sw.seconds();
  ++m_times.fills;
  return m_alpha;
}

const EquilibriumStats& StencilledShell::equilibrate() {
  Stopwatch sw;
  try {
    const EquilibriumStats& s = m_solver->solve(m_alpha);
    m_equilibrium_stencils = m_stencils;
    m_equilibrium_cover = m_cover;
    m_times.equilibrium += sw.seconds();
    ++m_times.equilibria;
    m_times.newton_iterations += s.newton_iterations;
    return s;
  } catch (...) {
    m_times.equilibrium += sw.seconds();
    throw;
  }
}

void StencilledShell::restore_equilibrium(std::span<const StencilParams> stencils, const RowMatX3d& positions) {
  set_stencils(stencils);
  m_solver->restore_equilibrium(positions, m_alpha);
  m_equilibrium_stencils = m_stencils;
  m_equilibrium_cover = m_cover;
}

EquilibriumSummary StencilledShell::summary() const {
  if (!m_solver->has_solution()) throw InternalError("no equilibrium has been solved for yet");
  return summarize_equilibrium(*m_model, m_solver->positions(), m_solver->alpha(),
                               m_filter.identity() ? nullptr : &m_filter.blend(),
                               m_equilibrium_cover.empty() ? nullptr : &m_equilibrium_cover);
}

void StencilledShell::parameter_gradient(const ObjectiveTerms& terms, Eigen::VectorXd& d_params,
                                         Eigen::VectorXd* d_alpha) {
  if (!m_derivatives)
    throw InternalError("StencilledShell::parameter_gradient needs fill-ratio derivatives and a stencil");
  Stopwatch sw;
  const Sensitivity s = fill_ratio_sensitivity(*m_solver, terms);
  m_times.adjoint += sw.seconds();
  ++m_times.adjoints;
  sw.restart();
  m_fill->pullback(m_filter.pull_back(s.gradient), d_params);
  if (!terms.d_cover.empty() && !m_cover.empty()) {
    Eigen::VectorXd by_shape;
    shape_cover_pullback(*m_fill, m_stencils, m_model->mechanics().corner_radius, m_filter, terms.d_cover, by_shape);
    d_params += by_shape;
  }
  m_times.pullback += sw.seconds();
  if (d_alpha) *d_alpha = s.gradient;
}

double StencilledShell::covered_area(Eigen::VectorXd* d_params) const {
  const Eigen::VectorXd& A = m_sim->face_areas();
  if (d_params) {
    if (!m_derivatives) throw InternalError("StencilledShell::covered_area: derivatives were not computed");
    m_fill->pullback(-A, *d_params);
  }
  return A.sum() - A.dot(face_alpha());
}

double StencilledShell::material_fraction() const {
  const Eigen::VectorXd& A = m_sim->face_areas();
  return A.dot(face_alpha()) / A.sum();
}

}  // namespace cutwork::solvers

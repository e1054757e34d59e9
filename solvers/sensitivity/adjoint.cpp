#include "solvers/sensitivity/adjoint.h"

#include <fmt/format.h>

#include "host/core/internal_error.h"
#include "host/core/timer.h"
#include "solvers/shell/fill_ratio_partials.h"

namespace cutwork::solvers {

Sensitivity fill_ratio_sensitivity(const EquilibriumSolver& solver, const StructuralObjectiveFn& objective) {
  if (!solver.has_solution())
    throw InternalError("sensitivities need an equilibrium: solve() has not succeeded yet");
  return fill_ratio_sensitivity(solver, objective(solver.model(), solver.positions(), solver.alpha()));
}

Sensitivity fill_ratio_sensitivity(const EquilibriumSolver& solver, const ObjectiveTerms& terms) {
  const ShellModel& model = solver.model();
  if (terms.d_positions.rows() != model.num_vertices() || terms.d_alpha.size() != model.num_faces())
    throw InternalError(fmt::format("objective partials sized {}x3 and {} for {} vertices and {} triangles",
                                    terms.d_positions.rows(), terms.d_alpha.size(), model.num_vertices(),
                                    model.num_faces()));
  Sensitivity s;
  s.value = terms.value;
  Stopwatch sw;
  s.adjoint = solver.solve_adjoint(model.gather_free(terms.d_positions));
  s.seconds = sw.seconds();
  s.gradient = terms.d_alpha + force_alpha_product(model, solver.positions(), solver.alpha(), s.adjoint);
  return s;
}

}  // namespace cutwork::solvers

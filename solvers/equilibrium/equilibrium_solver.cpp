#include "solvers/equilibrium/equilibrium_solver.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/timer.h"

namespace cutwork::solvers {

namespace {

/// Armijo constant of the line search.
constexpr double kArmijo = 1e-4;
/// Halvings before the line search gives up.
constexpr int kMaxHalvings = 40;
/// Relative size of an energy change that is round-off rather than progress.
constexpr double kEnergyRoundoff = 1e-13;
/// A residual this small (relative to the load) counts as converged when round-off stops the line
/// search from making progress on the energy.
constexpr double kRoundoffResidual = 1e-5;
/// A Newton step this small relative to the largest displacement changes nothing that matters.
constexpr double kNegligibleStep = 1e-10;
/// Steps below this fraction of the model size are at the round-off of the coordinates.
constexpr double kCoordinateRoundoff = 1e-13;
/// During the iteration a Newton iterate may overshoot; beyond this many times the displacement
/// limit the load is clearly beyond capacity and iterating further is pointless.
constexpr double kExplosionFactor = 10.0;

/// Newton–Krylov: conjugate-gradient iterations on the current Hessian, preconditioned by an
/// earlier factor, allowed per Newton step before the factor counts as stale and is recomputed;
/// a step that needs more than kStaleKrylov still serves, but the next one refactorises.
constexpr int kMaxKrylov = 20;
constexpr int kStaleKrylov = 6;
/// Forcing term of the inexact Newton step: CG stops at ‖H d + r‖ ≤ η ‖r‖ with η = kForcing × the
/// relative force residual (quadratic convergence, and the last step as good as an exact one for
/// the residual test), clamped to [kMinForcing, kMaxForcing].
constexpr double kForcing = 1e-3;
constexpr double kMinForcing = 1e-12;
constexpr double kMaxForcing = 1e-3;

/// Below this (h/ℓ)², bending over membrane stiffness (a shell a millionth as thick as its triangles
/// are wide), a rest stiffness found singular is put down to the thickness. Measured on the built-in
/// plate (10 mm triangles): h = 1e-10 m, 1e-16, is singular; 1e-9 m, 1e-14, factorises.
constexpr double kUnresolvedBendingRatio = 1e-12;

/// A model whose stiffness at rest is singular: no load step can help, so it is never retried.
class UnsupportedModel : public SolveError {
 public:
  using SolveError::SolveError;
};

/// ∇Π·d of the Newton direction d (`direction`, #DOF) at the force residual r. With a positive
/// definite factor it is negative unless round-off dominates; then d becomes the steepest
/// descent −r rather than walk uphill, and `steepest` is set.
double descent_slope(const Eigen::VectorXd& residual, Eigen::VectorXd& direction, bool& steepest) {
  const double slope = residual.dot(direction);
  steepest = !(slope < 0);
  if (!steepest) return slope;
  direction = -residual;
  return -residual.squaredNorm();
}

/// During the iteration a Newton iterate may overshoot, but a displacement `displacement` (m)
/// beyond kExplosionFactor times the limit (`ratio` × the model size `size`, m) is clearly beyond
/// the structure's capacity: throws SolveError.
void check_growth(double displacement, double ratio, double size) {
  if (displacement > kExplosionFactor * (ratio * size))
    throw SolveError(fmt::format(
        "the load exceeds what the structure can carry: the displacement grew to {:.3g} m during "
        "Newton's method, far beyond {:.0f}% of the model size ({:.3g} m)",
        displacement, 100 * ratio, size));
}

/// Backtracking line search on Π(x) = Ŵ(x) − f·(x − X) from the free coordinates `x` (the shell
/// at `positions`, #V×3, whose energy is `energy0`) along `direction` (#DOF), with the Armijo
/// test on `slope` = ∇Π·d. Near the solution the decrease of Π drowns in round-off of Ŵ and
/// f·u; then a step that reduces the force residual (|`residual`| now) is accepted instead.
/// Returns whether a step was accepted; then `x` and `positions` hold the new point, else they
/// are unchanged. Counts the energy evaluations in `stats`.
bool line_search(const ShellModel& model, const Eigen::VectorXd& alpha, const Eigen::VectorXd& load,
                 const Eigen::VectorXd& rest, const Eigen::VectorXd& direction, double slope,
                 const Eigen::VectorXd& residual, double energy0, Eigen::VectorXd& x, RowMatX3d& positions,
                 EquilibriumStats& stats) {
  const double work0 = load.dot(x - rest);
  const double potential0 = energy0 - work0;
  RowMatX3d candidate = positions;
  Eigen::VectorXd xt;
  double step = 1.0;
  for (int halving = 0; halving <= kMaxHalvings; ++halving, step *= 0.5) {
    xt = x + step * direction;
    model.scatter_free(xt, candidate);
    const double energy = shell_energy(model, candidate, alpha);
    ++stats.energy_evaluations;
    if (!std::isfinite(energy)) continue;
    const double work = load.dot(xt - rest);
    const double potential = energy - work;
    bool accepted = potential <= potential0 + kArmijo * step * slope;
    if (!accepted) {
      const double noise = kEnergyRoundoff * (std::abs(energy0) + std::abs(work0) + std::abs(energy));
      if (std::abs(potential - potential0) <= noise) {
        ShellAssembly probe;
        assemble_shell(model, candidate, alpha, false, probe);
        accepted = (probe.gradient - load).norm() < residual.norm();
      }
    }
    if (accepted) {
      x = xt;
      positions = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace

EquilibriumSolver::EquilibriumSolver(const ShellModel& model, NewtonSettings settings)
    : m_model(model), m_settings(std::move(settings)) {
  m_x = model.rest_positions();
  m_trial = m_x;
  Stopwatch sw;
  const BlockAssembly& a = model.assembly();
  m_cholmod.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
  m_analysis_seconds = sw.seconds();
}

void EquilibriumSolver::log(const std::string& line) const {
  if (m_settings.log) m_settings.log(line);
}

void EquilibriumSolver::reset() {
  m_x = m_model.rest_positions();
  m_alpha.resize(0);
  m_forces.resize(0, 3);
  m_has_solution = false;
  m_factor_at_solution = false;
}

void EquilibriumSolver::restore_equilibrium(const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  m_model.check_fill_ratios(alpha);
  if (x.rows() != m_model.rest_positions().rows())
    throw SolveError("restore_equilibrium: the positions do not fit the model (an internal error in cutwork)");
  assemble_shell(m_model, x, alpha, true, m_assembly);
  if (!m_cholmod.factorize(m_assembly.hessian.data(), 0.0))
    throw SolveError("restore_equilibrium: the Hessian is not positive definite there (not a stable equilibrium)");
  m_x = x;
  m_trial = x;
  m_alpha = alpha;
  m_forces = m_model.external_forces(alpha);
  m_has_solution = true;
  m_factor_at_solution = true;
  m_factor_stale = false;
  m_last_shift = 0;
}

void EquilibriumSolver::start_from(const RowMatX3d& x) {
  const RowMatX3d& rest = m_model.rest_positions();
  if (x.rows() != rest.rows() || !x.allFinite())
    throw InternalError(fmt::format("start_from: {} positions for a model of {} vertices, or some not finite",
                                    x.rows(), rest.rows()));
  m_guess = x;
  const LoadCase& lc = m_model.load_case();
  if (!lc.held_motion)
    for (Eigen::Index v = 0; v < x.rows(); ++v)
      if (size_t(v) < lc.fixed.size() && lc.fixed[size_t(v)]) m_guess.row(v) = rest.row(v);
  // A vertex held along some axes stays at rest along them: Newton never moves it there.
  for (Eigen::Index v = 0; v < x.rows(); ++v)
    if (size_t(v) < lc.held_axes.size())
      for (int a = 0; a < 3; ++a)
        if (lc.held_axes[size_t(v)] & (1u << a)) m_guess(v, a) = rest(v, a);
}

RowMatX3d EquilibriumSolver::displacements() const { return m_x - m_model.rest_positions(); }

double EquilibriumSolver::max_displacement() const {
  return (m_x - m_model.rest_positions()).rowwise().norm().maxCoeff();
}

double EquilibriumSolver::factorize_with_shift(int iteration) {
  Stopwatch sw;
  const std::vector<double>& h = m_assembly.hessian;
  ++m_stats.factorizations;
  if (m_cholmod.factorize(h.data(), 0.0)) {
    m_stats.factorization_seconds += sw.seconds();
    return 0.0;
  }
  // Not positive definite: shift the diagonal, starting near the last successful shift (the next
  // Newton step usually needs a similar one) or at a tiny fraction of the mean diagonal.
  const std::vector<int>& cols = m_model.assembly().column_starts();
  double mean_diagonal = 0;
  const int n = m_model.num_dofs();
  for (int j = 0; j < n; ++j) mean_diagonal += std::abs(h[cols[j + 1] - 1]);  // diagonal: last in column
  mean_diagonal /= std::max(n, 1);
  double shift = std::max(m_last_shift / 10.0, 1e-8 * mean_diagonal);
  for (int attempt = 0; attempt < 30; ++attempt, shift *= 10.0) {
    ++m_stats.factorizations;
    if (m_cholmod.factorize(h.data(), shift)) {
      m_stats.factorization_seconds += sw.seconds();
      m_last_shift = shift;
      ++m_stats.shifted_factorizations;
      m_stats.max_shift = std::max(m_stats.max_shift, shift);
      log(fmt::format("Newton iteration {}: Hessian not positive definite, factorised with diagonal "
                      "shift {:.3g} N/m ({:.1e} of the mean diagonal) after {} attempt(s)",
                      iteration, shift, shift / mean_diagonal, attempt + 1));
      return shift;
    }
  }
  m_stats.factorization_seconds += sw.seconds();
  throw SolveError("the stiffness matrix could not be regularised (no diagonal shift made it positive "
                   "definite): the model or its loads are degenerate");
}

bool EquilibriumSolver::krylov_step(const Eigen::VectorXd& residual, double forcing, Eigen::VectorXd& d) {
  Stopwatch sw;
  const int n = m_model.num_dofs();
  const BlockAssembly& pattern = m_model.assembly();
  const std::vector<int>& cols = pattern.column_starts();
  const std::vector<int>& rows = pattern.row_indices();
  const std::vector<double>& h = m_assembly.hessian;
  // y = H v from the upper triangle (compressed columns).
  auto multiply = [&](const Eigen::VectorXd& v, Eigen::VectorXd& y) {
    y.setZero(n);
    for (int j = 0; j < n; ++j) {
      double yj = 0;
      for (int k = cols[j]; k < cols[j + 1]; ++k) {
        const int i = rows[k];
        yj += h[k] * v[i];
        if (i != j) y[i] += h[k] * v[j];
      }
      y[j] += yj;
    }
  };
  Eigen::VectorXd r = -residual, z(n), p(n), hp(n);
  d.setZero(n);
  m_cholmod.solve(r.data(), z.data());
  p = z;
  double rz = r.dot(z);
  const double target = forcing * residual.norm();
  bool ok = false;
  for (int k = 1; k <= kMaxKrylov; ++k) {
    multiply(p, hp);
    const double curvature = p.dot(hp);
    if (!(curvature > 0)) break;  // not positive definite along p: the exact path shifts
    const double a = rz / curvature;
    d += a * p;
    r -= a * hp;
    ++m_stats.krylov_iterations;
    if (r.norm() <= target) {
      ok = true;
      m_factor_stale = k > kStaleKrylov;
      break;
    }
    m_cholmod.solve(r.data(), z.data());
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  m_stats.solve_seconds += sw.seconds();
  if (!ok) {
    m_factor_stale = true;
    return false;
  }
  ++m_stats.krylov_steps;
  return true;
}

double EquilibriumSolver::trial_displacement() const {
  return (m_trial - m_model.rest_positions()).rowwise().norm().maxCoeff();
}

void EquilibriumSolver::newton(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load, bool from_rest,
                               int max_iterations) {
  if (max_iterations < 0) max_iterations = m_settings.max_iterations;
  const ShellModel& model = m_model;
  const double load_norm = std::max(load.norm(), m_settings.force_scale);
  const double size = model.model_size();
  const Eigen::VectorXd rest = model.gather_free(model.rest_positions());
  Eigen::VectorXd x = model.gather_free(m_trial);
  Eigen::VectorXd direction(model.num_dofs());
  m_last_shift = 0;
  m_factor_at_solution = false;

  // The factor in m_cholmod is either that of the current iterate's Hessian (factor_current) or an
  // earlier one, which preconditions conjugate gradients on the current Hessian (Newton–Krylov).
  // Newton stops only with a current factor: the converged Hessian's, for the adjoint and for the
  // stability test.
  int iteration = 0;
  bool factor_current = false;
  double shift = 0;
  auto refactorize = [&] {
    shift = factorize_with_shift(iteration);
    factor_current = true;
    m_factor_stale = false;
  };
  auto exact_step = [&](const Eigen::VectorXd& residual) {
    Stopwatch sw;
    m_cholmod.solve(residual.data(), direction.data());
    direction = -direction;
    m_stats.solve_seconds += sw.seconds();
  };
  auto converge = [&](const char* stop) {
    if (!factor_current) refactorize();
    m_stats.converged = true;
    m_stats.stop = stop;
    m_stats.stable = shift == 0;
    m_factor_at_solution = m_stats.stable;
    if (!m_stats.stable)
      log("the equilibrium is unstable: its Hessian is not positive definite (a buckled or snap-through "
          "state); sensitivities are not available there");
  };

  for (;; ++iteration) {
    Stopwatch sw;
    assemble_shell(model, m_trial, alpha, true, m_assembly);
    m_stats.assembly_seconds += sw.seconds();
    if (!std::isfinite(m_assembly.energy))
      throw SolveError("the shell reached a degenerate shape (a collapsed triangle) during Newton's method");
    const Eigen::VectorXd residual = m_assembly.gradient - load;
    const double rel = residual.norm() / load_norm;
    m_stats.residual = rel;
    m_stats.newton_iterations = iteration;

    // The singular-at-rest test needs the exact factor of the rest state.
    factor_current = false;
    const bool first_from_rest = from_rest && iteration == 0;
    if (first_from_rest || !m_settings.reuse_factor || !m_cholmod.has_factor() || m_cholmod.shift() != 0 ||
        m_factor_stale)
      refactorize();
    if (first_from_rest && shift > 0) {
      // A shell so thin against its triangles that its bending stiffness, (h/ℓ)² of its membrane
      // stiffness, is lost in double precision is singular for that reason, not for its supports.
      const double h = model.material().thickness, edge = model.mesh().mean_edge_length();
      const double ratio = (h / edge) * (h / edge);
      if (ratio < kUnresolvedBendingRatio)
        throw UnsupportedModel(fmt::format(
            "the model's stiffness at rest is singular: the shell is too thin for its mesh (thickness {:.3g} m "
            "against triangles of {:.3g} m: its bending stiffness is {:.1e} of its membrane stiffness, below what "
            "double precision resolves); check the thickness and its unit (m)",
            h, edge, ratio));
      throw UnsupportedModel(
          "the model is not supported: its stiffness at rest is singular, so a mechanism or rigid "
          "motion is not held by the supports (add or clamp supports)");
    }
    if (rel <= m_settings.residual_tolerance) return converge("residual");
    if (iteration >= max_iterations)
      throw SolveError(fmt::format(
          "Newton's method did not converge in {} iterations (force residual {:.2e} of the load); the "
          "load may exceed what the structure can carry",
          iteration, rel));

    bool krylov = !factor_current && krylov_step(residual, std::clamp(kForcing * rel, kMinForcing, kMaxForcing), direction);
    if (!krylov && !factor_current) refactorize();
    if (!krylov) exact_step(residual);

    // With a positive definite Hessian the Newton step is the estimate of the remaining
    // displacement error. Once it is negligible against the displacement (or at the round-off of
    // the coordinates themselves), the residual is the round-off of the internal forces — which,
    // for a stiff membrane under a small load, can lie above residual_tolerance. An inexact step
    // is recomputed with the exact factor before it decides that.
    const double umax = (x - rest).lpNorm<Eigen::Infinity>();
    const double negligible = std::max(kNegligibleStep * umax, kCoordinateRoundoff * size);
    if (krylov && direction.lpNorm<Eigen::Infinity>() <= negligible) {
      refactorize();
      exact_step(residual);
      krylov = false;
    }
    if (!krylov && shift == 0 && direction.lpNorm<Eigen::Infinity>() <= negligible)
      return converge("negligible_step");

    bool steepest = false;
    const double slope = descent_slope(residual, direction, steepest);
    if (steepest) log(fmt::format("Newton iteration {}: not a descent direction, using the residual", iteration));

    sw.restart();
    const bool accepted =
        line_search(model, alpha, load, rest, direction, slope, residual, m_assembly.energy, x, m_trial, m_stats);
    m_stats.line_search_seconds += sw.seconds();
    if (!accepted) {
      if (rel <= kRoundoffResidual) {
        log(fmt::format("Newton stopped at round-off level (force residual {:.2e} of the load)", rel));
        return converge("roundoff");
      }
      throw SolveError(fmt::format(
          "Newton's line search could not reduce the potential energy (force residual {:.2e} of the "
          "load); the load may exceed what the structure can carry",
          rel));
    }
    check_growth(trial_displacement(), m_settings.max_displacement_ratio, size);
  }
}

void EquilibriumSolver::reach_equilibrium(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load, bool warm) {
  const ShellModel& model = m_model;
  const double limit = m_settings.max_displacement_ratio * model.model_size();
  auto too_far = [&] {
    return SolveError(fmt::format(
        "the load exceeds what the structure can carry: the displacement reached {:.3g} m, more than "
        "{:.0f}% of the model size ({:.3g} m); reduce the loads, add supports or stiffen the design",
        trial_displacement(), 100 * m_settings.max_displacement_ratio, model.model_size()));
  };
  if (m_settings.first_load_step < 1) {
    m_trial = model.rest_positions();
    return step_load(alpha, load);
  }
  try {
    try {
      newton(alpha, load, !warm);
    } catch (const UnsupportedModel&) {
      throw;
    } catch (const SolveError& first) {
      if (!warm || !m_settings.cold_restart) throw;
      log(std::string("warm-started Newton failed (") + first.what() + "); restarting from the rest state");
      m_stats.cold_restarted = true;
      m_trial = model.rest_positions();
      newton(alpha, load, true);
    }
    if (trial_displacement() > limit) throw too_far();
  } catch (const UnsupportedModel&) {
    throw;
  } catch (const SolveError& plain) {
    if (!m_settings.load_stepping) throw;
    log(std::string("Newton at the full load failed (") + plain.what() + "); continuing by load steps from rest");
    m_trial = model.rest_positions();
    step_load(alpha, load);
  }
}

void EquilibriumSolver::step_load(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load) {
  const ShellModel& model = m_model;
  const double size = model.model_size();
  const double limit = m_settings.max_displacement_ratio * size;
  const int step_iterations = std::min(m_settings.load_step_iterations, m_settings.max_iterations);
  RowMatX3d carried = m_trial;  // the last equilibrium reached: rest, then each accepted step
  double fraction = 0, step = std::clamp(m_settings.first_load_step, m_settings.min_load_step, 1.0);
  int iterations = 0;
  std::string why;
  while (fraction < 1) {
    const double target = std::min(1.0, fraction + step);
    m_trial = carried;
    bool ok = true;
    try {
      newton(alpha, target * load, fraction == 0, step_iterations);
      if (trial_displacement() > limit) {
        ok = false;
        why = fmt::format("the displacement exceeds {:.0f}% of the model size",
                          100 * m_settings.max_displacement_ratio);
      }
    } catch (const UnsupportedModel&) {
      throw;
    } catch (const SolveError&) {
      ok = false;
      why = "Newton's method finds no equilibrium (a limit point: the shell buckles, snaps through or collapses)";
    }
    iterations += m_stats.newton_iterations;
    if (ok) {
      ++m_stats.load_steps;
      fraction = target;
      carried = m_trial;
      step = std::min(2 * step, 1.0);
      continue;
    }
    ++m_stats.failed_load_steps;
    step /= 2;
    if (step < m_settings.min_load_step) {
      m_stats.newton_iterations = iterations;
      m_trial = carried;
      const double u = trial_displacement();
      if (fraction == 0)  // not even the smallest step: no displacement at "that fraction" to tell of
        throw SolveError(fmt::format(
            "the structure can carry none of the load (not even {:.2g} of it: at that fraction {}); reduce the "
            "loads, add supports or stiffen the design",
            m_settings.min_load_step, why));
      throw SolveError(fmt::format(
          "the structure can carry only {:.1f}% of the load: at that fraction the largest displacement is "
          "{:.3g} m ({:.1f}% of the model size {:.3g} m) and beyond it {} (load steps down to {:.2g} of the "
          "load tried); reduce the loads, add supports or stiffen the design",
          100 * fraction, u, 100 * u / size, size, why, m_settings.min_load_step));
    }
  }
  m_stats.newton_iterations = iterations;
  log(fmt::format("equilibrium reached in {} load steps ({} halved), {} Newton iterations", m_stats.load_steps,
                  m_stats.failed_load_steps, iterations));
}

const EquilibriumStats& EquilibriumSolver::solve(const Eigen::VectorXd& alpha) {
  Stopwatch total;
  const ShellModel& model = m_model;
  model.check_fill_ratios(alpha);
  m_stats = EquilibriumStats{};
  const RowMatX3d forces = model.external_forces(alpha);
  Eigen::VectorXd load = model.gather_free(forces);
  model.zero_held(load);  // what pushes along a held axis goes to the support
  if (!load.allFinite()) throw SolveError("the loads are not finite");
  m_stats.load_norm = load.norm();
  if (!std::isfinite(m_stats.load_norm))
    throw SolveError(fmt::format("the loads are too large to compute with: the norm of the load vector "
                                 "overflows double precision (largest component {:.3g} N)",
                                 load.lpNorm<Eigen::Infinity>()));
  if (!(m_stats.load_norm > 0) && !(model.load_case().held_motion && m_settings.force_scale > 0))
    throw SolveError("the load case applies no load to the free part of the shell: add a load");

  const bool guessed = m_guess.rows() > 0;
  const bool warm = m_has_solution || guessed;
  m_stats.warm_started = warm;
  m_trial = guessed ? m_guess : m_x;
  m_guess.resize(0, 3);
  try {
    reach_equilibrium(alpha, load, warm);
  } catch (const SolveError&) {
    // Keep the last valid equilibrium, including the factor its adjoint needs.
    m_trial = m_x;
    m_factor_at_solution = false;
    if (m_has_solution) {
      assemble_shell(model, m_x, m_alpha, true, m_assembly);
      m_factor_at_solution = m_cholmod.factorize(m_assembly.hessian.data(), 0.0);
    }
    m_stats.converged = false;
    m_stats.total_seconds = total.seconds();
    throw;
  }
  m_x = m_trial;
  m_alpha = alpha;
  m_forces = forces;
  m_has_solution = true;
  m_stats.total_seconds = total.seconds();
  return m_stats;
}

Eigen::VectorXd EquilibriumSolver::solve_adjoint(const Eigen::VectorXd& rhs) const {
  if (!m_has_solution)
    throw InternalError("sensitivities need an equilibrium: solve() has not succeeded yet");
  if (!m_factor_at_solution)
    throw SolveError("the equilibrium is unstable (its Hessian is not positive definite): sensitivities "
                     "are undefined there");
  if (rhs.size() != m_model.num_dofs())
    throw InternalError(fmt::format("adjoint right-hand side has {} entries, the model {} free DOFs",
                                    rhs.size(), m_model.num_dofs()));
  Stopwatch sw;
  Eigen::VectorXd held_rhs = rhs;
  m_model.zero_held(held_rhs);  // the adjoint of a held DOF is zero, as if it were eliminated
  Eigen::VectorXd out(rhs.size());
  m_cholmod.solve(held_rhs.data(), out.data());
  m_adjoint_seconds += sw.seconds();
  return out;
}

}  // namespace cutwork::solvers

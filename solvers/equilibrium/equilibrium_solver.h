#pragma once
/// Static equilibrium (12) of a ShellModel for given fill ratios: Newton's method on the total
/// potential Π(x) = Ŵ(x, α) − f_ext(α)·(x − X), with a backtracking line search on Π, warm-started
/// from the previous equilibrium, on the reduced system over the free DOFs.
///
/// Per topology (constructor): the sparsity pattern, scatter map and colouring (ShellModel) and
/// CHOLMOD's symbolic analysis. Per Newton iteration: a parallel refill of the Hessian values, the
/// convergence test, then the step: preconditioned conjugate gradients on the current Hessian with
/// the last factor (Newton–Krylov, NewtonSettings::reuse_factor), or a numeric refactorisation and
/// one solve when there is no usable factor or the gradients need too many iterations. Newton stops
/// only with the factor of the converged Hessian in place (refactorising once more if the last
/// steps were Krylov steps); it is what solve_adjoint() uses — the adjoint never factorises
/// anything itself — and the next solve's first preconditioner.
///
/// Indefinite Hessians (compressed membranes, folded hinges, far from equilibrium) are regularised
/// only when CHOLMOD reports them not positive definite: the factorisation is retried with a
/// diagonal shift τI, τ growing tenfold until it succeeds; each shift is counted and logged.
///
/// Stopping: ‖∇Π‖ ≤ residual_tolerance · ‖f_ext‖ over the free DOFs (force residual relative to the
/// load). A stiff membrane under a small load has internal forces whose round-off lies above that
/// (≈ ε·E h·|X| per vertex); Newton then also stops when the Hessian is positive definite and the
/// Newton step — the estimate of the remaining displacement error — is below 1e-10 of the largest
/// displacement (or 1e-13 of the model size, the round-off of the coordinates).
///
/// Large deflections: when Newton at the full load fails (warm, then from rest), the solver
/// continues by adaptive load steps from rest (NewtonSettings::load_stepping): each step starts at
/// the last equilibrium reached, a converged step doubles the next, a failed one is halved. When
/// the steps shrink below min_load_step the error names the fraction of the load carried and the
/// displacement there relative to the model size.
///
/// Failures are SolveErrors with a message a user can act on: a load that is zero or not
/// finite, an unconstrained model (ShellModel) or one that is singular at rest, displacements beyond
/// max_displacement_ratio of the model size (a load beyond what the structure can carry), no
/// convergence within max_iterations, or a line search that cannot reduce Π. After a failure the
/// solver still holds the last valid equilibrium (positions(), alpha()) — nothing partial.
#include <functional>
#include <string>

#include <Eigen/Core>

#include "solvers/linear/cholmod_solver.h"
#include "solvers/shell/shell_energy.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {

struct NewtonSettings {
  /// Converged when ‖∇Π‖ ≤ residual_tolerance · ‖f_ext‖ (free DOFs).
  double residual_tolerance = 1e-9;
  /// N: a floor under ‖f_ext‖ in that test, for a shell driven by held motion (LoadCase::held_motion)
  /// with little or no load of its own; the peak zoom's submodel passes the ‖f_ext‖ of the shell it
  /// was cut from, so that both are converged alike. 0: none.
  double force_scale = 0;
  int max_iterations = 60;
  /// Largest accepted displacement, as a fraction of the model size (rest bounding-box diagonal).
  /// A shell that deflects more is beyond its capacity for this tool (and beyond the small-strain
  /// validity of the St. Venant–Kirchhoff model).
  double max_displacement_ratio = 0.25;
  /// Retry from the rest state when a warm-started solve fails.
  bool cold_restart = true;
  /// When Newton cannot reach the equilibrium at the full load (large deflections), continue by
  /// adaptive load steps from rest: each step starts from the last equilibrium reached, doubles
  /// after a success and halves after a failure (Newton not converging within
  /// load_step_iterations, or the displacement passing the limit above).
  bool load_stepping = true;
  /// Fraction of the load of the first attempt: 1 tries plain Newton at the full load first and
  /// steps only when it fails; a smaller value starts stepping with this step.
  double first_load_step = 1.0;
  /// Newton iterations allowed per load step (a step that needs more is halved).
  int load_step_iterations = 25;
  /// Newton–Krylov: a Newton step first tries conjugate gradients on the current Hessian,
  /// preconditioned by the last Cholesky factor (of an earlier iterate, or of the previous
  /// equilibrium in a sequence of solves), and refactorises only when they need too many
  /// iterations or meet negative curvature. Newton still stops with the factor of the converged
  /// Hessian (the adjoint's and the stability test's). false: factorise every iteration.
  bool reuse_factor = true;
  /// Smallest load step (fraction of the full load) before giving up.
  double min_load_step = 1.0 / 512;
  /// Receives one line per notable event (shifted factorisations, restarts); may be empty.
  std::function<void(const std::string&)> log;
};

/// What one solve() did. Times in seconds.
struct EquilibriumStats {
  bool converged = false;
  int newton_iterations = 0;
  double residual = 0;              ///< final ‖∇Π‖ / ‖f_ext‖
  double load_norm = 0;             ///< ‖f_ext‖ over the free DOFs (N)
  int factorizations = 0;           ///< numeric factorisations, shifted retries included
  int shifted_factorizations = 0;   ///< Newton steps that needed a diagonal shift
  double max_shift = 0;             ///< largest shift used (N/m)
  int energy_evaluations = 0;       ///< line-search evaluations of Π
  bool warm_started = false;
  bool cold_restarted = false;
  /// Accepted load steps when the equilibrium was reached by load stepping (0: plain Newton), and
  /// the attempted steps that failed and were halved.
  int load_steps = 0;
  int failed_load_steps = 0;
  /// Newton steps taken by preconditioned conjugate gradients instead of a new factorisation, and
  /// their conjugate-gradient iterations in total.
  int krylov_steps = 0;
  int krylov_iterations = 0;
  bool stable = true;               ///< the converged Hessian is positive definite
  /// Why Newton stopped when it converged: "residual" (‖∇Π‖/‖f_ext‖ ≤ residual_tolerance),
  /// "negligible_step" (the Newton step is at the round-off of the displacement) or "roundoff"
  /// (the line search stalls in round-off with the residual ≤ 1e-5); empty when it did not.
  std::string stop;
  double assembly_seconds = 0;
  double factorization_seconds = 0;
  double solve_seconds = 0;
  double line_search_seconds = 0;
  double total_seconds = 0;
};

class EquilibriumSolver {
 public:
  /// `model` must outlive the solver. Runs CHOLMOD's symbolic analysis (timed in analysis_seconds()).
  explicit EquilibriumSolver(const ShellModel& model, NewtonSettings settings = {});

  /// Solves for the equilibrium at fill ratios `alpha` (#F), starting from the last equilibrium.
  /// Throws InputError for bad fill ratios and SolveError as described above; the state is then
  /// unchanged (the last valid equilibrium).
  const EquilibriumStats& solve(const Eigen::VectorXd& alpha);

  /// Forgets the warm start: the next solve starts from the rest state.
  void reset();
  /// The next solve starts Newton from `x` (#V×3, m): a guess, not an equilibrium — a coarser mesh's
  /// solution carried over (host/mesh/mesh_mapping.h interpolate_vertex_field). Fixed vertices are
  /// put back at rest unless the load case holds them moved (LoadCase::held_motion). If Newton
  /// fails from the guess, the solve restarts from rest (NewtonSettings::cold_restart), as after any
  /// warm start. The last valid equilibrium (positions(), has_solution()) is not touched until a
  /// solve succeeds. Throws InternalError for a wrong size or a position that is not finite.
  void start_from(const RowMatX3d& x);
  /// Makes `x` (#V×3, m) the last valid equilibrium at fill ratios `alpha` (#F), as a converged
  /// stable solve leaves it: the factor of the Hessian there (what Newton–Krylov preconditions
  /// the next solve with, and the adjoint uses). Checkpoints: solves after it are bit for bit
  /// those after the solve that found `x`. Throws SolveError when the Hessian at `x` is not
  /// positive definite (not a stable equilibrium).
  void restore_equilibrium(const RowMatX3d& x, const Eigen::VectorXd& alpha);

  /// The last valid equilibrium: positions (#V×3, m) and its fill ratios (#F). Before the first
  /// successful solve: the rest state and an empty alpha.
  const RowMatX3d& positions() const { return m_x; }
  const Eigen::VectorXd& alpha() const { return m_alpha; }
  bool has_solution() const { return m_has_solution; }
  /// Displacements x − X (#V×3, m) and their largest norm.
  RowMatX3d displacements() const;
  double max_displacement() const;
  /// f_ext(α) at the last equilibrium (#V×3, N).
  const RowMatX3d& external_forces() const { return m_forces; }

  /// Solves H λ = rhs with the factor of the converged Hessian H = ∂²Π/∂x² (free DOFs, #DOF).
  /// Throws SolveError when the equilibrium is unstable (H not positive definite: sensitivities
  /// are undefined there), InternalError without a converged equilibrium or for a wrong size.
  Eigen::VectorXd solve_adjoint(const Eigen::VectorXd& rhs) const;
  /// Seconds spent in solve_adjoint so far.
  double adjoint_seconds() const { return m_adjoint_seconds; }

  const EquilibriumStats& stats() const { return m_stats; }
  const ShellModel& model() const { return m_model; }
  const NewtonSettings& settings() const { return m_settings; }
  NewtonSettings& settings() { return m_settings; }
  const CholmodSolver& linear_solver() const { return m_cholmod; }
  double analysis_seconds() const { return m_analysis_seconds; }

 private:
  /// Newton from m_trial; returns normally when converged (state in m_trial), throws otherwise.
  /// At most `max_iterations` iterations (< 0: the setting).
  void newton(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load, bool from_rest,
              int max_iterations = -1);
  /// Newton–Krylov step: conjugate gradients on the assembled Hessian preconditioned by the factor
  /// in m_cholmod (an earlier Hessian's), to ‖H d + r‖ ≤ forcing·‖r‖. Returns false (and marks
  /// the factor stale) on negative curvature or when kMaxKrylov iterations do not reach it.
  bool krylov_step(const Eigen::VectorXd& residual, double forcing, Eigen::VectorXd& direction);
  /// Plain Newton at the full load (warm, then cold), then load stepping; state in m_trial.
  void reach_equilibrium(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load, bool warm);
  /// Adaptive load stepping from rest to the full load; state in m_trial, throws with the fraction
  /// of the load carried when it cannot reach the full load.
  void step_load(const Eigen::VectorXd& alpha, const Eigen::VectorXd& load);
  /// Largest displacement of the Newton iterate m_trial (m).
  double trial_displacement() const;
  /// Factorises the assembled Hessian, shifting when needed. Returns the shift used.
  double factorize_with_shift(int iteration);
  void log(const std::string& line) const;

  const ShellModel& m_model;
  NewtonSettings m_settings;
  CholmodSolver m_cholmod;
  ShellAssembly m_assembly;
  RowMatX3d m_x;        ///< last valid equilibrium
  Eigen::VectorXd m_alpha;
  RowMatX3d m_forces;
  RowMatX3d m_trial;    ///< Newton iterate
  RowMatX3d m_guess;    ///< start_from's guess for the next solve (0 rows: none)
  bool m_has_solution = false;
  bool m_factor_at_solution = false;
  bool m_factor_stale = false;  ///< the last Krylov step needed many iterations: refactorise
  double m_last_shift = 0;
  EquilibriumStats m_stats;
  double m_analysis_seconds = 0;
  mutable double m_adjoint_seconds = 0;
};

}  // namespace cutwork::solvers

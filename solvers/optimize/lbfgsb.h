#pragma once
/// Bound-constrained minimisation with L-BFGS-B (Byrd, Lu, Nocedal, Zhu 1995; paper §5.4),
/// built from LBFGSpp's pieces (Debian's liblbfgspp-dev: the compact L-BFGS matrix, the
/// generalised Cauchy point, the subspace minimisation). The iteration loop is LBFGSpp's
/// LBFGSBSolver::minimize, operation for operation, with its state made explicit (LbfgsbState)
/// so that a run can be checkpointed between two iterations and continued bit for bit. Three
/// additions the paper asks for or a user expects:
///  - monotone decrease (§5.4: "line search in order to ensure monotonic decrease") at few
///    evaluations: an Armijo search with quadratic interpolation replaces LBFGSpp's Moré–Thuente
///    (which may return a step at the bound without checking the decrease, and extrapolates short
///    steps by 1.1× per evaluation), and a run's first step is scaled by the last inverse-curvature
///    estimate sᵀy/yᵀy instead of LBFGSpp's unit length (LbfgsbOptions::first_scale);
///  - the best point ever evaluated is returned, whatever happens (after a failing line search
///    the run restarts from the best point with a fresh Hessian approximation a few times, then
///    stops);
///  - iterations, evaluations, the value history and the reason for stopping are reported, and
///    an optional callback sees every accepted iterate (progress display, cancellation).
/// Deterministic: no threads here; the objective decides.
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace cutwork {

struct LbfgsbOptions {
  int max_iterations = 200;          ///< accepted iterations in total (over restarts)
  int memory = 8;                    ///< m, number of correction pairs
  double gradient_tolerance = 1e-6;  ///< stop when ‖projected gradient‖∞ ≤ this
  double relative_decrease = 1e-10;  ///< stop when f_{k−past} − f_k ≤ this · max(|f_k|, 1)
  int past = 3;                      ///< k − past for the decrease test (0: off)
  int max_linesearch = 40;
  int max_restarts = 3;              ///< restarts after a failed line search
  /// γ of the first step −γ∇f (an inverse curvature, units of x² / f; 0: LBFGSpp's step of unit
  /// length). A caller running several minimisations in a row passes the previous result's scale.
  double first_scale = 0;
};

/// f(x, grad): returns the value and writes the gradient (same size as x).
using LbfgsbObjective = std::function<double(const Eigen::VectorXd& x, Eigen::VectorXd& grad)>;
/// Called after every accepted iterate with (iteration, x, f); return false to stop.
using LbfgsbCallback = std::function<bool(int iteration, const Eigen::VectorXd& x, double f)>;

struct LbfgsbResult {
  Eigen::VectorXd x;             ///< best point evaluated
  double f = 0;                  ///< its value
  double f_start = 0;            ///< value at the (bound-projected) start
  int iterations = 0;            ///< accepted iterates
  int evaluations = 0;           ///< objective calls
  int restarts = 0;
  double scale = 0;              ///< last inverse-curvature estimate sᵀy/yᵀy (0: none)
  bool converged = false;        ///< stopped by a tolerance (not by the iteration cap or failure)
  std::string stop_reason;       ///< "gradient", "decrease", "iterations", "callback", "line search: …"
  std::vector<double> history;   ///< f after each accepted iterate (history.front() = f_start)
};

/// The complete state of a minimisation between two iterations: with the same objective, bounds
/// and options, minimize_lbfgsb(..., resume = &state) continues exactly where the run was (the
/// same iterates, bit for bit, as a run that was never stopped). n = the number of variables.
struct LbfgsbState {
  LbfgsbResult result;          ///< so far: the best point, counts, history, scale
  double best_at_restart = 0;   ///< the best value when the last restart began
  /// The current quasi-Newton run (the start or a restart):
  Eigen::VectorXd x, gradient;  ///< iterate (n) and its gradient (n)
  Eigen::VectorXd direction;    ///< the next search direction (n)
  double f = 0;                 ///< f(x)
  int k = 1;                    ///< iteration within the run
  Eigen::VectorXd f_past;       ///< f of the last `past` iterates, cyclic (the decrease test)
  /// The correction pairs (s, y) the L-BFGS matrix received since the run began, in order: the
  /// matrix is rebuilt by adding them again (its factorisation depends on the whole sequence).
  std::vector<Eigen::VectorXd> s, y;
  /// The last evaluation (the objective is not called again at the same point).
  Eigen::VectorXd cache_x, cache_gradient;
  double cache_f = 0;
  bool first_of_run = false;
};

/// Called between two iterations with the state (checkpoints); an exception it throws ends the
/// minimisation and propagates to the caller.
using LbfgsbCheckpoint = std::function<void(const LbfgsbState&)>;

/// Minimises f over lb ≤ x ≤ ub starting at x0 (projected onto the box first).
/// Non-finite values or gradients from f are treated as +∞ (the line search backs off); a
/// non-finite start returns at once (stop_reason "non-finite objective at the start", x = x0).
/// `checkpoint` (may be empty) sees the state after every iteration that the run continues
/// from; `resume` (may be null) continues a run from such a state instead of starting at x0.
/// Exceptions from the callback or the checkpoint propagate. Throws std::invalid_argument for
/// mismatched sizes or lb > ub.
LbfgsbResult minimize_lbfgsb(const LbfgsbObjective& f, const Eigen::VectorXd& x0,
                             const Eigen::VectorXd& lb, const Eigen::VectorXd& ub,
                             const LbfgsbOptions& options = {},
                             const LbfgsbCallback& callback = {},
                             const LbfgsbCheckpoint& checkpoint = {},
                             const LbfgsbState* resume = nullptr);

}  // namespace cutwork

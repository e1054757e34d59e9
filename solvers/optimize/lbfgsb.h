#pragma once
/// Bound-constrained minimisation with L-BFGS-B (Byrd, Lu, Nocedal, Zhu 1995; paper §5.4),
/// driving LBFGSpp's LBFGSBSolver (Debian's liblbfgspp-dev) with three additions the paper
/// asks for or a user expects:
///  - monotone decrease (§5.4: "line search in order to ensure monotonic decrease") at few
///    evaluations: an Armijo search with quadratic interpolation replaces LBFGSpp's Moré–Thuente
///    (which may return a step at the bound without checking the decrease, and extrapolates short
///    steps by 1.1× per evaluation), and a run's first step is scaled by the last inverse-curvature
///    estimate sᵀy/yᵀy instead of LBFGSpp's unit length (LbfgsbOptions::first_scale);
///  - the best point ever evaluated is returned, whatever happens (a failing line search throws
///    inside LBFGSpp; the run restarts from the best point with a fresh Hessian approximation a
///    few times, then stops);
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

/// Minimises f over lb ≤ x ≤ ub starting at x0 (projected onto the box first).
/// Non-finite values or gradients from f are treated as +∞ (the line search backs off); a
/// non-finite start returns at once (stop_reason "non-finite objective at the start", x = x0).
/// Throws std::invalid_argument for mismatched sizes or lb > ub.
LbfgsbResult minimize_lbfgsb(const LbfgsbObjective& f, const Eigen::VectorXd& x0,
                             const Eigen::VectorXd& lb, const Eigen::VectorXd& ub,
                             const LbfgsbOptions& options = {},
                             const LbfgsbCallback& callback = {});

}  // namespace cutwork

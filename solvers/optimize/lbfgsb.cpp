#include "solvers/optimize/lbfgsb.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <LBFGSB.h>

namespace cutwork {

namespace {

/// Thrown by the tracker to leave LBFGSpp early (iteration cap, callback).
struct StopRequested {
  std::string reason;
};
/// Thrown by the tracker on a non-finite value or gradient (treated like a failed search).
struct NonFiniteValue : std::runtime_error {
  NonFiniteValue() : std::runtime_error("the objective returned a non-finite value or gradient") {}
};

class Tracker {
 public:
  Tracker(const LbfgsbObjective& f, const LbfgsbCallback& cb, int max_iterations,
          LbfgsbResult& result)
      : m_f(f), m_cb(cb), m_max_iterations(max_iterations), m_result(result) {}

  double operator()(const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    if (m_cached && x.size() == m_cache_x.size() && x == m_cache_x) {
      g = m_cache_g;
      return m_cache_f;
    }
    ++m_result.evaluations;
    g.resize(x.size());
    const double v = m_f(x, g);
    if (!std::isfinite(v) || !g.allFinite()) throw NonFiniteValue();
    m_cached = true;
    m_cache_x = x;
    m_cache_g = g;
    m_cache_f = v;
    if (!m_has_best || v < m_result.f) {
      m_has_best = true;
      m_result.f = v;
      m_result.x = x;
    }
    return v;
  }

  /// One accepted iterate; s = x − x_previous and y = ∇f(x) − ∇f(x_previous) update the
  /// inverse-curvature estimate sᵀy / yᵀy that scales the next run's first step.
  void accepted(const Eigen::VectorXd& x, double f, const Eigen::VectorXd& s, const Eigen::VectorXd& y) {
    const double sy = s.dot(y), yy = y.squaredNorm();
    if (sy > 0 && yy > 0) m_result.scale = sy / yy;
    m_first_of_run = false;
    ++m_result.iterations;
    m_result.history.push_back(f);
    if (m_cb && !m_cb(m_result.iterations, x, f)) throw StopRequested{"callback"};
    if (m_max_iterations > 0 && m_result.iterations >= m_max_iterations)
      throw StopRequested{"iterations"};
  }

  bool has_best() const { return m_has_best; }

  /// A new LBFGSpp run (start or restart): its first step gets scaled.
  void start_run() { m_first_of_run = true; }

  /// The line search's first trial step along `drt` (slope dg = ∇f·drt): LBFGSpp's `step` except
  /// on a run's first iteration, where LBFGSpp's direction has unit length whatever the scale of
  /// x; there the step is the one an inverse Hessian γI would take, γ the last sᵀy/yᵀy (this
  /// call's, else options.first_scale) when there is one.
  double initial_step(double step, double step_max, double dg, double drt_squared_norm) const {
    if (!m_first_of_run || !(drt_squared_norm > 0)) return step;
    const double gamma = m_result.scale > 0 ? m_result.scale : m_first_scale;
    return gamma > 0 ? std::min(step_max, gamma * std::abs(dg) / drt_squared_norm) : step;
  }
  void set_first_scale(double gamma) { m_first_scale = gamma; }

 private:
  const LbfgsbObjective& m_f;
  const LbfgsbCallback& m_cb;
  int m_max_iterations;
  LbfgsbResult& m_result;
  bool m_has_best = false;
  bool m_first_of_run = true;
  double m_first_scale = 0;
  bool m_cached = false;
  Eigen::VectorXd m_cache_x, m_cache_g;
  double m_cache_f = 0;
};

/// Armijo backtracking with safeguarded quadratic interpolation, replacing LBFGSpp's Moré–Thuente
/// search. The quasi-Newton step (step 1, or the step to the bound) is accepted as soon as it
/// decreases f sufficiently — one evaluation per iteration in the common case. Moré–Thuente also
/// insists on the strong curvature condition and, when a step is short, extrapolates by only 1.1×
/// per evaluation; measured on the built-in designs that made 2.6 evaluations per iteration. The
/// BFGS update stays safe without the curvature condition: LBFGSpp skips pairs with sᵀy ≤ ε yᵀy.
/// The first step of a run is scaled (LBFGSpp's first direction has unit length): see
/// LbfgsbOptions::first_scale.
template <typename Scalar>
class ArmijoLineSearch {
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

 public:
  template <typename Foo>
  static void LineSearch(Foo& f, Scalar& fx, Vector& x, Vector& grad, Scalar& step,
                         const Scalar& step_max, const Vector& drt, const Vector& xp,
                         const LBFGSpp::LBFGSBParam<Scalar>& param) {
    const Scalar fx_init = fx;
    const Scalar dg_init = grad.dot(drt);
    if (!(dg_init < 0)) throw std::logic_error("the search direction is not a descent direction");
    step = f.initial_step(step, step_max, dg_init, drt.squaredNorm());
    const Vector grad_init = grad;
    for (int k = 0; k < param.max_linesearch; ++k) {
      x.noalias() = xp + step * drt;
      bool finite = true;
      try {
        fx = f(x, grad);
      } catch (const NonFiniteValue&) {
        finite = false;
      }
      if (finite && fx <= fx_init + param.ftol * step * dg_init) {
        f.accepted(x, fx, x - xp, grad - grad_init);
        return;
      }
      // Minimiser of the parabola through φ(0), φ'(0) and φ(step), kept within [0.1, 0.5]·step.
      Scalar next = Scalar(0.5) * step;
      const Scalar curvature = fx - fx_init - dg_init * step;
      if (finite && curvature > 0) next = -dg_init * step * step / (2 * curvature);
      step = std::clamp(next, Scalar(0.1) * step, Scalar(0.5) * step);
    }
    throw std::runtime_error("no decrease along the search direction");
  }
};

}  // namespace

LbfgsbResult minimize_lbfgsb(const LbfgsbObjective& f, const Eigen::VectorXd& x0,
                             const Eigen::VectorXd& lb, const Eigen::VectorXd& ub,
                             const LbfgsbOptions& options, const LbfgsbCallback& callback) {
  if (lb.size() != x0.size() || ub.size() != x0.size())
    throw std::invalid_argument("minimize_lbfgsb: bounds and start must have the same size");
  if ((lb.array() > ub.array()).any())
    throw std::invalid_argument("minimize_lbfgsb: a lower bound exceeds its upper bound");

  LbfgsbResult result;
  Tracker tracker(f, callback, options.max_iterations, result);
  tracker.set_first_scale(options.first_scale);
  Eigen::VectorXd x = x0.cwiseMax(lb).cwiseMin(ub);
  {
    Eigen::VectorXd g;
    try {
      result.f_start = tracker(x, g);
    } catch (const NonFiniteValue&) {
      // Nowhere to go from a start without a value: report it, x unchanged.
      result.x = x;
      result.f = result.f_start = INFINITY;
      result.history.push_back(INFINITY);
      result.stop_reason = "non-finite objective at the start";
      return result;
    }
    result.history.push_back(result.f_start);
  }
  if (x.size() == 0 || options.max_iterations == 0) {
    result.stop_reason = x.size() == 0 ? "gradient" : "iterations";
    result.converged = x.size() == 0;
    return result;
  }

  LBFGSpp::LBFGSBParam<double> param;
  param.m = options.memory;
  param.epsilon = options.gradient_tolerance;
  param.epsilon_rel = 0;
  param.past = options.past;
  param.delta = options.relative_decrease;
  param.max_iterations = 0;  // the tracker enforces the cap across restarts
  param.max_linesearch = options.max_linesearch;

  double best_at_restart = result.f;
  for (;;) {
    LBFGSpp::LBFGSBSolver<double, ArmijoLineSearch> solver(param);
    double fx = 0;
    tracker.start_run();
    try {
      x = result.x;
      solver.minimize(tracker, x, fx, lb, ub);
      // LBFGSpp returned by its own tests: the projected gradient or the decrease.
      Eigen::VectorXd g;
      tracker(result.x, g);
      const double pg = ((result.x - g).cwiseMax(lb).cwiseMin(ub) - result.x).cwiseAbs().maxCoeff();
      result.stop_reason = pg <= options.gradient_tolerance ? "gradient" : "decrease";
      result.converged = true;
      break;
    } catch (const StopRequested& s) {
      result.stop_reason = s.reason;
      break;
    } catch (const std::exception& e) {
      // A failed line search or a non-descent direction: restart from the best point with a
      // fresh Hessian approximation, unless the last restart did not help.
      const bool no_progress = result.restarts > 0 && !(result.f < best_at_restart);
      if (result.restarts >= options.max_restarts || no_progress) {
        result.stop_reason = std::string("line search: ") + e.what();
        break;
      }
      ++result.restarts;
      best_at_restart = result.f;
    }
  }
  return result;
}

}  // namespace cutwork

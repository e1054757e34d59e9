// The L-BFGS-B driver: known minima with and without active bounds, monotone decrease, the
// best point kept through failures, iteration caps and callbacks.
#include <gtest/gtest.h>

#include <cmath>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "solvers/optimize/lbfgsb.h"

namespace cutwork {
namespace {

double rosenbrock(const Eigen::VectorXd& x, Eigen::VectorXd& g) {
  double f = 0;
  g.setZero(x.size());
  for (Eigen::Index i = 0; i + 1 < x.size(); ++i) {
    const double a = x[i + 1] - x[i] * x[i], b = 1 - x[i];
    f += 100 * a * a + b * b;
    g[i] += -400 * a * x[i] - 2 * b;
    g[i + 1] += 200 * a;
  }
  return f;
}

bool monotone(const std::vector<double>& h) {
  for (size_t k = 1; k < h.size(); ++k)
    if (h[k] > h[k - 1]) return false;
  return true;
}

TEST(Lbfgsb, RosenbrockUnconstrained) {
  const int n = 10;
  Eigen::VectorXd x0 = Eigen::VectorXd::Constant(n, -1.2);
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(n, -INFINITY), ub = Eigen::VectorXd::Constant(n, INFINITY);
  LbfgsbOptions o;
  o.max_iterations = 500;
  o.gradient_tolerance = 1e-8;
  o.relative_decrease = 0;
  const LbfgsbResult r = minimize_lbfgsb(rosenbrock, x0, lb, ub, o);
  EXPECT_TRUE(r.converged) << r.stop_reason;
  EXPECT_NEAR((r.x - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff(), 0.0, 1e-6);
  EXPECT_TRUE(monotone(r.history));
  EXPECT_EQ(int(r.history.size()), r.iterations + 1);
  EXPECT_GT(r.evaluations, r.iterations);
}

TEST(Lbfgsb, ActiveBounds) {
  // min Σ (x_i − c_i)² with c outside the box: the solution is c clamped to the box.
  const Eigen::Vector4d c(2, -3, 0.5, 0.25);
  const Eigen::Vector4d lb(-1, -1, -1, 0.5), ub(1, 1, 1, 1);
  auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g = 2 * (x - Eigen::VectorXd(c));
    return (x - Eigen::VectorXd(c)).squaredNorm();
  };
  const LbfgsbResult r = minimize_lbfgsb(f, Eigen::VectorXd::Zero(4), lb, ub);
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR((r.x - Eigen::VectorXd(Eigen::Vector4d(1, -1, 0.5, 0.5))).norm(), 0.0, 1e-9);
  // A start outside the box is projected first.
  const LbfgsbResult r2 = minimize_lbfgsb(f, Eigen::VectorXd::Constant(4, 5.0), lb, ub);
  EXPECT_NEAR(r2.f_start, (Eigen::VectorXd(ub) - Eigen::VectorXd(c)).squaredNorm(), 1e-12);
}

TEST(Lbfgsb, IterationCapAndCallbackStop) {
  Eigen::VectorXd x0 = Eigen::VectorXd::Constant(6, -1.2);
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(6, -5), ub = Eigen::VectorXd::Constant(6, 5);
  LbfgsbOptions o;
  o.max_iterations = 7;
  LbfgsbResult r = minimize_lbfgsb(rosenbrock, x0, lb, ub, o);
  EXPECT_EQ(r.iterations, 7);
  EXPECT_EQ(r.stop_reason, "iterations");
  EXPECT_FALSE(r.converged);
  int seen = 0;
  o.max_iterations = 100;
  r = minimize_lbfgsb(rosenbrock, x0, lb, ub, o, [&](int it, const Eigen::VectorXd&, double) {
    seen = it;
    return it < 3;
  });
  EXPECT_EQ(seen, 3);
  EXPECT_EQ(r.iterations, 3);
  EXPECT_EQ(r.stop_reason, "callback");
  o.max_iterations = 0;
  r = minimize_lbfgsb(rosenbrock, x0, lb, ub, o);
  EXPECT_EQ(r.iterations, 0);
  EXPECT_EQ(r.x, x0);
}

TEST(Lbfgsb, KeepsTheBestPointWhenTheObjectiveMisbehaves) {
  // A wrong gradient (sign flipped in one component) makes line searches fail; the driver
  // restarts, then stops, returning the best point it evaluated — never a worse one.
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g = 2 * x;
    g[0] = -g[0];
    return x.squaredNorm();
  };
  Eigen::VectorXd x0(3);
  x0 << 1, 1, 1;
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(3, -INFINITY), ub = Eigen::VectorXd::Constant(3, INFINITY);
  const LbfgsbResult r = minimize_lbfgsb(f, x0, lb, ub);
  EXPECT_LE(r.f, 3.0);
  EXPECT_TRUE(monotone(r.history));
  EXPECT_NEAR(r.f, r.x.squaredNorm(), 0);
  // Non-finite values are backed off from.
  auto g = [](const Eigen::VectorXd& x, Eigen::VectorXd& gr) {
    gr = 2 * (x - Eigen::VectorXd::Constant(x.size(), 3.0));
    if (x[0] > 2.5) return std::nan("");
    return (x - Eigen::VectorXd::Constant(x.size(), 3.0)).squaredNorm();
  };
  const LbfgsbResult r2 = minimize_lbfgsb(g, Eigen::VectorXd::Zero(2), lb.head(2), ub.head(2));
  EXPECT_TRUE(std::isfinite(r2.f));
  EXPECT_LE(r2.x[0], 2.5);
  EXPECT_LT(r2.f, r2.f_start);
  EXPECT_TRUE(monotone(r2.history));
}

TEST(Lbfgsb, BugsInterruptionsAndOutOfMemoryInAnEvaluationLeaveTheRun) {
  // A SolveError at a trial point is a failed line search (the run restarts and ends with a
  // stop reason); an InternalError, an Interrupted or std::bad_alloc leave minimize_lbfgsb as
  // they are, whether thrown at the start or at a later evaluation.
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(2, -INFINITY), ub = Eigen::VectorXd::Constant(2, INFINITY);
  const Eigen::VectorXd x0 = Eigen::VectorXd::Constant(2, 1.0);
  auto throwing_at = [](int when, auto make) {
    return [when, make, calls = 0](const Eigen::VectorXd& x, Eigen::VectorXd& g) mutable {
      if (++calls == when) throw make();
      g = 2 * (x - Eigen::VectorXd::Constant(2, 3.0));
      return (x - Eigen::VectorXd::Constant(2, 3.0)).squaredNorm();
    };
  };
  for (int when : {1, 3}) {
    SCOPED_TRACE(when);
    EXPECT_THROW(minimize_lbfgsb(throwing_at(when, [] { return InternalError("a bug"); }), x0, lb, ub), InternalError);
    EXPECT_THROW(minimize_lbfgsb(throwing_at(when, [] { return Interrupted("stop", 2); }), x0, lb, ub), Interrupted);
    EXPECT_THROW(minimize_lbfgsb(throwing_at(when, [] { return std::bad_alloc(); }), x0, lb, ub), std::bad_alloc);
  }
  const LbfgsbResult r = minimize_lbfgsb(throwing_at(3, [] { return SolveError("no equilibrium"); }), x0, lb, ub);
  EXPECT_LT(r.f, r.f_start);
  EXPECT_NEAR(r.f, 0.0, 1e-10) << "the run restarted after the failed evaluation and converged";
}

TEST(Lbfgsb, BadArguments) {
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g = x;
    return 0.5 * x.squaredNorm();
  };
  EXPECT_THROW(minimize_lbfgsb(f, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(2)),
               std::invalid_argument);
  EXPECT_THROW(minimize_lbfgsb(f, Eigen::VectorXd::Zero(2), Eigen::VectorXd::Ones(2), Eigen::VectorXd::Zero(2)),
               std::invalid_argument);
}

TEST(Lbfgsb, NonFiniteStartReturnsTheStartUnchanged) {
  // A start where the objective has no value (the joint optimiser: no stable equilibrium there)
  // is reported, not thrown through the caller.
  auto f = [](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g = x;
    return x[0] > 0.5 ? INFINITY : 0.5 * x.squaredNorm();
  };
  const Eigen::VectorXd x0 = Eigen::VectorXd::Ones(2);
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(2, -10), ub = Eigen::VectorXd::Constant(2, 10);
  const LbfgsbResult r = minimize_lbfgsb(f, x0, lb, ub);
  EXPECT_EQ(r.x, x0);
  EXPECT_FALSE(std::isfinite(r.f));
  EXPECT_EQ(r.iterations, 0);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.stop_reason, "non-finite objective at the start");
}

TEST(Lbfgsb, AboutOneEvaluationPerIteration) {
  // An ill-conditioned quadratic (curvatures 1 … 1e3) and Rosenbrock: the quasi-Newton step is
  // accepted at once most of the time; a bound is active in the quadratic.
  const int n = 30;
  Eigen::VectorXd d(n);
  for (int i = 0; i < n; ++i) d[i] = std::pow(1e3, double(i) / (n - 1));
  auto quadratic = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    g = d.cwiseProduct(x - Eigen::VectorXd::Ones(n));
    return 0.5 * (x - Eigen::VectorXd::Ones(n)).dot(g);
  };
  Eigen::VectorXd lb = Eigen::VectorXd::Constant(n, -INFINITY), ub = Eigen::VectorXd::Constant(n, INFINITY);
  ub[3] = 0.5;
  LbfgsbOptions o;
  o.max_iterations = 500;
  o.gradient_tolerance = 1e-8;
  o.relative_decrease = 0;
  LbfgsbResult r = minimize_lbfgsb(quadratic, Eigen::VectorXd::Constant(n, 5.0), lb, ub, o);
  EXPECT_TRUE(r.converged) << r.stop_reason;
  EXPECT_NEAR(r.x[3], 0.5, 1e-9);
  EXPECT_NEAR(r.x[7], 1.0, 1e-6);
  EXPECT_LE(r.evaluations, 1.3 * r.iterations + 3) << r.iterations << " iterations";
  EXPECT_TRUE(monotone(r.history));

  lb.setConstant(-INFINITY);
  ub.setConstant(INFINITY);
  r = minimize_lbfgsb(rosenbrock, Eigen::VectorXd::Constant(10, -1.2), lb.head(10), ub.head(10), o);
  EXPECT_TRUE(r.converged) << r.stop_reason;
  EXPECT_LE(r.evaluations, 1.5 * r.iterations + 3) << r.iterations << " iterations";
}

TEST(Lbfgsb, FirstStepIsScaledByTheGivenInverseCurvature) {
  // f = ‖x − c‖² has the Hessian 2I: with γ = 1/2 the first step −γ∇f lands on c (LBFGSpp's own
  // first step would have length 1), and the result reports the curvature it measured.
  const Eigen::Vector3d c(3, -2, 1);
  std::vector<Eigen::VectorXd> points;
  auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    points.push_back(x);
    g = 2 * (x - Eigen::VectorXd(c));
    return (x - Eigen::VectorXd(c)).squaredNorm();
  };
  const Eigen::VectorXd lb = Eigen::VectorXd::Constant(3, -INFINITY), ub = Eigen::VectorXd::Constant(3, INFINITY);
  LbfgsbOptions o;
  o.first_scale = 0.5;
  o.max_iterations = 1;
  const LbfgsbResult r = minimize_lbfgsb(f, Eigen::VectorXd::Zero(3), lb, ub, o);
  ASSERT_GE(points.size(), 2u);
  EXPECT_NEAR((points[1] - Eigen::VectorXd(c)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.scale, 0.5, 1e-12);
  EXPECT_EQ(r.evaluations, 2);
}

}  // namespace
}  // namespace cutwork

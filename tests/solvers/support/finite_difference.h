#pragma once
/// Central-difference checks for the solver tests: the error of an analytic derivative against
/// central differences over a sweep of step sizes, with a printable table (error vs step shows the
/// O(h²) convergence and where round-off takes over).
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <fmt/format.h>

namespace cutwork::test {

struct DerivativeCheck {
  std::vector<double> steps;
  std::vector<double> errors;  ///< relative error ‖fd − analytic‖ / max(‖analytic‖, floor)
  double best = INFINITY;
  std::string table() const {
    std::string s = "     step      rel.error\n";
    for (std::size_t i = 0; i < steps.size(); ++i) s += fmt::format("  {:9.1e}  {:12.4e}\n", steps[i], errors[i]);
    return s;
  }
};

/// Steps from 1e-2·scale down to 1e-7·scale.
inline std::vector<double> fd_steps(double scale) {
  std::vector<double> s;
  for (double h = 1e-2; h >= 1e-7; h /= std::sqrt(10.0)) s.push_back(h * scale);
  return s;
}

/// Checks the Jacobian `analytic` (m×n) of f: Rⁿ → Rᵐ at x by central differences, column by column.
inline DerivativeCheck check_jacobian(const std::function<Eigen::VectorXd(const Eigen::VectorXd&)>& f,
                                      const Eigen::VectorXd& x, const Eigen::MatrixXd& analytic,
                                      double scale, double floor = 0) {
  DerivativeCheck c;
  for (double h : fd_steps(scale)) {
    Eigen::MatrixXd fd(analytic.rows(), analytic.cols());
    for (int j = 0; j < x.size(); ++j) {
      Eigen::VectorXd xp = x, xm = x;
      xp[j] += h;
      xm[j] -= h;
      fd.col(j) = (f(xp) - f(xm)) / (2 * h);
    }
    const double err = (fd - analytic).norm() / std::max(analytic.norm(), floor);
    c.steps.push_back(h);
    c.errors.push_back(err);
    c.best = std::min(c.best, err);
  }
  return c;
}

/// Scalar version: gradient of f: Rⁿ → R.
inline DerivativeCheck check_gradient(const std::function<double(const Eigen::VectorXd&)>& f,
                                      const Eigen::VectorXd& x, const Eigen::VectorXd& analytic,
                                      double scale, double floor = 0) {
  auto fv = [&](const Eigen::VectorXd& y) { return Eigen::VectorXd::Constant(1, f(y)); };
  return check_jacobian(fv, x, analytic.transpose(), scale, floor);
}

}  // namespace cutwork::test

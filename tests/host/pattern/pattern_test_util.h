#pragma once
// Shared helpers for the pattern tests: a central-difference gradient check that prints the
// error against the step size on failure (the convergence order shows whether a mismatch is a
// bug or round-off), and small meshes.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "host/core/types.h"
#include "host/mesh/surface_mesh.h"
#include "host/surfaces/generators.h"

namespace cutwork::test {

/// f(x, grad) → value. Checks grad against central differences at step h: the largest error
/// relative to max(max |grad|, scale_floor) must be ≤ rel_tol (scale_floor: the natural size
/// of the derivative, for gradients that happen to vanish). On failure prints the error for
/// h·10^-k, k = −2..3 (the convergence order tells a bug from round-off).
inline ::testing::AssertionResult gradient_matches(
    const std::function<double(const Eigen::VectorXd&, Eigen::VectorXd*)>& f,
    const Eigen::VectorXd& x, double h, double rel_tol, const std::string& what,
    double scale_floor = 1e-12) {
  Eigen::VectorXd g;
  f(x, &g);
  auto fd = [&](double step) {
    Eigen::VectorXd out(x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      Eigen::VectorXd a = x, b = x;
      a[k] += step;
      b[k] -= step;
      out[k] = (f(a, nullptr) - f(b, nullptr)) / (2 * step);
    }
    return out;
  };
  const Eigen::VectorXd n = fd(h);
  const double scale = std::max(g.cwiseAbs().maxCoeff(), scale_floor);
  const double err = (n - g).cwiseAbs().maxCoeff() / scale;
  if (err <= rel_tol) return ::testing::AssertionSuccess();
  std::string table = fmt::format("{}: max |FD − analytic| / max|analytic| = {:.3e} > {:.1e}\n"
                                  "  step        rel. error\n",
                                  what, err, rel_tol);
  for (int k = -2; k <= 3; ++k) {
    const double s = h * std::pow(10.0, -k);
    table += fmt::format("  {:.1e}    {:.3e}\n", s, (fd(s) - g).cwiseAbs().maxCoeff() / scale);
  }
  Eigen::Index worst = 0;
  (n - g).cwiseAbs().maxCoeff(&worst);
  table += fmt::format("  worst component {}: analytic {:.9e}, FD {:.9e}", worst, g[worst], n[worst]);
  return ::testing::AssertionFailure() << table;
}

/// A flat plate [0, w] × [0, h] at z = 0 with edge length e (the built-in shape, moved so
/// that its lower-left corner is the origin whatever placement the generator uses).
inline SurfaceMesh flat_plate(double w, double h, double e) {
  const SurfaceMesh m = generate_shape("plate", {{"width", w}, {"height", h}}, e);
  RowMatX3d v = m.vertices();
  v.rowwise() -= m.bbox_min().transpose();
  return SurfaceMesh(v, m.faces(), "plate");
}

}  // namespace cutwork::test

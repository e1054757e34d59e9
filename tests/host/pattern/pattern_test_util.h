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

/// Packs positions q (#S×3) and scales r (#S) into one vector, and back.
inline Eigen::VectorXd pack(const RowMatX3d& q, const Eigen::VectorXd& r) {
  Eigen::VectorXd x(q.size() + r.size());
  x.head(q.size()) = Eigen::Map<const Eigen::VectorXd>(q.data(), q.size());
  x.tail(r.size()) = r;
  return x;
}
inline void unpack(const Eigen::VectorXd& x, int n, RowMatX3d& q, Eigen::VectorXd& r) {
  q = Eigen::Map<const RowMatX3d>(x.data(), n, 3);
  r = x.tail(n);
}

/// A pattern term of positions and scales: the value, its gradients written or accumulated into
/// the (zeroed) arrays when given.
using TermFn = std::function<double(const RowMatX3d&, const Eigen::VectorXd&, RowMatX3d*, Eigen::VectorXd*)>;

/// gradient_matches for a term of (q, r) at (q0, r0).
inline ::testing::AssertionResult check_term(const TermFn& term, const RowMatX3d& q0, const Eigen::VectorXd& r0,
                                             double h, const std::string& what, double rel_tol = 1e-6) {
  const int n = int(q0.rows());
  auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
    RowMatX3d q;
    Eigen::VectorXd r;
    unpack(x, n, q, r);
    RowMatX3d gq = RowMatX3d::Zero(n, 3);
    Eigen::VectorXd gr = Eigen::VectorXd::Zero(n);
    const double v = term(q, r, g ? &gq : nullptr, g ? &gr : nullptr);
    if (g) *g = pack(gq, gr);
    return v;
  };
  return gradient_matches(f, pack(q0, r0), h, rel_tol, what);
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

#pragma once
/// Central-difference check of dα/dp for the whole pipeline p → α (closest-point projection,
/// Phong normal, tangent field, equidistant projection, clipping, fill), used by the flat and
/// curved fill-ratio tests. Prints the error-vs-step table of every failing column.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <set>
#include <utility>
#include <vector>

#include "host/stencil/fill_ratio.h"

namespace cutwork::test {

struct FdReport {
  int checked = 0;  ///< columns compared
  int skipped = 0;  ///< columns where the pair set / clamp / centre face was not stable
  double worst = 0; ///< largest relative error seen
};

/// The non-empty (stencil, face) overlaps and the clamped faces: what must not change between
/// the two sides of a central difference for it to measure the derivative.
inline std::pair<std::set<std::pair<int, int>>, std::vector<bool>> active_set(
    const FillRatioEvaluator& ev) {
  std::set<std::pair<int, int>> active;
  for (size_t i = 0; i < ev.pairs().size(); ++i) {
    if (ev.overlaps()[i].fraction != 0.0) active.insert({ev.pairs()[i].stencil, ev.pairs()[i].face});
  }
  std::vector<bool> clamped(size_t(ev.alpha().size()));
  for (Eigen::Index f = 0; f < ev.alpha().size(); ++f) {
    clamped[size_t(f)] = ev.alpha()[f] <= ev.options().min_fill;
  }
  return {active, clamped};
}

/// Compares every column ∂α/∂p_{s,k} with central differences of step `rel_step`·(s for
/// position and scale, 1 for the angle); requires max|analytic − fd| ≤ tol · max(|fd|_∞,
/// 1e-3 · natural) with natural = 1/s (position, scale) or 1 (angle).
/// A column is skipped (not stable) when the set of non-empty overlaps or of clamped faces
/// differs between the two sides, or — with `same_face` — when the stencil centre changes
/// face (the Phong normal is only C0 across edges; on a flat mesh that does not matter).
inline FdReport check_fill_derivatives(const FaceBvh& bvh, const StencilLibrary& lib,
                                       const std::vector<StencilParams>& stencils,
                                       FillBackend backend, bool same_face = true,
                                       double rel_step = 1e-6, double tol = 1e-6) {
  FillRatioOptions opt;
  opt.backend = backend;
  FillRatioEvaluator ev(bvh, lib, opt);
  ev.evaluate(stencils);
  const Eigen::MatrixXd J = Eigen::MatrixXd(ev.jacobian());
  const auto base = active_set(ev);
  std::vector<int> base_face(stencils.size());
  for (size_t s = 0; s < stencils.size(); ++s) base_face[s] = ev.frames()[s].where.face;

  FillRatioOptions fd_opt = opt;
  fd_opt.derivatives = false;
  FillRatioEvaluator probe(bvh, lib, fd_opt);
  auto alpha_at = [&](size_t s, int k, double step, bool* stable) {
    std::vector<StencilParams> p = stencils;
    if (k < 3) p[s].position[k] += step;
    if (k == 3) p[s].scale += step;
    if (k == 4) p[s].angle += step;
    probe.evaluate(p);
    if (stable != nullptr) {
      *stable = *stable && (!same_face || probe.frames()[s].where.face == base_face[s]) &&
                active_set(probe) == base;
    }
    return Eigen::VectorXd(probe.alpha());
  };

  FdReport report;
  for (size_t s = 0; s < stencils.size(); ++s) {
    const double scale = stencils[s].scale;
    for (int k = 0; k < 5; ++k) {
      const double unit = k < 4 ? scale : 1.0;
      const double natural = k < 4 ? 1.0 / scale : 1.0;
      const double h = rel_step * unit;
      bool stable = true;
      const Eigen::VectorXd ap = alpha_at(s, k, h, &stable);
      const Eigen::VectorXd am = alpha_at(s, k, -h, &stable);
      if (!stable) {
        ++report.skipped;
        continue;
      }
      ++report.checked;
      const Eigen::VectorXd fd = (ap - am) / (2 * h);
      const Eigen::VectorXd an = J.col(Eigen::Index(5 * s + size_t(k)));
      const double ref = std::max(fd.lpNorm<Eigen::Infinity>(), 1e-3 * natural);
      const double err = (an - fd).lpNorm<Eigen::Infinity>() / ref;
      report.worst = std::max(report.worst, err);
      if (err > tol) {
        std::printf("stencil %zu parameter %d: |fd|_inf = %.6e, |analytic|_inf = %.6e\n", s, k,
                    fd.lpNorm<Eigen::Infinity>(), an.lpNorm<Eigen::Infinity>());
        std::printf("  relative step   relative error\n");
        for (double r = 1e-2; r >= 1e-9; r /= 10) {
          const Eigen::VectorXd p2 = alpha_at(s, k, r * unit, nullptr);
          const Eigen::VectorXd m2 = alpha_at(s, k, -r * unit, nullptr);
          const Eigen::VectorXd f2 = (p2 - m2) / (2 * r * unit);
          std::printf("  %.0e           %.3e\n", r, (an - f2).lpNorm<Eigen::Infinity>() / ref);
        }
        ADD_FAILURE() << "dα/dp mismatch: stencil " << s << " parameter " << k
                      << " relative error " << err;
      }
    }
  }
  return report;
}

}  // namespace cutwork::test

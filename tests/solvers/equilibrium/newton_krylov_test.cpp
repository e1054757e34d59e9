// Newton–Krylov (conjugate gradients preconditioned by an earlier Cholesky factor) against plain
// Newton (a factorisation every iteration) on every built-in scene: the same equilibrium to the
// solver's tolerance, from rest and warm-started after a change of the fill ratios, with fewer
// factorisations, and the adjoint served by the converged Hessian's factor either way.
#include <random>

#include <gtest/gtest.h>

#include "host/scene/scene.h"
#include "solvers/equilibrium/equilibrium_solver.h"

namespace cutwork::solvers {
namespace {

TEST(NewtonKrylov, SameEquilibriaAsPlainNewtonOnEveryBuiltinScene) {
  for (const BuiltinScene& builtin : builtin_scenes()) {
    SCOPED_TRACE(builtin.name);
    const Scene scene = load_scene(builtin.name);
    const SceneMeshes meshes = build_scene_meshes(scene);
    const LoadCase lc = resolve_load_case(scene, meshes.sim);
    const ShellModel model(meshes.sim, scene.material, lc);
    NewtonSettings plain_settings;
    plain_settings.reuse_factor = false;
    EquilibriumSolver plain(model, plain_settings), krylov(model);
    ASSERT_TRUE(krylov.settings().reuse_factor);

    // From rest, then warm-started at fill ratios a design might have (a random tenth cut to 0.3–1).
    Eigen::VectorXd alpha = Eigen::VectorXd::Ones(model.num_faces());
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    int factorizations_plain = 0, factorizations_krylov = 0, krylov_steps = 0;
    for (int round = 0; round < 2; ++round) {
      if (round == 1)
        for (int f = 0; f < model.num_faces(); ++f)
          if (u(rng) < 0.1) alpha[f] = 0.3 + 0.7 * u(rng);
      const EquilibriumStats p = plain.solve(alpha);
      const EquilibriumStats k = krylov.solve(alpha);
      ASSERT_TRUE(p.converged && k.converged);
      EXPECT_EQ(p.krylov_steps, 0);
      factorizations_plain += p.factorizations;
      factorizations_krylov += k.factorizations;
      krylov_steps += k.krylov_steps;
      // Both stop where the Newton step is below 1e-10 of the displacement or the force residual
      // below 1e-9 of the load: the equilibria agree to well within 1e-7 of the displacement.
      const double u_max = plain.max_displacement();
      const double difference = (krylov.positions() - plain.positions()).rowwise().norm().maxCoeff();
      EXPECT_LE(difference, 1e-7 * u_max) << "round " << round << ", largest displacement " << u_max;
      const Eigen::VectorXd rhs = Eigen::VectorXd::Ones(model.num_dofs());
      const Eigen::VectorXd lp = plain.solve_adjoint(rhs), lk = krylov.solve_adjoint(rhs);
      EXPECT_LE((lk - lp).norm(), 1e-6 * lp.norm()) << "round " << round;
    }
    EXPECT_GT(krylov_steps, 0);
    EXPECT_LT(factorizations_krylov, factorizations_plain);
  }
}

}  // namespace
}  // namespace cutwork::solvers

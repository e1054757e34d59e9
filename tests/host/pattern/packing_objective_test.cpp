// The packing terms (1)–(5): analytic gradients against central differences (error against
// step printed on failure), values against hand computations, grid candidates against the
// brute-force twin.
#include <numbers>

#include <gtest/gtest.h>

#include "host/pattern/packing_objective.h"
#include "host/pattern/random.h"
#include "host/surfaces/generators.h"
#include "pattern_test_util.h"

namespace cutwork {
namespace {

/// A random cluster of n stencils in the plane z = 0 (some overlapping), unit-ish scales.
void random_layout(int n, PatternRng& rng, double spread, RowMatX3d& q, Eigen::VectorXd& r) {
  q.resize(n, 3);
  r.resize(n);
  for (int i = 0; i < n; ++i) {
    q.row(i) << rng.uniform(0, spread), rng.uniform(0, spread), rng.uniform(-0.05, 0.05) * spread;
    r[i] = rng.uniform(0.3, 0.7);
  }
}

using test::check_term;

TEST(PackingObjective, CollisionGradient) {
  PatternRng rng(1);
  RowMatX3d q;
  Eigen::VectorXd r;
  random_layout(30, rng, 4.0, q, r);
  const double s = 0.2, unit = 0.8;
  const auto cand = pairs_within_brute_force(q, 1e9);
  auto term = [&](const RowMatX3d& qq, const Eigen::VectorXd& rr, RowMatX3d* gq, Eigen::VectorXd* gr) {
    return collision_objective(qq, rr, s, unit, cand, gq, gr);
  };
  double v = term(q, r, nullptr, nullptr);
  ASSERT_GT(v, 0) << "the configuration must have collisions";
  EXPECT_TRUE(check_term(term, q, r, 1e-6, "collision (1)"));
  // With the minimum feature's gap: more pairs active, the same exact gradient.
  const double gap = 0.3;
  auto with_gap = [&](const RowMatX3d& qq, const Eigen::VectorXd& rr, RowMatX3d* gq, Eigen::VectorXd* gr) {
    return collision_objective(qq, rr, s, unit, cand, gq, gr, gap);
  };
  EXPECT_GT(with_gap(q, r, nullptr, nullptr), v);
  EXPECT_TRUE(check_term(with_gap, q, r, 1e-6, "collision (1) with a gap"));
}

TEST(PackingObjective, CollisionValueForOnePair) {
  RowMatX3d q(2, 3);
  q << 0, 0, 0, 1.5, 0, 0;
  Eigen::VectorXd r(2);
  r << 0.5, 1.0;
  const auto cand = pairs_within_brute_force(q, 10);
  // ((1+s)(r_i + r_j) − d)² / ℓ² = ((1.2·1.5 − 1.5)/0.5)² = 0.36.
  EXPECT_NEAR(collision_objective(q, r, 0.2, 0.5, cand, nullptr, nullptr), 0.36, 1e-14);
  q(1, 0) = 1.8;  // exactly touching with the safety factor: no collision
  EXPECT_EQ(collision_objective(q, r, 0.2, 0.5, cand, nullptr, nullptr), 0.0);
  // A gap of 0.1 m must stay between the enlarged circles: ((1.8 + 0.1 − 1.8)/0.5)² = 0.04.
  EXPECT_NEAR(collision_objective(q, r, 0.2, 0.5, cand, nullptr, nullptr, 0.1), 0.04, 1e-14);
  q(1, 0) = 1.9;
  EXPECT_EQ(collision_objective(q, r, 0.2, 0.5, cand, nullptr, nullptr, 0.1), 0.0);
}

TEST(PackingObjective, RepulsionGradientAndContinuity) {
  PatternRng rng(2);
  RowMatX3d q;
  Eigen::VectorXd r;
  random_layout(30, rng, 3.0, q, r);
  const double eps = 1.1, unit = 0.7;
  const auto cand = pairs_within_brute_force(q, 1e9);
  auto term = [&](const RowMatX3d& qq, const Eigen::VectorXd&, RowMatX3d* gq, Eigen::VectorXd*) {
    return repulsion_objective(qq, eps, unit, cand, gq);
  };
  EXPECT_TRUE(check_term(term, q, r, 1e-6, "repulsion (3)"));
  // Continuity at the cut-off: the shifted term tends to 0 as d → ε.
  RowMatX3d two(2, 3);
  two << 0, 0, 0, eps * (1 - 1e-9), 0, 0;
  const auto c2 = pairs_within_brute_force(two, 10);
  EXPECT_NEAR(repulsion_objective(two, eps, unit, c2, nullptr), 0.0, 1e-8);
  // Value: w(d)/d² − w(ε)/ε² in ℓ units, w = (ε√2π)⁻¹ exp(−d²/2ε²).
  two(1, 0) = 0.5;
  const double e = eps / unit, d = 0.5 / unit;
  const double w = std::exp(-d * d / (2 * e * e)) / (e * std::sqrt(2 * std::numbers::pi));
  const double we = std::exp(-0.5) / (e * std::sqrt(2 * std::numbers::pi));
  EXPECT_NEAR(repulsion_objective(two, eps, unit, c2, nullptr), w / (d * d) - we / (e * e), 1e-14);
}

TEST(PackingObjective, GrowthGradient) {
  PatternRng rng(3);
  RowMatX3d q;
  Eigen::VectorXd r;
  random_layout(10, rng, 1.0, q, r);
  auto term = [&](const RowMatX3d&, const Eigen::VectorXd& rr, RowMatX3d*, Eigen::VectorXd* gr) {
    return growth_objective(rr, 0.25, gr);
  };
  EXPECT_NEAR(term(q, r, nullptr, nullptr), -r.sum() / 0.25, 1e-14);
  EXPECT_TRUE(check_term(term, q, r, 1e-6, "growth (4)"));
}

TEST(PackingObjective, BoundaryCollisionGradientOnPlateAndBowl) {
  // Stencils near the open boundary, inside and slightly beyond it (signed distance).
  for (const char* name : {"plate", "bowl"}) {
    const ShapeInfo* info = find_shape(name);
    const SurfaceMesh mesh = generate_shape(name, {}, info->base_edge_length);
    const double e = mesh.mean_edge_length();
    const BoundaryPolylines bl(mesh, 4 * e);
    PatternRng rng(4);
    const int n = 25;
    RowMatX3d q(n, 3);
    Eigen::VectorXd r(n);
    const auto& loop = mesh.boundary_loops()[0];
    for (int i = 0; i < n; ++i) {
      // A point near the middle of a boundary edge (nearest point inside a segment), moved
      // inwards or outwards along the surface.
      const int k = rng.below(int(loop.size()));
      const Vec3 a = mesh.vertices().row(loop[size_t(k)]).transpose();
      const Vec3 b = mesh.vertices().row(loop[(size_t(k) + 1) % loop.size()]).transpose();
      const auto bp = bl.nearest(0.5 * (a + b), 1.0);
      const Vec3 m = bp->inward;
      q.row(i) = (0.5 * (a + b) + rng.uniform(-0.3, 1.5) * e * m).transpose();
      r[i] = rng.uniform(0.8, 1.6) * e;
    }
    const double s = 0.2, unit = e;
    auto term = [&](const RowMatX3d& qq, const Eigen::VectorXd& rr, RowMatX3d* gq, Eigen::VectorXd* gr) {
      return boundary_collision_objective(qq, rr, s, unit, bl, nullptr, gq, gr);
    };
    ASSERT_GT(term(q, r, nullptr, nullptr), 0);
    EXPECT_TRUE(check_term(term, q, r, 1e-7 * e, std::string("boundary collision (2) on ") + name));
    const double gap = 0.4 * e;
    auto with_gap = [&](const RowMatX3d& qq, const Eigen::VectorXd& rr, RowMatX3d* gq, Eigen::VectorXd* gr) {
      return boundary_collision_objective(qq, rr, s, unit, bl, nullptr, gq, gr, gap);
    };
    EXPECT_GT(with_gap(q, r, nullptr, nullptr), term(q, r, nullptr, nullptr));
    EXPECT_TRUE(check_term(with_gap, q, r, 1e-7 * e, std::string("boundary collision (2) with a gap on ") + name));
  }
}

TEST(PackingObjective, CandidatesMatchBruteForceAndTotalGradient) {
  const SurfaceMesh mesh = test::flat_plate(0.2, 0.1, 0.01);
  const BoundaryPolylines bl(mesh, 0.02);
  PatternRng rng(6);
  const int n = 60;
  RowMatX3d q(n, 3);
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) {
    q.row(i) << rng.uniform(0.0, 0.2), rng.uniform(0.0, 0.1), 0.0;
    r[i] = rng.uniform(0.004, 0.009);
  }
  PackingSettings st;
  st.safety = 0.2;
  st.epsilon = 0.05;
  st.unit = 0.006;
  const auto a = packing_candidates(q, r, st.safety, st.epsilon);
  const auto b = packing_candidates_brute_force(q, r, st.safety, st.epsilon);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].i, b[k].i);
    EXPECT_EQ(a[k].j, b[k].j);
  }
  auto term = [&](const RowMatX3d& qq, const Eigen::VectorXd& rr, RowMatX3d* gq, Eigen::VectorXd* gr) {
    RowMatX3d tq;
    Eigen::VectorXd tr;
    if (gq) tq = RowMatX3d::Zero(n, 3), tr = Eigen::VectorXd::Zero(n);
    const double v = packing_objective(qq, rr, st, bl, nullptr, gq ? &tq : nullptr, gr ? &tr : nullptr);
    if (gq) *gq += tq, *gr += tr;
    return v;
  };
  PackingTerms terms;
  packing_objective(q, r, st, bl, nullptr, nullptr, nullptr, &terms);
  EXPECT_GT(terms.collision, 0);
  EXPECT_GT(terms.boundary, 0);
  EXPECT_GT(terms.repulsion, 0);
  EXPECT_LT(terms.growth, 0);
  EXPECT_TRUE(check_term(term, q, r, 1e-9, "packing (5)"));
}

}  // namespace
}  // namespace cutwork

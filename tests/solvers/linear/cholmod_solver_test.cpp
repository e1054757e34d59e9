// The CHOLMOD wrapper against Eigen's dense LLT on the same matrices: analysis once, numeric
// refactorisations with new values, solves, the shifted factorisation, NOT_POSDEF reported as
// `false`, and misuse reported as SolveError. The block assembly's pattern against a dense twin.
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "solvers/linear/block_assembly.h"
#include "solvers/linear/cholmod_solver.h"
#include "solvers/linear/thread_policy.h"

#include <tbb/global_control.h>
#include <tbb/task_arena.h>

namespace cutwork::solvers {
namespace {

/// A random 3-DOF-per-node "mesh" of elements over `nodes` nodes, with some DOF-less slots.
std::vector<BlockAssembly::ElementNodes> random_elements(int nodes, int count, std::mt19937& rng) {
  std::uniform_int_distribution<int> pick(0, nodes - 1), size(2, BlockAssembly::kMaxNodes), missing(0, 5);
  std::vector<BlockAssembly::ElementNodes> elements;
  for (int e = 0; e < count; ++e) {
    BlockAssembly::ElementNodes n = BlockAssembly::nodes({});
    const int k = size(rng);
    for (int i = 0; i < k; ++i) {
      int c;
      do c = pick(rng);
      while (std::find(n.begin(), n.end(), c) != n.end());
      n[i] = missing(rng) == 0 ? -1 : c;
    }
    elements.push_back(n);
  }
  return elements;
}

/// Assembles symmetric positive semi-definite local matrices (plus a diagonal) through the block
/// assembly, and the same into a dense matrix.
void assemble_random(const BlockAssembly& a, const std::vector<BlockAssembly::ElementNodes>& elements,
                     std::mt19937& rng, std::vector<double>& values, Eigen::MatrixXd& dense) {
  std::normal_distribution<double> n;
  values.assign(std::size_t(a.num_nonzeros()), 0.0);
  dense = Eigen::MatrixXd::Zero(a.num_dofs(), a.num_dofs());
  for (int e = 0; e < int(elements.size()); ++e) {
    constexpr int K = BlockAssembly::kMaxNodes;
    Eigen::Matrix<double, 3 * K, 3 * K> B;
    for (int i = 0; i < B.size(); ++i) B.data()[i] = n(rng);
    const Eigen::Matrix<double, 3 * K, 3 * K> local = B * B.transpose();
    a.scatter_matrix<K>(e, local, values.data());
    for (int p = 0; p < K; ++p)
      for (int q = 0; q < K; ++q)
        if (elements[e][p] >= 0 && elements[e][q] >= 0)
          dense.block<3, 3>(3 * elements[e][p], 3 * elements[e][q]) += local.block<3, 3>(3 * p, 3 * q);
  }
  // Make it definite: add the identity to the diagonal (the last entry of every column).
  for (int j = 0; j < a.num_dofs(); ++j) values[a.column_starts()[j + 1] - 1] += 1.0;
  dense += Eigen::MatrixXd::Identity(a.num_dofs(), a.num_dofs());
}

Eigen::MatrixXd dense_from_upper(const BlockAssembly& a, const std::vector<double>& values) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(a.num_dofs(), a.num_dofs());
  for (int j = 0; j < a.num_dofs(); ++j)
    for (int k = a.column_starts()[j]; k < a.column_starts()[j + 1]; ++k) {
      EXPECT_LE(a.row_indices()[k], j);
      m(a.row_indices()[k], j) = m(j, a.row_indices()[k]) = values[k];
    }
  return m;
}

TEST(BlockAssembly, PatternScatterAndColouringMatchDenseTwin) {
  std::mt19937 rng(1);
  const int nodes = 40;
  const auto elements = random_elements(nodes, 120, rng);
  const BlockAssembly a(nodes, elements);
  std::vector<double> values;
  Eigen::MatrixXd dense;
  assemble_random(a, elements, rng, values, dense);
  EXPECT_LE((dense_from_upper(a, values) - dense).norm(), 1e-12 * dense.norm());
  // Rows sorted and unique within each column, diagonal last.
  for (int j = 0; j < a.num_dofs(); ++j) {
    for (int k = a.column_starts()[j] + 1; k < a.column_starts()[j + 1]; ++k)
      EXPECT_LT(a.row_indices()[k - 1], a.row_indices()[k]);
    EXPECT_EQ(a.row_indices()[a.column_starts()[j + 1] - 1], j);
  }
  // Colouring: every element with a DOF in exactly one colour, no node shared within a colour.
  std::vector<int> seen(elements.size(), 0);
  for (const auto& colour : a.colours()) {
    std::vector<bool> used(nodes, false);
    for (int e : colour) {
      ++seen[e];
      for (int n : elements[e])
        if (n >= 0) {
          EXPECT_FALSE(used[n]) << "node " << n << " twice in one colour";
          used[n] = true;
        }
    }
  }
  for (int e : a.uncoloured()) ++seen[e];
  for (int s : seen) EXPECT_EQ(s, 1);
}

TEST(BlockAssembly, ChunkColoursCoverEveryElementOnceWithoutSharedNodes) {
  std::mt19937 rng(3);
  const int nodes = 400;
  // Elements along a strip (nearby nodes, as a mesh's consecutive faces are), a few with no DOF.
  std::vector<BlockAssembly::ElementNodes> elements;
  for (int e = 0; e < 1000; ++e) {
    BlockAssembly::ElementNodes en;
    en.fill(-1);
    for (int a = 0; a < 6; ++a) en[a] = e % 97 == 0 ? -1 : (e * nodes / 1000 + int(rng() % 12)) % nodes;
    elements.push_back(en);
  }
  const BlockAssembly a(nodes, elements);
  std::vector<int> seen(elements.size(), 0);
  for (const auto& colour : a.chunk_colours()) {
    std::vector<int> owner(nodes, -1);
    for (std::size_t c = 0; c < colour.size(); ++c) {
      EXPECT_LE(colour[c].end - colour[c].begin, BlockAssembly::kChunkElements);
      for (int e = colour[c].begin; e < colour[c].end; ++e) {
        ++seen[e];
        for (int n : elements[e])
          if (n >= 0) {
            EXPECT_TRUE(owner[n] < 0 || owner[n] == int(c)) << "node " << n << " in two chunks of one colour";
            owner[n] = int(c);
          }
      }
    }
  }
  for (int s : seen) EXPECT_EQ(s, 1);
  EXPECT_GT(a.chunk_colours().size(), 1u);
  EXPECT_LT(a.chunk_colours().size(), 8u);  // a strip: each chunk meets only its neighbours
}

TEST(CholmodSolver, FactorizesAndSolvesLikeDenseCholesky) {
  std::mt19937 rng(2);
  const int nodes = 60;
  const auto elements = random_elements(nodes, 200, rng);
  const BlockAssembly a(nodes, elements);
  CholmodSolver chol;
  chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
  EXPECT_TRUE(chol.analyzed());
  EXPECT_FALSE(chol.has_factor());
  EXPECT_TRUE(chol.supernodal());
  std::normal_distribution<double> n;
  // Several numeric refactorisations on the one symbolic analysis, with and without a shift.
  for (int round = 0; round < 3; ++round) {
    std::vector<double> values;
    Eigen::MatrixXd dense;
    assemble_random(a, elements, rng, values, dense);
    const double shift = round == 2 ? 0.5 : 0.0;
    ASSERT_TRUE(chol.factorize(values.data(), shift));
    EXPECT_TRUE(chol.has_factor());
    EXPECT_EQ(chol.shift(), shift);
    Eigen::VectorXd b(a.num_dofs()), x(a.num_dofs());
    for (int i = 0; i < b.size(); ++i) b[i] = n(rng);
    chol.solve(b.data(), x.data());
    const Eigen::MatrixXd shifted = dense + shift * Eigen::MatrixXd::Identity(b.size(), b.size());
    const Eigen::VectorXd reference = shifted.llt().solve(b);
    EXPECT_LE((x - reference).norm(), 1e-10 * reference.norm()) << "round " << round;
    EXPECT_LE((shifted * x - b).norm(), 1e-10 * b.norm());
    EXPECT_GT(chol.rcond(), 0.0);
  }
  EXPECT_GT(chol.factor_nonzeros(), 0);
  EXPECT_NE(chol.ordering(), "none");
}

TEST(CholmodSolver, EveryOrderingSolvesTheSameSystem) {
  std::mt19937 rng(5);
  const int nodes = 80;
  const auto elements = random_elements(nodes, 260, rng);
  const BlockAssembly a(nodes, elements);
  std::vector<double> values;
  Eigen::MatrixXd dense;
  assemble_random(a, elements, rng, values, dense);
  Eigen::VectorXd b(a.num_dofs());
  std::normal_distribution<double> n;
  for (int i = 0; i < b.size(); ++i) b[i] = n(rng);
  const Eigen::VectorXd reference = dense.llt().solve(b);
  const std::pair<Ordering, const char*> cases[] = {
      {Ordering::Amd, "amd"}, {Ordering::Metis, "metis"}, {Ordering::Nesdis, "nesdis"}, {Ordering::Automatic, "amd"}};
  for (const auto& [ordering, name] : cases) {
    CholmodSolver chol(ordering);
    chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
    EXPECT_EQ(chol.ordering(), name);
    EXPECT_GT(chol.factorization_flops(), 0.0);
    ASSERT_TRUE(chol.factorize(values.data()));
    Eigen::VectorXd x(b.size());
    chol.solve(b.data(), x.data());
    EXPECT_LE((x - reference).norm(), 1e-10 * reference.norm()) << name;
  }
  // The same with OpenBLAS parallel (a budget of four, the threshold at zero), after serial
  // factorisations stopped its workers, and serial again.
  const double threshold = parallel_factor_flops();
  set_parallel_factor_flops(0);
  for (int threads : {4, 1}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    tbb::task_arena arena(threads);
    arena.execute([&] {
      CholmodSolver chol;
      chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
      ASSERT_TRUE(chol.factorize(values.data()));
      Eigen::VectorXd x(b.size());
      chol.solve(b.data(), x.data());
      EXPECT_LE((x - reference).norm(), 1e-10 * reference.norm()) << threads << " threads";
    });
  }
  set_parallel_factor_flops(threshold);
  // Automatic chooses by size.
  EXPECT_EQ(choose_ordering(kMetisFromDofs - 1), Ordering::Amd);
  EXPECT_EQ(choose_ordering(kMetisFromDofs), Ordering::Metis);
}

TEST(CholmodSolver, ReportsIndefiniteMatricesAndMisuse) {
  // A 2×2-block (6 DOF) matrix with a negative eigenvalue.
  const std::vector<BlockAssembly::ElementNodes> elements{BlockAssembly::nodes({0, 1})};
  const BlockAssembly a(2, elements);
  Eigen::Matrix<double, 6, 6> local = Eigen::Matrix<double, 6, 6>::Identity();
  local(4, 4) = -2.0;
  std::vector<double> values(std::size_t(a.num_nonzeros()), 0.0);
  a.scatter_matrix<2>(0, local, values.data());

  CholmodSolver chol;
  std::vector<double> b(6, 1.0), x(6);
  EXPECT_THROW(chol.factorize(values.data()), InternalError);  // before analyze
  chol.analyze(a.num_dofs(), a.column_starts(), a.row_indices());
  EXPECT_THROW(chol.solve(b.data(), x.data()), InternalError);  // no factor yet
  EXPECT_FALSE(chol.factorize(values.data()));               // CHOLMOD_NOT_POSDEF
  EXPECT_FALSE(chol.has_factor());
  EXPECT_THROW(chol.solve(b.data(), x.data()), InternalError);
  EXPECT_TRUE(chol.factorize(values.data(), 2.5));  // shifted past the negative eigenvalue
  chol.solve(b.data(), x.data());
  EXPECT_NEAR(x[4], 1.0 / 0.5, 1e-12);
  EXPECT_NEAR(x[0], 1.0 / 3.5, 1e-12);
  EXPECT_THROW(chol.analyze(0, {0}, {}), SolveError);
}

}  // namespace
}  // namespace cutwork::solvers

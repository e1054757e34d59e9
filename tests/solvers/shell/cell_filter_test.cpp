// The cell filter of fill ratios (solvers/shell/cell_filter.h): a convex combination per row
// (B·1 = 1, entries ≥ 0), its pull-back is its transpose, the blend keeps resolved faces as they
// are, the neighbourhood never jumps between sheets that are close in space but not connected,
// and a perforation that alternates face by face is averaged to its mean.
#include <gtest/gtest.h>

#include <random>

#include "host/core/error.h"
#include "host/mesh/mirror.h"
#include "solvers/shell/cell_filter.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork::solvers {
namespace {

Eigen::VectorXd constant(const SurfaceMesh& m, double v) { return Eigen::VectorXd::Constant(m.num_faces(), v); }

TEST(CellFilter, RowsAreConvexCombinationsAndThePullBackIsTheTranspose) {
  const SurfaceMesh mesh = test::jittered(test::equilateral_rectangle(1.0, 0.5, 20), 0.2, 3);
  // Spacing 3 edges, stencils 1.5 edges across: h/d ≈ 0.67, a partial blend.
  const double h = 0.05;
  const CellFilter filter(mesh, constant(mesh, 3 * h), constant(mesh, 1.5 * h));
  ASSERT_FALSE(filter.identity());
  const auto& B = filter.matrix();
  for (int t = 0; t < B.rows(); ++t) {
    double sum = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(B, t); it; ++it) {
      EXPECT_GE(it.value(), 0.0);
      sum += it.value();
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "row " << t;
  }
  EXPECT_GT(filter.mean_row_size(), 6);
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(0.01, 1.0);
  Eigen::VectorXd alpha(mesh.num_faces()), g(mesh.num_faces());
  for (int t = 0; t < mesh.num_faces(); ++t) alpha[t] = u(gen), g[t] = u(gen) - 0.5;
  const Eigen::VectorXd filtered = filter.apply(alpha);
  EXPECT_GE(filtered.minCoeff(), alpha.minCoeff());
  EXPECT_LE(filtered.maxCoeff(), alpha.maxCoeff());
  EXPECT_NEAR(g.dot(filtered), filter.pull_back(g).dot(alpha), 1e-12 * g.cwiseAbs().sum());
  EXPECT_TRUE(filter.apply(constant(mesh, 1.0)).isApprox(constant(mesh, 1.0), 1e-14));
  EXPECT_THROW(filter.apply(Eigen::VectorXd::Ones(3)), InputError);
  EXPECT_THROW(CellFilter(mesh, constant(mesh, -1.0), constant(mesh, h)), InputError);
}

TEST(CellFilter, BlendKeepsResolvedFacesAndAveragesLargeOnes) {
  EXPECT_EQ(cell_filter_blend(0.1), 0.0);
  EXPECT_EQ(cell_filter_blend(0.25), 0.0);
  EXPECT_EQ(cell_filter_blend(1.0), 1.0);
  EXPECT_EQ(cell_filter_blend(3.0), 1.0);
  EXPECT_NEAR(cell_filter_blend(0.625), 0.5, 1e-15);
  for (double x = 0.25; x < 1; x += 0.05) EXPECT_LT(cell_filter_blend(x), cell_filter_blend(x + 0.05));

  const SurfaceMesh mesh = test::equilateral_rectangle(1.0, 0.5, 20);
  // Stencils eight edges across: four triangles across a stencil and more, every face keeps its α.
  const CellFilter resolved(mesh, constant(mesh, 0.6), constant(mesh, 0.4));
  std::mt19937 gen(1);
  std::uniform_real_distribution<double> u(0.01, 1.0);
  Eigen::VectorXd alpha(mesh.num_faces());
  for (int t = 0; t < mesh.num_faces(); ++t) alpha[t] = u(gen);
  EXPECT_EQ((resolved.apply(alpha) - alpha).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(resolved.blend().maxCoeff(), 0.0);
  EXPECT_EQ(resolved.resolution().minCoeff(), 1.0);
  // Stencils smaller than an edge: every face takes the cell's α and resolves nothing.
  const CellFilter large(mesh, constant(mesh, 0.025), constant(mesh, 0.02));  // (border faces are halves)
  EXPECT_EQ(large.blend().minCoeff(), 1.0);
  EXPECT_EQ(large.resolution().maxCoeff(), 0.0);
  EXPECT_EQ(CellFilter().resolution().size(), 0);
}

// Faces marked to keep their own α (scene_cell_filter marks those at a clamp) are rows of the
// identity with blend 0, and columns with their diagonal entry only: no other face's average counts
// them. The rows whose cones do not reach a marked face are those of the unmarked filter.
TEST(CellFilter, MarkedFacesKeepTheirOwnFillRatio) {
  const SurfaceMesh mesh = test::equilateral_rectangle(1.0, 0.5, 20);
  const double h = 0.05;
  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  auto centroid_x = [&](int t) { return (V(F(t, 0), 0) + V(F(t, 1), 0) + V(F(t, 2), 0)) / 3; };
  std::vector<bool> marked(size_t(mesh.num_faces()), false);
  for (int t = 0; t < mesh.num_faces(); ++t) marked[size_t(t)] = centroid_x(t) < 0.1;
  const double spacing = 3 * h;
  const CellFilter plain(mesh, constant(mesh, spacing), constant(mesh, 2 * h));
  const CellFilter kept(mesh, constant(mesh, spacing), constant(mesh, 2 * h), &marked);
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(0.01, 1.0);
  Eigen::VectorXd alpha(mesh.num_faces());
  for (int t = 0; t < mesh.num_faces(); ++t) alpha[t] = u(gen);
  const Eigen::VectorXd a = plain.apply(alpha), b = kept.apply(alpha);
  int n_marked = 0, n_filtered = 0, n_far = 0, n_near_changed = 0;
  for (int t = 0; t < mesh.num_faces(); ++t) {
    if (marked[size_t(t)]) {
      ++n_marked;
      EXPECT_EQ(b[t], alpha[t]) << "face " << t;
      EXPECT_EQ(kept.blend()[t], 0.0);
      EXPECT_EQ(kept.resolution()[t], plain.resolution()[t]);  // a mark is not a resolution
      EXPECT_EQ(kept.resolution()[t], 1 - plain.blend()[t]);
      n_filtered += a[t] != alpha[t];
    } else if (centroid_x(t) > 0.1 + spacing + h) {  // its cone ends short of the marks
      ++n_far;
      EXPECT_EQ(b[t], a[t]) << "face " << t;
    } else {
      n_near_changed += b[t] != a[t];
    }
  }
  EXPECT_GT(n_marked, 10);
  EXPECT_GT(n_far, 100);
  EXPECT_EQ(n_filtered, n_marked);  // without the marks those faces were averaged
  EXPECT_GT(n_near_changed, 10);    // and counted in their neighbours' averages
  // Columns: a marked face appears in its own row only. Rows still sum to 1.
  const auto& B = kept.matrix();
  for (int t = 0; t < B.outerSize(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(B, t); it; ++it) {
      if (marked[size_t(it.col())]) {
        EXPECT_EQ(it.row(), it.col()) << "face " << it.col() << " in row " << it.row();
      }
    }
  EXPECT_NEAR((kept.apply(Eigen::VectorXd::Ones(mesh.num_faces())).array() - 1).abs().maxCoeff(), 0.0, 1e-14);
  // A solid margin at the clamp (α = 1 there) and a uniform lattice inside (α = 0.4): the faces
  // inside read the lattice's 0.4 exactly, where counting the margin raised those next to it.
  Eigen::VectorXd margin(mesh.num_faces());
  for (int t = 0; t < mesh.num_faces(); ++t) margin[t] = marked[size_t(t)] ? 1.0 : 0.4;
  const Eigen::VectorXd inside = kept.apply(margin), raised = plain.apply(margin);
  double worst = 0, highest = 0;
  for (int t = 0; t < mesh.num_faces(); ++t) {
    if (marked[size_t(t)]) continue;
    worst = std::max(worst, std::abs(inside[t] - 0.4));
    highest = std::max(highest, raised[t]);
  }
  EXPECT_LT(worst, 1e-14);
  EXPECT_GT(highest, 0.45);
  const std::vector<bool> wrong(3, false);
  EXPECT_THROW(CellFilter(mesh, constant(mesh, 3 * h), constant(mesh, 2 * h), &wrong), InputError);
}

TEST(CellFilter, AnAlternatingPerforationIsAveragedToItsMean) {
  // Faces alternately nearly empty and full (what 1-stencil-per-face coverage looks like), on
  // triangles as large as the stencils: away from the border the filtered field is the mean 0.55
  // within a few percent; unfiltered it swings by ±0.45.
  const SurfaceMesh mesh = test::equilateral_rectangle(1.0, 1.0, 20);
  const double h = 0.05;
  Eigen::VectorXd alpha(mesh.num_faces());
  const RowMatX3d& V = mesh.vertices();
  const RowMatX3i& F = mesh.faces();
  for (int t = 0; t < mesh.num_faces(); ++t) {
    // Up- and down-pointing triangles alternate along every row.
    const double ymid = (V(F(t, 0), 1) + V(F(t, 1), 1) + V(F(t, 2), 1)) / 3;
    int below = 0;
    for (int k = 0; k < 3; ++k) below += V(F(t, k), 1) < ymid;
    alpha[t] = below == 2 ? 0.1 : 1.0;
  }
  const CellFilter filter(mesh, constant(mesh, 2 * h), constant(mesh, h));
  const Eigen::VectorXd filtered = filter.apply(alpha);
  double worst = 0;
  for (int t = 0; t < mesh.num_faces(); ++t) {
    const Vec3 c = (V.row(F(t, 0)) + V.row(F(t, 1)) + V.row(F(t, 2))).transpose() / 3;
    if (c.x() < 0.15 || c.x() > 0.85 || c.y() < 0.15 || c.y() > 0.85) continue;
    worst = std::max(worst, std::abs(filtered[t] - 0.55));
  }
  EXPECT_LT(worst, 0.03);
  EXPECT_GT((alpha.array() - 0.55).abs().minCoeff(), 0.4);
}

// A half on a symmetry plane (and a quarter on two) filters as the whole its mirror images make:
// on the whole of a jittered half mesh mirrored in y = 0 (then x = 0), with a fill ratio field that
// is the half's mirrored, the whole's filtered α on the half's faces is the half's with the planes to
// round-off; without the planes the faces beside them differ (their cones stopped at the plane).
TEST(CellFilter, AHalfOnASymmetryPlaneFiltersAsTheWhole) {
  const SurfaceMesh half = test::jittered(test::equilateral_rectangle(0.6, 0.3, 12), 0.2, 5);  // x, y ≥ 0
  const double h = 0.05;
  for (int planes : {1, 2}) {
    SCOPED_TRACE(planes == 1 ? "a half on y = 0" : "a quarter on y = 0 and x = 0");
    const Vec3 mirror(planes == 2 ? 0.0 : NAN, 0.0, NAN);
    MirroredMesh m = mirror_across_plane(half.vertices(), half.faces(), 1, 0.0, 1e-12);
    if (planes == 2) m = mirror_across_plane(m.vertices, m.faces, 0, 0.0, 1e-12);
    const SurfaceMesh whole(m.vertices, m.faces, "whole");
    std::mt19937 gen(11);
    std::uniform_real_distribution<double> u(0.05, 1.0);
    Eigen::VectorXd alpha(half.num_faces());
    for (int t = 0; t < half.num_faces(); ++t) alpha[t] = u(gen);
    // The whole's faces are the half's, then their images (each block a copy of the last).
    Eigen::VectorXd whole_alpha(whole.num_faces());
    for (int t = 0; t < whole.num_faces(); ++t) whole_alpha[t] = alpha[t % half.num_faces()];
    std::vector<bool> keep(size_t(half.num_faces()), false), whole_keep(size_t(whole.num_faces()), false);
    keep[0] = true;  // a marked face (at a clamp) and its images
    for (int t = 0; t < whole.num_faces(); t += half.num_faces()) whole_keep[size_t(t)] = true;
    const Eigen::VectorXd expected =
        CellFilter(whole, constant(whole, 3 * h), constant(whole, 1.5 * h), &whole_keep).apply(whole_alpha);
    const Eigen::VectorXd mirrored =
        CellFilter(half, constant(half, 3 * h), constant(half, 1.5 * h), &keep, mirror).apply(alpha);
    const Eigen::VectorXd stopped = CellFilter(half, constant(half, 3 * h), constant(half, 1.5 * h), &keep).apply(alpha);
    EXPECT_LT((mirrored - expected.head(half.num_faces())).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_GT((stopped - expected.head(half.num_faces())).cwiseAbs().maxCoeff(), 1e-3);
  }
}

TEST(CellFilter, SheetsCloseInSpaceDoNotMix) {
  // Two unit squares 1 mm apart (a folded sheet's two sides, a table top over its shelf): the
  // filter's radius is far larger than the gap, yet no row reaches the other sheet.
  const SurfaceMesh a = test::grid_rectangle(1.0, 1.0, 10, 10);
  RowMatX3d V(2 * a.num_vertices(), 3);
  RowMatX3i F(2 * a.num_faces(), 3);
  V << a.vertices(), a.vertices().rowwise() + Eigen::RowVector3d(0, 0, 0.001);
  F << a.faces(), a.faces().array() + a.num_vertices();
  const SurfaceMesh two(V, F, "two sheets");
  const CellFilter filter(two, constant(two, 0.3), constant(two, 0.1));
  const int half = a.num_faces();
  const auto& B = filter.matrix();
  for (int t = 0; t < B.rows(); ++t)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(B, t); it; ++it)
      EXPECT_EQ(t < half, it.col() < half) << "row " << t << " reaches " << it.col();
}

}  // namespace
}  // namespace cutwork::solvers

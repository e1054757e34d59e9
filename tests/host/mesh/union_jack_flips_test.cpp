// The union-jack diagonals of a mesh turned one way (host/mesh/union_jack_flips.h): the pattern
// found and taken apart to valence 6, nothing else touched, creases kept.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "host/mesh/union_jack_flips.h"
#include "tests/solvers/support/test_meshes.h"

namespace cutwork {
namespace {

/// An n × n grid over [0, 1]², lifted by z(x, y), its quads cut along alternating diagonals
/// (`union_jack`) or all along the same one.
SurfaceMesh grid(int n, bool union_jack, const std::function<double(double, double)>& z = {}) {
  RowMatX3d V((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = double(i) / n, y = double(j) / n;
      V.row(j * (n + 1) + i) << x, y, z ? z(x, y) : 0.0;
    }
  RowMatX3i F(2 * n * n, 3);
  int f = 0;
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (!union_jack || (i + j) % 2 == 0) {
        F.row(f++) << a, b, c;
        F.row(f++) << a, c, d;
      } else {
        F.row(f++) << a, b, d;
        F.row(f++) << b, c, d;
      }
    }
  return SurfaceMesh(V, F, "grid");
}

std::vector<int> valences(const SurfaceMesh& m) {
  std::vector<int> v(std::size_t(m.num_vertices()), 0);
  for (int e = 0; e < m.num_edges(); ++e)
    for (int k = 0; k < 2; ++k) ++v[std::size_t(m.edges()(e, k))];
  return v;
}

TEST(UnionJackFlips, TurnThePatternsDiagonalsOneWay) {
  const SurfaceMesh jack = grid(8, true);
  const UnionJackFlips out = flip_union_jack_diagonals(jack);
  EXPECT_GT(out.union_jack_edges, 0);
  EXPECT_EQ(out.flips, 30);  // half of the quads, less the corners the pattern's rule does not reach
  ASSERT_EQ(out.mesh.num_faces(), jack.num_faces());
  EXPECT_EQ(out.mesh.vertices(), jack.vertices());
  EXPECT_NEAR(out.mesh.face_areas().sum(), 1.0, 1e-12);
  for (int f = 0; f < out.mesh.num_faces(); ++f) EXPECT_GT(out.mesh.face_normals()(f, 2), 0.999) << f;
  // Every inner vertex at valence 6 (was 4 or 8), but where a corner quad, which the pattern's rule
  // does not reach (no inner vertex opposite its diagonal), kept its diagonal the other way.
  const std::vector<int> v = valences(out.mesh);
  int off = 0;
  for (int i = 0; i < out.mesh.num_vertices(); ++i)
    if (!out.mesh.is_boundary_vertex()[std::size_t(i)]) {
      EXPECT_GE(v[std::size_t(i)], 5);
      EXPECT_LE(v[std::size_t(i)], 7);
      off += v[std::size_t(i)] != 6;
    }
  EXPECT_LE(off, 4);
}

TEST(UnionJackFlips, LeaveOtherMeshesAlone) {
  for (const SurfaceMesh& m : {grid(8, false), test::equilateral_rectangle(1, 1, 8)}) {
    const UnionJackFlips out = flip_union_jack_diagonals(m);
    EXPECT_EQ(out.flips, 0);
    EXPECT_EQ(out.union_jack_edges, 0);
    EXPECT_EQ(out.mesh.faces(), m.faces());
  }
}

// A coarse saddle: each quad is folded across its diagonal by more than kUnionJackMaxDihedral, so
// turning the diagonal would change the surface: nothing is flipped though the pattern is there.
TEST(UnionJackFlips, KeepCreases) {
  const SurfaceMesh saddle = grid(6, true, [](double x, double y) { return 3 * (x - 0.5) * (y - 0.5); });
  const UnionJackFlips out = flip_union_jack_diagonals(saddle);
  EXPECT_GT(out.union_jack_edges, 0);
  EXPECT_EQ(out.flips, 0);
  // A gentle one is a smooth surface: turned.
  const SurfaceMesh gentle = grid(6, true, [](double x, double y) { return 0.05 * (x - 0.5) * (y - 0.5); });
  EXPECT_GT(flip_union_jack_diagonals(gentle).flips, 0);
}

}  // namespace
}  // namespace cutwork

#include "host/mesh/surface_mesh.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "host/core/error.h"
#include "tests/host/mesh/mesh_fixtures.h"

namespace cutwork {
namespace {

using test::MeshArrays;

std::pair<int, int> sorted_pair(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

/// True when face f walks the directed edge a -> b.
bool face_has_directed_edge(const SurfaceMesh& m, int f, int a, int b) {
  for (int k = 0; k < 3; ++k)
    if (m.faces()(f, k) == a && m.faces()(f, (k + 1) % 3) == b) return true;
  return false;
}

int opposite_vertex(const SurfaceMesh& m, int f, int a, int b) {
  for (int k = 0; k < 3; ++k)
    if (m.faces()(f, k) != a && m.faces()(f, k) != b) return m.faces()(f, k);
  return -1;
}

/// Connectivity invariants every valid mesh must satisfy, checked without the hash maps.
void expect_consistent_connectivity(const SurfaceMesh& m) {
  const int ne = m.num_edges();
  std::set<std::pair<int, int>> unique;
  for (int e = 0; e < ne; ++e) {
    EXPECT_LT(m.edges()(e, 0), m.edges()(e, 1));
    unique.insert({m.edges()(e, 0), m.edges()(e, 1)});
  }
  EXPECT_EQ(int(unique.size()), ne) << "edges are not unique";

  std::vector<int> uses(ne, 0);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int e = m.face_edges()(f, k);
      const int a = m.faces()(f, k), b = m.faces()(f, (k + 1) % 3);
      EXPECT_EQ(sorted_pair(a, b), std::make_pair(m.edges()(e, 0), m.edges()(e, 1)));
      EXPECT_TRUE(m.edge_faces()(e, 0) == f || m.edge_faces()(e, 1) == f);
      ++uses[e];
    }
  int interior = 0;
  for (int e = 0; e < ne; ++e) {
    EXPECT_EQ(uses[e], m.edge_faces()(e, 1) < 0 ? 1 : 2);
    interior += m.edge_faces()(e, 1) >= 0;
  }
  ASSERT_EQ(int(m.hinges().size()), interior);

  for (const Hinge& h : m.hinges()) {
    EXPECT_EQ(sorted_pair(h.v[0], h.v[1]), std::make_pair(m.edges()(h.edge, 0), m.edges()(h.edge, 1)));
    EXPECT_TRUE(face_has_directed_edge(m, h.face[0], h.v[0], h.v[1]));
    EXPECT_TRUE(face_has_directed_edge(m, h.face[1], h.v[1], h.v[0]));
    EXPECT_EQ(h.v[2], opposite_vertex(m, h.face[0], h.v[0], h.v[1]));
    EXPECT_EQ(h.v[3], opposite_vertex(m, h.face[1], h.v[0], h.v[1]));
  }

  // Boundary loops: every boundary edge exactly once, walked the way its face walks it.
  int boundary_edges = 0;
  for (int e = 0; e < ne; ++e) boundary_edges += m.edge_faces()(e, 1) < 0;
  int loop_edges = 0;
  std::vector<bool> on_loop(m.num_vertices(), false);
  for (const auto& loop : m.boundary_loops()) {
    ASSERT_GE(loop.size(), 3u);
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      on_loop[a] = true;
      bool found = false;
      for (int f = 0; f < m.num_faces() && !found; ++f) found = face_has_directed_edge(m, f, a, b);
      EXPECT_TRUE(found) << "loop step " << a << "->" << b << " is not a face's directed edge";
      ++loop_edges;
    }
  }
  EXPECT_EQ(loop_edges, boundary_edges);
  for (int v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(m.is_boundary_vertex()[v], on_loop[v]) << v;
}

void expect_geometry(const SurfaceMesh& m) {
  for (int f = 0; f < m.num_faces(); ++f) {
    const Vec3 a = m.vertices().row(m.faces()(f, 0)), b = m.vertices().row(m.faces()(f, 1)),
               c = m.vertices().row(m.faces()(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    EXPECT_NEAR(m.face_areas()[f], 0.5 * n.norm(), 1e-15);
    EXPECT_NEAR((m.face_normals().row(f).transpose() - n.normalized()).norm(), 0, 1e-14);
  }
  // Area-weighted vertex normals, summed here face by face without the mesh's arrays.
  RowMatX3d sum = RowMatX3d::Zero(m.num_vertices(), 3);
  for (int f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      sum.row(m.faces()(f, k)) += 2 * m.face_areas()[f] * m.face_normals().row(f);
  for (int v = 0; v < m.num_vertices(); ++v) {
    EXPECT_NEAR(m.vertex_normals().row(v).norm(), 1, 1e-14);
    EXPECT_NEAR((m.vertex_normals().row(v) - sum.row(v).normalized()).norm(), 0, 1e-14) << "vertex " << v;
  }
}

/// Signed area of a closed polygon in the xy plane (positive = counter-clockwise).
double signed_area_xy(const SurfaceMesh& m, const std::vector<int>& loop) {
  double a = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const auto p = m.vertices().row(loop[i]), q = m.vertices().row(loop[(i + 1) % loop.size()]);
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a / 2;
}

TEST(SurfaceMesh, SquareTopologyAndHingeOrder) {
  const SurfaceMesh m = test::make(test::square());
  EXPECT_EQ(m.num_vertices(), 4);
  EXPECT_EQ(m.num_edges(), 5);
  EXPECT_EQ(m.num_faces(), 2);
  EXPECT_EQ(m.euler_characteristic(), 1);
  EXPECT_EQ(m.num_components(), 1);
  ASSERT_EQ(m.hinges().size(), 1u);
  const Hinge& h = m.hinges()[0];
  // Shared edge (0,2): face 0 = (0,1,2) walks it as 2 -> 0, opposite vertex 1; face 1 = (0,2,3)
  // walks 0 -> 2, opposite vertex 3.
  EXPECT_EQ(h.face[0], 0);
  EXPECT_EQ(h.face[1], 1);
  EXPECT_EQ((std::array<int, 4>{h.v[0], h.v[1], h.v[2], h.v[3]}), (std::array<int, 4>{2, 0, 1, 3}));
  ASSERT_EQ(m.boundary_loops().size(), 1u);
  // Counter-clockwise seen from +z (the face normals' side), as a cyclic sequence 0 1 2 3.
  const auto& loop = m.boundary_loops()[0];
  ASSERT_EQ(loop.size(), 4u);
  const auto start = std::find(loop.begin(), loop.end(), 0) - loop.begin();
  for (int i = 0; i < 4; ++i) EXPECT_EQ(loop[(start + i) % 4], i);
  for (int f = 0; f < 2; ++f) EXPECT_NEAR(m.face_normals()(f, 2), 1.0, 1e-15);
  expect_consistent_connectivity(m);
  expect_geometry(m);
  EXPECT_DOUBLE_EQ(m.face_areas().sum(), 1.0);
  EXPECT_NEAR(m.mean_edge_length(), (4 + std::sqrt(2.0)) / 5, 1e-15);
  EXPECT_EQ(m.bbox_min(), Vec3(0, 0, 0));
  EXPECT_EQ(m.bbox_max(), Vec3(1, 1, 0));
}

TEST(SurfaceMesh, TetrahedronIsClosedWithOutwardNormals) {
  const SurfaceMesh m = test::make(test::tetrahedron());
  EXPECT_EQ(m.num_edges(), 6);
  EXPECT_EQ(m.euler_characteristic(), 2);
  EXPECT_EQ(m.hinges().size(), 6u);
  EXPECT_TRUE(m.boundary_loops().empty());
  EXPECT_EQ(m.num_components(), 1);
  const Vec3 center(0.25, 0.25, 0.25);
  for (int f = 0; f < 4; ++f) {
    const Vec3 c = (m.vertices().row(m.faces()(f, 0)) + m.vertices().row(m.faces()(f, 1)) +
                    m.vertices().row(m.faces()(f, 2))).transpose() / 3;
    EXPECT_GT(m.face_normals().row(f).dot(c - center), 0) << "face " << f << " points inwards";
  }
  for (int v = 0; v < 4; ++v)
    EXPECT_GT(m.vertex_normals().row(v).dot(m.vertices().row(v).transpose() - center), 0);
  expect_consistent_connectivity(m);
  expect_geometry(m);
}

TEST(SurfaceMesh, IcosphereCountsAndNormals) {
  for (int levels = 0; levels <= 3; ++levels) {
    SCOPED_TRACE(levels);
    const SurfaceMesh m = test::make(test::icosphere(levels));
    const int faces = 20 << (2 * levels);
    EXPECT_EQ(m.num_faces(), faces);
    EXPECT_EQ(m.num_edges(), faces * 3 / 2);
    EXPECT_EQ(m.num_vertices(), faces / 2 + 2);
    EXPECT_EQ(m.euler_characteristic(), 2);
    EXPECT_TRUE(m.boundary_loops().empty());
    EXPECT_EQ(int(m.hinges().size()), m.num_edges());
    EXPECT_EQ(m.num_components(), 1);
    for (int v = 0; v < m.num_vertices(); ++v)  // close to radial (the icosphere is irregular)
      EXPECT_GT(m.vertex_normals().row(v).dot(m.vertices().row(v)), 0.999);
    // Inscribed polyhedron: the area grows towards 4π from below.
    EXPECT_LT(m.face_areas().sum(), 4 * std::numbers::pi);
    if (levels == 3) {
      EXPECT_GT(m.face_areas().sum(), 0.99 * 4 * std::numbers::pi);
    }
    expect_consistent_connectivity(m);
    expect_geometry(m);
  }
}

TEST(SurfaceMesh, AnnulusHasTwoOppositelyOrientedLoops) {
  const int around = 24, rings = 3;
  const SurfaceMesh m = test::make(test::annulus(around, rings));
  EXPECT_EQ(m.euler_characteristic(), 0);
  EXPECT_EQ(m.num_components(), 1);
  for (int f = 0; f < m.num_faces(); ++f) EXPECT_NEAR(m.face_normals()(f, 2), 1, 1e-15);
  ASSERT_EQ(m.boundary_loops().size(), 2u);
  int outer = 0, inner = 0;
  for (const auto& loop : m.boundary_loops()) {
    EXPECT_EQ(int(loop.size()), around);
    const double area = signed_area_xy(m, loop);
    // Surface on the left: the outer circle runs counter-clockwise, the hole clockwise.
    if (std::abs(area) > 2 * std::numbers::pi) {
      ++outer;
      EXPECT_GT(area, 0);
      for (int v : loop) EXPECT_GE(v, rings * around);
    } else {
      ++inner;
      EXPECT_LT(area, 0);
      for (int v : loop) EXPECT_LT(v, around);
    }
  }
  EXPECT_EQ(outer, 1);
  EXPECT_EQ(inner, 1);
  int flagged = 0;
  for (bool b : m.is_boundary_vertex()) flagged += b;
  EXPECT_EQ(flagged, 2 * around);
  expect_consistent_connectivity(m);
  expect_geometry(m);
}

TEST(SurfaceMesh, BowtieLoopsStaySimpleAndComponentsCount) {
  // Two triangles touching at vertex 0 only: two components, two boundary loops of 3 vertices.
  const auto arrays = test::from_lists({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                       {{0, 1, 2}, {0, 3, 4}});
  const SurfaceMesh m = test::make(arrays);
  EXPECT_EQ(m.num_components(), 2);
  ASSERT_EQ(m.boundary_loops().size(), 2u);
  for (const auto& loop : m.boundary_loops()) EXPECT_EQ(loop.size(), 3u);
  expect_consistent_connectivity(m);

  // Two fans of a bumpy grid sharing one corner vertex in the middle of a larger mesh.
  const auto fans = test::from_lists(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 0, 0}, {-1, -1, 0}, {0, -1, 0}},
      {{0, 1, 2}, {0, 2, 3}, {0, 4, 5}, {0, 5, 6}});
  const SurfaceMesh b = test::make(fans);
  EXPECT_EQ(b.num_components(), 2);
  ASSERT_EQ(b.boundary_loops().size(), 2u);
  for (const auto& loop : b.boundary_loops()) EXPECT_EQ(loop.size(), 4u);
  expect_consistent_connectivity(b);
}

TEST(SurfaceMesh, UnreferencedVertexIsKept) {
  auto arrays = test::square();
  arrays.vertices.conservativeResize(5, 3);
  arrays.vertices.row(4) << 5, 5, 5;
  const SurfaceMesh m = test::make(arrays);
  EXPECT_EQ(m.num_vertices(), 5);
  EXPECT_FALSE(m.is_boundary_vertex()[4]);
  EXPECT_EQ(m.vertex_normals().row(4).norm(), 0.0);
  EXPECT_EQ(m.euler_characteristic(), 2);  // the lone vertex counts, like in any V − E + F
}

TEST(SurfaceMesh, QualityMeasures) {
  const auto equilateral =
      test::from_lists({{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}}, {{0, 1, 2}});
  const SurfaceMesh e = test::make(equilateral);
  EXPECT_NEAR(min_angle(e), std::numbers::pi / 3, 1e-14);
  EXPECT_NEAR(max_aspect_ratio(e), 1.0, 1e-14);
  const SurfaceMesh s = test::make(test::square());  // right isosceles triangles
  EXPECT_NEAR(min_angle(s), std::numbers::pi / 4, 1e-14);
  // l_max² √3 / (4A) with l_max = √2, A = 1/2
  EXPECT_NEAR(max_aspect_ratio(s), std::sqrt(3.0), 1e-14);
  const auto sliver = test::from_lists({{0, 0, 0}, {1, 0, 0}, {0.5, 0.01, 0}}, {{0, 1, 2}});
  EXPECT_GT(max_aspect_ratio(test::make(sliver)), 80);
  // Fractions of faces below an angle: the square's two faces have 45° corners.
  EXPECT_EQ(fraction_of_faces_below_angle(s, std::numbers::pi / 4 - 1e-9), 0.0);
  EXPECT_EQ(fraction_of_faces_below_angle(s, std::numbers::pi / 4 + 1e-9), 1.0);
  // An equilateral face beside a sliver (smallest angle atan(0.02) ≈ 1.15°): half of them below 10°.
  const auto mixed = test::from_lists({{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}, {0.5, -0.01, 0}},
                                      {{0, 1, 2}, {0, 3, 1}});
  const SurfaceMesh mx = test::make(mixed);
  EXPECT_EQ(fraction_of_faces_below_angle(mx, 10 * std::numbers::pi / 180), 0.5);
  EXPECT_NEAR(min_angle(mx), std::atan(0.02), 1e-12);
}

TEST(SurfaceMesh, PointAndPhongNormal) {
  for (const MeshArrays& arrays : {test::bumpy_grid(8), test::icosphere(2)}) {
    const SurfaceMesh m = test::make(arrays);
    for (int f = 0; f < m.num_faces(); ++f) {
      for (int k = 0; k < 3; ++k) {
        SurfacePoint corner{f, Vec3::Zero()};
        corner.bary[k] = 1;
        const int v = m.faces()(f, k);
        EXPECT_EQ(m.point(corner), m.vertices().row(v).transpose());
        EXPECT_NEAR((m.phong_normal(corner) - m.vertex_normals().row(v).transpose()).norm(), 0, 1e-15);
      }
      const SurfacePoint inside{f, Vec3(0.2, 0.3, 0.5)};
      const Vec3 expected = 0.2 * m.vertices().row(m.faces()(f, 0)) + 0.3 * m.vertices().row(m.faces()(f, 1)) +
                            0.5 * m.vertices().row(m.faces()(f, 2));
      EXPECT_NEAR((m.point(inside) - expected).norm(), 0, 1e-15);
      const Vec3 blended = 0.2 * m.vertex_normals().row(m.faces()(f, 0)) +
                           0.3 * m.vertex_normals().row(m.faces()(f, 1)) +
                           0.5 * m.vertex_normals().row(m.faces()(f, 2));
      EXPECT_NEAR((m.phong_normal(inside) - blended.normalized()).norm(), 0, 1e-15);
      EXPECT_GT(m.phong_normal(inside).dot(m.face_normals().row(f)), 0);
    }
  }
}

TEST(SurfaceMesh, TinyButValidTriangleIsAccepted) {
  // The zero-area test is relative to the triangle's size: a micrometre-scale mesh is fine.
  auto arrays = test::square();
  arrays.vertices *= 1e-6;
  const SurfaceMesh m = test::make(arrays);
  EXPECT_NEAR(m.face_areas().sum(), 1e-12, 1e-27);
}

/// Expects the constructor to throw InputError with exactly `message`.
void expect_rejected(const MeshArrays& arrays, const std::string& message) {
  try {
    SurfaceMesh m(arrays.vertices, arrays.faces, "bunny.obj");
    ADD_FAILURE() << "accepted; expected: " << message;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), message);
  }
}

TEST(SurfaceMesh, RejectsEachInvalidInputWithItsReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  MeshArrays a = test::square();

  expect_rejected({a.vertices, RowMatX3i(0, 3)}, "bunny.obj: no faces");

  MeshArrays bad = a;
  bad.vertices(2, 1) = nan;
  expect_rejected(bad, "bunny.obj: vertex 2 has a non-finite coordinate");
  bad = a;
  bad.vertices(3, 0) = -inf;
  expect_rejected(bad, "bunny.obj: vertex 3 has a non-finite coordinate");

  bad = a;
  bad.faces(1, 2) = 99;
  expect_rejected(bad, "bunny.obj: face 1 index 99 out of range [0,4)");
  bad = a;
  bad.faces(0, 0) = -1;
  expect_rejected(bad, "bunny.obj: face 0 index -1 out of range [0,4)");

  bad = a;
  bad.faces.row(1) << 0, 2, 2;
  expect_rejected(bad, "bunny.obj: face 1 repeats vertex 2");
  bad = a;
  bad.faces.row(0) << 1, 2, 1;
  expect_rejected(bad, "bunny.obj: face 0 repeats vertex 1");

  bad = a;  // vertex 3 moved onto the diagonal: face (0,2,3) collapses to a segment
  bad.vertices.row(3) << 0.25, 0.25, 0;
  expect_rejected(bad, "bunny.obj: face 1 has zero area");

  // Same vertex set in another order (and the opposite orientation).
  expect_rejected(test::from_lists({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                                   {{0, 1, 2}, {0, 2, 3}, {2, 0, 1}}),
                  "bunny.obj: faces 0 and 2 are duplicates");
  expect_rejected(test::from_lists({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
                                   {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}}),
                  "bunny.obj: faces 0 and 2 are duplicates");

  // Three faces on edge (0,1): a fin.
  expect_rejected(test::from_lists({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}},
                                   {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}),
                  "bunny.obj: edge (0,1) is shared by 3 faces (non-manifold): faces 0, 1, 2");

  // Face 1 flipped: both faces walk the diagonal 2 -> 0.
  expect_rejected(test::from_lists({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 3, 2}}),
                  "bunny.obj: faces 0 and 1 both use edge 2->0 in the same direction (inconsistent "
                  "orientation; flip one of them)");
}

}  // namespace
}  // namespace cutwork

// is_oriented_manifold_soup against its twin, CGAL's PMP::is_polygon_soup_a_polygon_mesh, on
// hand-made cases and on thousands of randomly damaged soups (open and closed meshes with faces
// removed, flipped, repeated, degenerated, or added between random vertices).
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <gtest/gtest.h>

#include <array>
#include <random>
#include <vector>

#include "host/export/solid.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

bool cgal_says(const RowMatX3i& faces) {
  std::vector<std::array<int, 3>> polygons(size_t(faces.rows()));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) polygons[size_t(f)] = {faces(f, 0), faces(f, 1), faces(f, 2)};
  return CGAL::Polygon_mesh_processing::is_polygon_soup_a_polygon_mesh(polygons);
}

RowMatX3i rows(const std::vector<std::array<int, 3>>& t) {
  RowMatX3i f(Eigen::Index(t.size()), 3);
  for (size_t i = 0; i < t.size(); ++i) f.row(Eigen::Index(i)) << t[i][0], t[i][1], t[i][2];
  return f;
}

TEST(ManifoldSoup, HandMadeCases) {
  // Two triangles sharing an edge, consistently oriented: a manifold with boundary.
  EXPECT_TRUE(is_oriented_manifold_soup(rows({{0, 1, 2}, {0, 2, 3}}), 4));
  // The same with one flipped: the directed edge 0→2 twice.
  EXPECT_FALSE(is_oriented_manifold_soup(rows({{0, 1, 2}, {0, 3, 2}}), 4));
  // Three triangles on one edge.
  EXPECT_FALSE(is_oriented_manifold_soup(rows({{0, 1, 2}, {1, 0, 3}, {1, 0, 4}}), 5));
  // A bow tie: two fans meeting at vertex 0 only.
  const RowMatX3i bowtie = rows({{0, 1, 2}, {0, 3, 4}});
  EXPECT_FALSE(is_oriented_manifold_soup(bowtie, 5));
  EXPECT_EQ(cgal_says(bowtie), false);
  // A closed fan (an open cone) around vertex 0 and the same with one face missing.
  EXPECT_TRUE(is_oriented_manifold_soup(rows({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 1}}), 5));
  EXPECT_TRUE(is_oriented_manifold_soup(rows({{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}), 5));
  // Repeated and out-of-range corners.
  EXPECT_FALSE(is_oriented_manifold_soup(rows({{0, 1, 1}}), 2));
  EXPECT_FALSE(is_oriented_manifold_soup(rows({{0, 1, 2}}), 2));
  EXPECT_FALSE(is_oriented_manifold_soup(rows({{0, -1, 2}}), 3));
  // Nothing, and isolated vertices, are fine.
  EXPECT_TRUE(is_oriented_manifold_soup(RowMatX3i(0, 3), 0));
  EXPECT_TRUE(is_oriented_manifold_soup(rows({{0, 1, 2}}), 10));
}

TEST(ManifoldSoup, AgreesWithCgalOnRandomlyDamagedSoups) {
  const SurfaceMesh plate = generate_shape("plate", {{"width", 0.1}, {"height", 0.1}}, 0.02);
  const Solid box = thicken_surface(plate.vertices(), plate.faces(), 0.01);
  std::mt19937 rng(7);
  int tried = 0, manifold = 0;
  for (const auto* base : {&plate.faces(), &box.faces}) {
    const int V = int(base == &box.faces ? box.vertices.rows() : plate.vertices().rows());
    ASSERT_TRUE(is_oriented_manifold_soup(*base, V));
    ASSERT_TRUE(cgal_says(*base));
    for (int trial = 0; trial < 1500; ++trial) {
      std::vector<std::array<int, 3>> t;
      for (Eigen::Index f = 0; f < base->rows(); ++f) t.push_back({(*base)(f, 0), (*base)(f, 1), (*base)(f, 2)});
      std::uniform_int_distribution<int> kind(0, 7), vertex(0, V - 1), count(1, 2);
      for (int m = count(rng); m > 0; --m) {
        std::uniform_int_distribution<size_t> face(0, t.size() - 1);
        switch (kind(rng)) {
          case 4: { auto& x = t[face(rng)]; std::swap(x[0], x[1]); break; }       // flip
          case 5: t.push_back(t[face(rng)]); break;                                // repeat
          case 6: { auto& x = t[face(rng)]; x[2] = x[0]; break; }                  // degenerate
          case 7: t.push_back({vertex(rng), vertex(rng), vertex(rng)}); break;     // random
          default: t.erase(t.begin() + long(face(rng))); break;                    // remove (half)
        }
        if (t.empty()) t.push_back({0, 1, 2});
      }
      const RowMatX3i f = rows(t);
      const bool ours = is_oriented_manifold_soup(f, V), cgal = cgal_says(f);
      ASSERT_EQ(ours, cgal) << "trial " << trial << " of " << (base == &box.faces ? "the box" : "the plate");
      ++tried;
      manifold += ours;
    }
  }
  // Both answers occur often enough for the comparison to mean something.
  EXPECT_GT(manifold, tried / 10);
  EXPECT_LT(manifold, tried - tried / 10);
}

}  // namespace
}  // namespace cutwork

// A mesh completed by its mirror image in a coordinate plane (host/mesh/mirror.h).
#include "host/mesh/mirror.h"

#include <gtest/gtest.h>

#include <cmath>

#include "host/mesh/surface_mesh.h"
#include "host/surfaces/generators.h"

namespace cutwork {
namespace {

// The plate's half x ∈ [−0.1, 0] mirrored in x = 0 is one surface: the vertices on the plane
// shared (snapped onto it), the others imaged, every face's image turned to face the same side, the
// area doubled, one boundary loop, and the whole mirror-symmetric.
TEST(Mirror, AHalfAndItsImageAreOneSurface) {
  SurfaceMesh half = generate_shape("plate", {{"width", 0.1}, {"height", 0.1}}, 0.01);
  RowMatX3d X = half.vertices();
  X.col(0).array() -= 0.05;  // x ∈ [−0.1, 0]
  int nudged = -1;  // a vertex a hair off the plane, which the mirror puts on it
  for (int v = 0; v < X.rows() && nudged < 0; ++v)
    if (std::abs(X(v, 0)) < 1e-12) nudged = v;
  ASSERT_GE(nudged, 0);
  X(nudged, 0) = -3e-13;
  half = SurfaceMesh(X, half.faces(), "half");
  int on_plane = 0;
  for (int v = 0; v < half.num_vertices(); ++v) on_plane += std::abs(X(v, 0)) < 1e-9;
  const MirroredMesh m = mirror_across_plane(half.vertices(), half.faces(), 0, 0.0, 1e-9);
  ASSERT_EQ(m.vertices.rows(), 2 * half.num_vertices() - on_plane);
  ASSERT_EQ(m.faces.rows(), 2 * half.num_faces());
  EXPECT_EQ(m.vertices(nudged, 0), 0.0);
  const SurfaceMesh whole(m.vertices, m.faces, "whole");
  EXPECT_NEAR(whole.face_areas().sum(), 2 * half.face_areas().sum(), 1e-12);  // (the snapped vertex moved 3e-13)
  EXPECT_EQ(whole.boundary_loops().size(), 1u);
  for (int f = 0; f < half.num_faces(); ++f) {
    const Vec3 n = whole.face_normals().row(f), image = whole.face_normals().row(half.num_faces() + f);
    EXPECT_NEAR(n.dot(image), 1.0, 1e-12) << f;  // flat: the same side up
  }
  for (int v = 0; v < half.num_vertices(); ++v) {
    const int w = m.image[std::size_t(v)];
    EXPECT_EQ(m.vertices(w, 0), -m.vertices(v, 0)) << v;
    EXPECT_EQ(m.vertices(w, 1), X(v, 1));
    EXPECT_EQ(w == v, std::abs(X(v, 0)) < 1e-9) << v;
  }
}

}  // namespace
}  // namespace cutwork

#pragma once
/// The printable solid: a cut surface thickened by the material thickness into a closed,
/// consistently oriented triangle mesh, its validity check (CGAL) and its files (STL, 3MF).
///
/// Thickening: every vertex v of the surface gets two copies v ± (t/2) n_v, n_v the area-
/// weighted vertex normal (the shell's mid-surface stays in the middle, as in the simulation);
/// the top copy keeps the surface's faces, the bottom copy gets them reversed, and every
/// boundary edge (a → b, the surface on its left) gets a wall of two triangles
/// (top_a, bottom_a, bottom_b), (top_a, bottom_b, top_b) whose normal points away from the
/// surface. For a manifold, consistently oriented surface the result is closed and oriented
/// outwards on the side the face normals point to; it can still self-intersect where the
/// surface curves more sharply than t/2 or where two stencil outlines touch at a vertex, which
/// is what check_solid finds.
#include <filesystem>
#include <string>

#include "host/core/types.h"
#include "host/mesh/bvh.h"

namespace cutwork {

/// A closed triangle mesh (metres).
struct Solid {
  RowMatX3d vertices;  ///< #V×3 (m): the surface's vertices offset up (first #V/2), then down
  RowMatX3i faces;     ///< #F×3, counter-clockwise seen from outside
  int wall_faces = 0;  ///< how many of the faces are boundary walls (the last ones)
};

/// Thickens `faces` on `vertices` by `thickness` (m, > 0; see the file comment). Throws
/// InputError for a non-positive thickness, no faces, or a surface that is not manifold along
/// its edges (an edge used twice in the same direction, or by more than two faces).
/// `normals` (#V×3 unit, optional) replaces the area-weighted vertex normals: the cut surface's
/// sliver triangles along outlines give noisy normals, so a design offsets along the smooth
/// Phong normals of the base surface instead (surface_normals_at).
Solid thicken_surface(const RowMatX3d& vertices, const RowMatX3i& faces, double thickness,
                      const RowMatX3d* normals = nullptr);

/// The Phong normal of the surface of `bvh` at the closest point to each of `points` (#P×3).
RowMatX3d surface_normals_at(const FaceBvh& bvh, const RowMatX3d& points);

/// What CGAL says about a solid (Polygon Mesh Processing, exact predicates).
struct SolidCheck {
  bool manifold = false;          ///< the triangle soup is a manifold polygon mesh
  bool closed = false;            ///< no border edges (CGAL::is_closed)
  bool self_intersecting = true;  ///< some pair of faces intersects (PMP::does_self_intersect)
  bool outward = false;           ///< oriented outwards (PMP::is_outward_oriented)
  bool bounds_volume = false;     ///< PMP::does_bound_a_volume
  double volume = 0;              ///< PMP::volume (m³), when closed
  double area = 0;                ///< PMP::area (m²)
  std::string problem;            ///< empty when valid, else the first problem in the order above
  bool valid() const { return problem.empty(); }
};

/// Checks `solid` with CGAL (the checks are listed in SolidCheck, in the order they run; the
/// later ones need the earlier ones to hold); the first, `manifold`, is
/// is_oriented_manifold_soup below.
SolidCheck check_solid(const Solid& solid);

/// Whether the triangles `faces` (indices into `num_vertices` vertices) form an oriented
/// 2-manifold with boundary — what CGAL's PMP::is_polygon_soup_a_polygon_mesh decides for a
/// triangle soup, on sorted arrays instead of a std::set node per edge (that set was half of all
/// page faults of a design): every triangle has three distinct vertices, no directed edge occurs
/// twice (consistent orientation, at most two faces per edge), and the faces around every vertex
/// form one fan (one path or one cycle of their opposite edges). O(F log F).
bool is_oriented_manifold_soup(const RowMatX3i& faces, Eigen::Index num_vertices);

/// Binary STL of `solid` in millimetres (the unit slicers assume), atomic.
void write_stl(const std::filesystem::path& path, const Solid& solid);

/// 3MF (lib3mf) of `solid` as one mesh object and build item, in millimetres, atomic. Throws
/// InputError naming the file with lib3mf's message when lib3mf fails.
void write_3mf(const std::filesystem::path& path, const Solid& solid, const std::string& name);

/// The vertices (mm) and triangles of the single mesh object of a 3MF file, read with lib3mf
/// (for tests and checks). Throws InputError naming the file when it cannot be read.
struct ThreeMfMesh {
  RowMatX3d vertices;
  RowMatX3i faces;
  std::string unit;
};
ThreeMfMesh read_3mf(const std::filesystem::path& path);

}  // namespace cutwork

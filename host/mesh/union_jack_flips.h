#pragma once
/// Union-jack patches of a triangle mesh, and the edge flips that take them apart.
///
/// A "union jack" is a grid of quads cut along alternating diagonals: inner vertices of valence 4
/// and 8 in a checkerboard, each diagonal joining two valence-8 vertices between two valence-4 ones.
/// On it the shape-operator bending element (solvers/shell/shape_operator_energy.h) has a spurious
/// mode: a checkerboard of normal displacements (±z on the two colours) is, on every face's
/// six-node patch, a quadratic — the patch reads it as the same uniform curvature (4z/h² in each
/// Voigt component) on every face — so it cancels part of any smooth curvature field at no cost of
/// its own. Measured (tests/solvers/equilibrium/shell_benchmarks_test.cpp): a flat square plate on
/// a union jack 73% too soft whatever the mesh size, the Scordelis-Lo roof 16%, where grids cut
/// along one diagonal, shifted rows and isotropic remeshes converge to the references. Meshes
/// cutwork makes never have the pattern; a mesh file may (quads of a CAD surface split both ways).
///
/// The remedy is on the simulation mesh: turn the pattern's diagonals all one way. The pattern's
/// quads are the face pairs across a diagonal with an inner valence-8 end and an inner valence-4
/// opposite vertex; neighbouring quads have their diagonals the other way, so each connected patch
/// of them is 2-coloured and one colour flipped, which leaves every inner vertex of the patch at
/// valence 6 (a grid cut along one diagonal, on which the element converges). A quad is flipped
/// only where its two faces are nearly coplanar (the flip re-triangulates the same four points;
/// across a crease it would change the shape) and its two new faces keep the old orientation.
/// Greedy valence-lowering flips (CGAL's rule) were tried first: they left the flat plate 14% too
/// soft (a quarter of the pattern's diagonals flipped: 15%).
#include <cstddef>
#include <string>

#include "host/mesh/surface_mesh.h"

namespace cutwork {

struct UnionJackFlips {
  SurfaceMesh mesh;          ///< the input with the flips made (the input itself when none)
  int flips = 0;             ///< edges flipped
  int union_jack_edges = 0;  ///< edges of the input with two inner valence-4 opposite vertices
};

/// Dihedral angle (degrees) between an edge's two faces above which it is never flipped.
inline constexpr double kUnionJackMaxDihedral = 10.0;
/// Connected quads of the pattern below which a patch is left alone (an irregular mesh may have a
/// valence-4 vertex beside a valence-8 one; that is no union jack).
inline constexpr std::size_t kUnionJackMinQuads = 4;

/// Flips the union-jack diagonals of `mesh` (see above), sweeping its edges in order and skipping
/// edges whose opposite vertices an earlier flip has already changed.
UnionJackFlips flip_union_jack_diagonals(const SurfaceMesh& mesh, double max_dihedral_degrees = kUnionJackMaxDihedral);

}  // namespace cutwork

#pragma once
/// Mesh files. OBJ (cutwork's own output format) is read in double precision with
/// tinyobjloader; PLY (ASCII and binary), OFF and STL go through assimp, which stores
/// coordinates as float. Vertices with identical positions are welded (STL stores triangle
/// soups, OBJ groups may repeat vertices), polygons are triangulated, and the result is
/// validated by the SurfaceMesh constructor. Writing is cutwork's own, atomic.
#include <filesystem>
#include <map>
#include <string>

#include "host/mesh/surface_mesh.h"

namespace cutwork {

/// Reads a mesh file. Throws InputError("<path>: <problem>") when the file is missing,
/// unreadable, empty, of an unknown format, or the mesh is invalid (see SurfaceMesh).
///
/// Notes: OBJ positions are exact: the doubles write_obj writes come back bit for bit (with
/// its numbering, when every vertex is used and distinct). PLY, OFF and STL positions come back
/// rounded to single precision (assimp's ai_real is float; binary STL is float anyway).
/// All meshes/groups/objects of a file become one surface. Faces keep the file's order
/// (polygons are replaced in place by their triangles; OBJ's relative, negative indices are
/// allowed). Welded vertices are numbered in the file's order — for OBJ only the vertices that
/// faces use, for STL in the order of first use by a face corner — and validation messages use
/// that numbering. PLY and OFF files first pass the structural checks of
/// host/mesh/mesh_file_checks.h, because assimp silently repairs (or hangs on) some broken
/// ones; OBJ files pass a scan of their own (see mesh_io.cpp). Point and line elements are
/// rejected, not skipped.
SurfaceMesh read_mesh(const std::filesystem::path& path);

/// True for the extensions read_mesh accepts (.obj .ply .off .stl, case-insensitive).
bool is_mesh_file(const std::filesystem::path& path);

/// Writes Wavefront OBJ (atomic).
void write_obj(const std::filesystem::path& path, const RowMatX3d& vertices, const RowMatX3i& faces);

/// Writes a binary little-endian PLY with per-face scalar properties (float64), readable by
/// MeshLab and ParaView (atomic). Each field must have #F entries.
void write_ply_with_face_fields(const std::filesystem::path& path, const SurfaceMesh& mesh,
                                const std::map<std::string, Eigen::VectorXd>& face_fields);

}  // namespace cutwork

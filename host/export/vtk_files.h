#pragma once
/// VTK XML files for ParaView: fields.vtu (the simulation mesh with its per-face and per-vertex
/// fields) and stencils.vtp (polylines), plus a reader for the .vtu files cutwork writes.
///
/// Format (VTK file format 1.0, "VTK XML"): ASCII data arrays, Float64 values written with 17
/// significant digits so they read back bit for bit, Int64 connectivity and offsets, UInt8 cell
/// types (5 = VTK_TRIANGLE, 4 = VTK_POLY_LINE). Face fields are CellData arrays, vertex fields
/// PointData arrays (vectors with NumberOfComponents="3"), each named by its map key.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "host/core/types.h"
#include "host/mesh/surface_mesh.h"

namespace cutwork {

/// Per-face scalars (each #F) and per-vertex 3-vectors (each #V×3) of one mesh.
struct MeshFields {
  std::map<std::string, Eigen::VectorXd> face;
  std::map<std::string, RowMatX3d> vertex;
};

/// Writes `mesh` with `fields` as a VTK UnstructuredGrid of triangles (atomic). Throws
/// InternalError when a field has the wrong size, InputError when the file cannot be written.
void write_vtu(const std::filesystem::path& path, const SurfaceMesh& mesh, const MeshFields& fields);

/// A .vtu file read back: points, triangles and the named arrays.
struct VtuContents {
  RowMatX3d vertices;
  RowMatX3i faces;
  MeshFields fields;
};

/// Reads an UnstructuredGrid of triangles with ASCII arrays (what write_vtu writes) with
/// libxml2. Throws InputError naming the file for anything else: not XML, another VTK type,
/// binary or appended data, cells that are not triangles, arrays of the wrong length.
VtuContents read_vtu(const std::filesystem::path& path);

/// Writes polylines as a VTK PolyData file (atomic): line i has the points `lines[i]` (#P_i×3),
/// closed by repeating its first point when `closed`; `cell_fields` are per-line scalars
/// (each #lines entries), e.g. the stencil index and type.
void write_vtp_polylines(const std::filesystem::path& path, const std::vector<RowMatX3d>& lines, bool closed,
                         const std::map<std::string, Eigen::VectorXd>& cell_fields);

/// A .vtp file of polylines read back (what write_vtp_polylines writes): each line's points
/// (a closed line ends with its first point again) and the per-line arrays. Same rules as
/// read_vtu.
struct VtpContents {
  std::vector<RowMatX3d> lines;
  std::map<std::string, Eigen::VectorXd> cell_fields;
};
VtpContents read_vtp_polylines(const std::filesystem::path& path);

}  // namespace cutwork

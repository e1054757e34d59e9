#include "host/mesh/mesh_io.h"

#include <Eigen/Geometry>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/core/input_file.h"
#include "host/core/work_limits.h"
#include "host/mesh/mesh_file_checks.h"
#include "host/mesh/polygon_triangulation.h"

#ifndef TINYOBJLOADER_USE_DOUBLE
#error "link tinyobjloader::tinyobjloader_double: OBJ files must be read in double precision"
#endif
static_assert(sizeof(tinyobj::real_t) == sizeof(double));

// assimp (Debian's build keeps its internal assertions) calls this on an internal consistency
// failure, and its own version aborts the process — e.g. when the triangulation step finds a
// face count that a reader got wrong on a malformed file. Defining it here interposes the
// library's definition (ELF symbol interposition; assimp is linked as a shared library), so
// the failure becomes an exception: Importer::ReadFile catches it and returns no scene, and
// read_mesh reports an InputError naming the file instead of the whole run dying.
namespace Assimp {
void aiAssertViolation(const char* failed_expression, const char* file, int line) {
  throw std::runtime_error(fmt::format("assimp internal check failed ({}) at {}:{}",
                                       failed_expression, file, line));
}
}  // namespace Assimp

namespace cutwork {
namespace fs = std::filesystem;

namespace {

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

/// Packs a coordinate so that welding compares exact values (−0 and +0 are the same point).
std::uint64_t weld_bits(double x) { return std::bit_cast<std::uint64_t>(x == 0.0 ? 0.0 : x); }

struct WeldKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const WeldKey& o) const { return bits == o.bits; }
};
struct WeldKeyHash {
  std::size_t operator()(const WeldKey& k) const {
    std::uint64_t h = 1469598103934665603ull;
    for (std::uint64_t b : k.bits) h = (h ^ b) * 1099511628211ull + (b >> 29);
    return std::size_t(h);
  }
};

template <typename T>
void put_le(std::string& out, T value) {
  auto bytes = std::bit_cast<std::array<char, sizeof(T)>>(value);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bytes.begin(), bytes.end());
  out.append(bytes.data(), bytes.size());
}

void check_faces_in_range(const fs::path& path, const RowMatX3d& vertices, const RowMatX3i& faces) {
  for (int f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      if (faces(f, k) < 0 || faces(f, k) >= vertices.rows())
        throw InternalError(fmt::format("{}: cannot write: face {} index {} out of range [0,{})",
                                     path.string(), f, faces(f, k), vertices.rows()));
}

// ---- OBJ: tinyobjloader (double build) plus a scan of the text ----------------------------
//
// tinyobjloader parses the statements, resolves relative indices, groups and triangulates. It
// is not trusted with what it gets wrong or hides, which a scan of the same text covers first:
//  - its number parser is not correctly rounded (a %.17g double comes back a few ulps off in
//    most cases), so the 'v' coordinates are read again here with std::from_chars;
//  - an unparsable coordinate silently becomes 0 ("v nan 1 0" is (0,1,0)), a missing one too;
//  - indices are read with atoi (overflow wraps, "3x" is 3); an out-of-range one gives at most
//    a warning, a relative one before the first vertex none, and it stays in the output;
//  - faces with fewer than 3 corners are dropped with a warning, and line and point elements
//    are kept apart from the faces (and dropped with their group on a 'g' line);
//  - its triangulation (2.0.0rc10) splits a quad along the shorter diagonal, the outside one
//    for a concave quad, and its ear clipping of larger polygons gets concave ones wrong (a
//    triangle outside the polygon, flipped) or gives up and drops the rest of the polygon.
//    Each polygon's triangles are checked against the polygon; a wrong set is replaced by
//    CGAL's triangulation of the polygon, and only when that fails too is it an InputError.

constexpr std::string_view kObjParseError = "cannot be parsed: OBJ";

[[noreturn]] void obj_fail(const std::string& what, const std::string& problem) {
  throw InputError(what + ": " + problem);
}

[[noreturn]] void obj_fail_at(const std::string& what, std::size_t line, const std::string& problem) {
  obj_fail(what, fmt::format("{} line {}: {}", kObjParseError, line, problem));
}

bool is_blank(char c) { return c == ' ' || c == '\t'; }

/// The next blank-separated token of `rest` (consumed); empty at the end of the line.
std::string_view next_token(std::string_view& rest) {
  std::size_t begin = 0;
  while (begin < rest.size() && is_blank(rest[begin])) ++begin;
  std::size_t end = begin;
  while (end < rest.size() && !is_blank(rest[end])) ++end;
  const std::string_view token = rest.substr(begin, end - begin);
  rest.remove_prefix(end);
  return token;
}

/// A leading '+' (accepted by OBJ writers and atoi, not by from_chars) is dropped.
std::string_view without_plus(std::string_view token) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '+' && token[1] != '-')
    token.remove_prefix(1);
  return token;
}

/// A decimal coordinate, correctly rounded; "nan" and "inf" parse (SurfaceMesh rejects them).
/// Beyond double's range it becomes ±inf or ±0 as strtod makes it.
std::optional<double> parse_coordinate(std::string_view token) {
  token = without_plus(token);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (end != token.data() + token.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return std::strtod(std::string(token).c_str(), nullptr);
  if (ec != std::errc()) return std::nullopt;
  return value;
}

/// An 'f' statement with more than 3 corners.
struct ObjPolygon {
  std::int64_t first_triangle;  ///< the number of its first triangle
  std::size_t first_corner;     ///< into ObjScan::polygon_corners
  int corners;
};

struct ObjScan {
  std::vector<Vec3> positions;      ///< the 'v' statements, in file order
  std::int64_t triangles = 0;       ///< what triangulating the 'f' statements must give
  std::vector<ObjPolygon> polygons;
  std::vector<int> polygon_corners;  ///< 0-based, relative indices resolved
  bool index_out_of_range = false;
};

/// Reads the 'v' coordinates and checks the 'f', 'l' and 'p' statements of an OBJ text; lines
/// end like tinyobjloader's (\n, \r\n or \r; a NUL ends the line's content). Throws at the first
/// problem in file order; an index beyond the last vertex is only flagged (see read_obj).
ObjScan scan_obj(std::string_view text, const std::string& what) {
  ObjScan scan;
  std::int64_t max_index = 0;
  std::size_t line_number = 0;
  while (!text.empty()) {
    std::size_t end = text.find_first_of("\r\n");
    std::string_view line = text.substr(0, end);
    if (end == std::string_view::npos) end = text.size();
    else if (text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n') end += 2;
    else end += 1;
    text.remove_prefix(end);
    ++line_number;
    line = line.substr(0, line.find('\0'));

    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (keyword == "v") {
      Vec3 p;
      for (int c = 0; c < 3; ++c) {
        const std::string_view token = next_token(rest);
        if (token.empty())
          obj_fail_at(what, line_number, fmt::format("vertex has {} coordinates, expected 3", c));
        const std::optional<double> x = parse_coordinate(token);
        if (!x)
          obj_fail_at(what, line_number, fmt::format("vertex coordinate '{}' is not a number", token));
        p[c] = *x;
      }
      scan.positions.push_back(p);  // further values (w, or a colour) are left to tinyobjloader
      if (scan.positions.size() >= std::size_t(INT_MAX))
        obj_fail_at(what, line_number, "too many vertices");
    } else if (keyword == "f" || keyword == "l" || keyword == "p") {
      int corners = 0;
      const std::size_t first_corner = scan.polygon_corners.size();
      for (std::string_view token = next_token(rest); !token.empty(); token = next_token(rest)) {
        ++corners;
        if (keyword != "f") continue;
        const std::string_view field = without_plus(token.substr(0, token.find('/')));
        int index = 0;
        const auto [ptr, ec] = std::from_chars(field.data(), field.data() + field.size(), index);
        if (ptr != field.data() + field.size() || field.empty() ||
            (ec != std::errc() && ec != std::errc::result_out_of_range))
          obj_fail_at(what, line_number, fmt::format("face corner '{}' is not a vertex index", token));
        if (ec == std::errc::result_out_of_range)
          scan.index_out_of_range = true;
        else if (index == 0)
          obj_fail_at(what, line_number,
                      fmt::format("face corner '{}' has vertex index 0 (OBJ counts from 1)", token));
        else if (index > 0)
          max_index = std::max<std::int64_t>(max_index, index);
        else if (std::int64_t(scan.positions.size()) + index < 0)  // relative to the last vertex
          scan.index_out_of_range = true;
        scan.polygon_corners.push_back(index > 0 ? index - 1 : int(scan.positions.size()) + index);
      }
      if (keyword != "f" || corners < 3)
        obj_fail(what, fmt::format("face {} has {} vertices: point and line elements are not "
                                   "supported, only triangle and polygon faces",
                                   scan.triangles, corners));
      if (corners > 3) scan.polygons.push_back({scan.triangles, first_corner, corners});
      else scan.polygon_corners.resize(first_corner);
      scan.triangles += corners - 2;
    }
  }
  if (max_index > std::int64_t(scan.positions.size())) scan.index_out_of_range = true;
  return scan;
}

/// The face cap (work_limits().max_faces), checked before the mesh's topology is built.
void check_face_count(std::size_t faces, const std::string& what) {
  const int limit = work_limits().max_faces;
  if (faces > std::size_t(limit))
    throw InputError(fmt::format("{}: has {} faces, more than the limit of {} (raise it with --max-faces if this "
                                 "is meant; a finer mesh than that is beyond what the solvers can factorise)",
                                 what, faces, limit));
}

/// tinyobjloader's message on one line (its messages span several).
std::string one_line(std::string message) {
  for (char& c : message)
    if (c == '\n' || c == '\r') c = ' ';
  while (!message.empty() && message.back() == ' ') message.pop_back();
  return message;
}

/// The triangles tinyobjloader makes of an OBJ text (`scan` is its scan_obj), in file order,
/// polygons fanned; throws for what tinyobjloader rejects or warns about that concerns the surface.
std::vector<std::array<int, 3>> tinyobj_triangles(const std::string& text, const ObjScan& scan,
                                                  const std::string& what) {
  const std::string out_of_range = fmt::format("{}: vertex index out of range", kObjParseError);
  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  try {
    // From the text already read: 'mtllib' files are neither needed nor opened.
    reader.ParseFromString(text, "", config);
  } catch (const std::exception& e) {
    obj_fail(what, fmt::format("{}: {}", kObjParseError, e.what()));
  }
  if (!reader.Valid() || !reader.Error().empty())
    obj_fail(what, fmt::format("{}: {}", kObjParseError,
                               reader.Error().empty() ? std::string("tinyobjloader failed")
                                                      : one_line(reader.Error())));
  // Warnings about materials, group names, normal or texture indices do not concern the
  // surface; those about vertex indices or dropped faces do.
  const std::string& warning = reader.Warning();
  if (warning.find("Vertex indices out of bounds") != std::string::npos ||
      warning.find("invalid vertex index") != std::string::npos)
    obj_fail(what, out_of_range);
  if (warning.find("Degenerated face") != std::string::npos)
    obj_fail(what, fmt::format("{}: {}", kObjParseError, one_line(warning)));

  const int nv = int(scan.positions.size());
  if (reader.GetAttrib().vertices.size() != 3 * scan.positions.size())
    obj_fail(what, fmt::format("{}: tinyobjloader read {} vertices, the file has {}", kObjParseError,
                               reader.GetAttrib().vertices.size() / 3, nv));
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(std::size_t(scan.triangles));
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    if (!shape.lines.indices.empty() || !shape.points.indices.empty())  // the scan rejects these
      obj_fail(what, fmt::format("{}: point or line elements", kObjParseError));
    const tinyobj::mesh_t& mesh = shape.mesh;
    std::size_t offset = 0;
    for (const unsigned int corners : mesh.num_face_vertices) {
      if (corners != 3 || offset + 3 > mesh.indices.size())
        obj_fail(what, fmt::format("face {} has {} vertices and could not be triangulated",
                                   triangles.size(), corners));
      std::array<int, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        tri[k] = mesh.indices[offset + k].vertex_index;
        if (tri[k] < 0 || tri[k] >= nv) obj_fail(what, out_of_range);
      }
      offset += 3;
      triangles.push_back(tri);
    }
  }
  return triangles;
}

/// Each polygon must have given corners − 2 triangles of its own corners (in file order:
/// triangles and quads always give 1 and 2), each facing like the polygon (its normal by
/// Newell's method; a self-intersecting polygon may have none). Triangles of exactly zero
/// area are left to the SurfaceMesh checks, which name them.
/// A set that fails is the polygon triangulated again by CGAL (triangulate_polygon; concave
/// polygons, which tinyobjloader gets wrong), checked the same way, and replaces the set in
/// `triangles`. A set must also cover the polygon's (projected) area |Newell normal| / 2 once,
/// and contain no zero-area triangle unless no valid set avoids one (corners on a line):
/// SurfaceMesh then names the degenerate face.
void check_polygon_triangles(const ObjScan& scan, std::vector<std::array<int, 3>>& triangles,
                             const std::string& what) {
  for (const ObjPolygon& polygon : scan.polygons) {
    const int* corners = scan.polygon_corners.data() + polygon.first_corner;
    const int* corners_end = corners + polygon.corners;
    Vec3 normal = Vec3::Zero();
    for (int k = 0; k < polygon.corners; ++k)
      normal += scan.positions[std::size_t(corners[k])].cross(
          scan.positions[std::size_t(corners[(k + 1) % polygon.corners])]);
    const std::int64_t first = polygon.first_triangle, count = polygon.corners - 2;
    auto tiles_the_polygon = [&](std::span<const std::array<int, 3>> tris, bool allow_zero_area) {
      if (std::int64_t(tris.size()) != count) return false;
      double twice_total = 0;
      for (const std::array<int, 3>& tri : tris) {
        for (int v : tri)
          if (std::find(corners, corners_end, v) == corners_end) return false;
        const Vec3& a = scan.positions[std::size_t(tri[0])];
        const Vec3& b = scan.positions[std::size_t(tri[1])];
        const Vec3& c = scan.positions[std::size_t(tri[2])];
        const Vec3 twice_area = (b - a).cross(c - a);
        if (!(twice_area.dot(normal) > 0.0 || (allow_zero_area && twice_area.isZero(0.0)))) return false;
        twice_total += twice_area.dot(normal);
      }
      // Vector area is additive: the triangles of a tiling sum to the polygon's Newell normal,
      // planar or warped; projected on it, |normal|².
      return std::abs(twice_total - normal.squaredNorm()) <= 1e-9 * normal.squaredNorm();
    };
    if (first + count > std::int64_t(triangles.size()))
      obj_fail(what, fmt::format("face {} has {} vertices and could not be triangulated", first, polygon.corners));
    const std::span<std::array<int, 3>> own(triangles.data() + first, std::size_t(count));
    if (tiles_the_polygon(own, false)) continue;
    std::vector<Vec3> outline;
    outline.reserve(std::size_t(polygon.corners));
    for (const int* c = corners; c != corners_end; ++c) outline.push_back(scan.positions[std::size_t(*c)]);
    std::vector<std::array<int, 3>> again = triangulate_polygon(outline);
    for (auto& tri : again)
      for (int& v : tri) v = corners[v];
    if (tiles_the_polygon(again, false) ||
        (!tiles_the_polygon(own, true) && tiles_the_polygon(again, true))) {
      std::copy(again.begin(), again.end(), own.begin());
      continue;
    }
    if (!tiles_the_polygon(own, true))
      obj_fail(what, fmt::format("face {} has {} vertices and could not be triangulated (self-intersecting "
                                 "or degenerate polygon?)",
                                 first, polygon.corners));
  }
  if (std::int64_t(triangles.size()) != scan.triangles)
    obj_fail(what, fmt::format("{}: the faces give {} triangles, {} expected", kObjParseError,
                               triangles.size(), scan.triangles));
}

/// Reads an OBJ text in double precision. All shapes become one surface, faces in file order
/// (polygons replaced by their triangles); the vertices that faces use are welded by exact
/// position and numbered in file order.
SurfaceMesh read_obj(std::string text, const std::string& what) {
  if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);  // a UTF-8 byte order mark
  const ObjScan scan = scan_obj(text, what);
  if (scan.index_out_of_range) obj_fail(what, fmt::format("{}: vertex index out of range", kObjParseError));
  std::vector<std::array<int, 3>> triangles = tinyobj_triangles(text, scan, what);
  check_polygon_triangles(scan, triangles, what);

  // Weld the used vertices by exact position, numbered in file order (a file that cutwork
  // wrote, with every vertex used and distinct, keeps its numbering).
  const int nv = int(scan.positions.size());
  std::vector<char> used(std::size_t(nv), 0);
  for (const auto& tri : triangles)
    for (int v : tri) used[std::size_t(v)] = 1;
  std::unordered_map<WeldKey, int, WeldKeyHash> weld;
  std::vector<int> welded(std::size_t(nv), -1);
  std::vector<int> kept;
  for (int v = 0; v < nv; ++v) {
    if (!used[std::size_t(v)]) continue;
    const Vec3& p = scan.positions[std::size_t(v)];
    const WeldKey key{{weld_bits(p.x()), weld_bits(p.y()), weld_bits(p.z())}};
    auto [it, inserted] = weld.emplace(key, int(kept.size()));
    if (inserted) kept.push_back(v);
    welded[std::size_t(v)] = it->second;
  }
  RowMatX3d vertices(kept.size(), 3);
  for (std::size_t v = 0; v < kept.size(); ++v) vertices.row(v) = scan.positions[std::size_t(kept[v])];
  RowMatX3i faces(triangles.size(), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) faces(f, k) = welded[std::size_t(triangles[f][k])];
  check_face_count(std::size_t(faces.rows()), what);
  return SurfaceMesh(std::move(vertices), std::move(faces), what);
}

}  // namespace

bool is_mesh_file(const fs::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

SurfaceMesh read_mesh(const fs::path& path) {
  const std::string what = path.string();
  auto fail = [&](const std::string& problem) { throw InputError(what + ": " + problem); };

  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) fail("file not found");
  if (fs::is_directory(status)) fail("is a directory, not a mesh file");
  if (!is_mesh_file(path)) {
    const std::string ext = path.extension().string();
    fail(fmt::format("unknown mesh format '{}' (expected .obj, .ply, .off or .stl)",
                     ext.empty() ? "no extension" : excerpt(ext, 20)));
  }
  // A regular file (a FIFO would block) of at most max_mesh_file_bytes.
  std::string content = read_input_file(path, max_mesh_file_bytes, "a mesh file");
  if (content.empty()) fail("file is empty");
  const std::string ext = lower_extension(path);

  // OBJ, cutwork's own output format, is read in double precision (tinyobjloader's double
  // build; see read_obj). The other formats go through assimp, which stores coordinates as
  // float: exact for binary STL (float by definition) and float PLY, rounded for double PLY
  // and for ASCII PLY, OFF and STL.
  if (ext == ".obj") return read_obj(std::move(content), what);
  if (ext == ".off") check_off_structure(content, what);
  else if (ext == ".ply") check_ply_structure(content, what);
  else check_stl_structure(content, what);
  content = std::string();

  // Only triangulation: assimp's repairing steps (FindDegenerates, FindInvalidData,
  // ValidateDataStructure fixes, JoinIdenticalVertices with normal splitting) would hide
  // problems that the SurfaceMesh validation must report.
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(what, aiProcess_Triangulate);
  } catch (const std::exception& e) {
    fail("cannot be parsed: " + excerpt(e.what(), 200));
  }
  // assimp's messages may quote the file: one bounded line.
  if (scene == nullptr) fail("cannot be parsed: " + excerpt(importer.GetErrorString(), 200));
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    fail("cannot be parsed: assimp reports an incomplete scene");

  // All meshes of the file become one surface; vertices with identical positions are welded
  // (STL arrives split per face corner). Welded vertices keep the order in which assimp
  // delivers them, which for PLY and OFF is the file's own vertex order.
  std::unordered_map<WeldKey, int, WeldKeyHash> weld;
  std::vector<Vec3> positions;
  std::vector<std::array<int, 3>> triangles;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    std::vector<int> welded(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const Vec3 p(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
      const WeldKey key{{weld_bits(p.x()), weld_bits(p.y()), weld_bits(p.z())}};
      auto [it, inserted] = weld.emplace(key, int(positions.size()));
      if (inserted) positions.push_back(p);
      welded[v] = it->second;
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      const int face_number = int(triangles.size());
      if (face.mNumIndices < 3)
        fail(fmt::format("face {} has {} vertices: point and line elements are not supported, "
                         "only triangle and polygon faces",
                         face_number, face.mNumIndices));
      if (face.mNumIndices > 3)
        fail(fmt::format("face {} has {} vertices and could not be triangulated", face_number,
                         face.mNumIndices));
      std::array<int, 3> tri{};
      for (int k = 0; k < 3; ++k) {
        const unsigned index = face.mIndices[k];
        if (index >= mesh->mNumVertices)  // PLY keeps any index it reads; a negative one wraps
          fail(fmt::format("face {} index {} out of range [0,{})", face_number,
                           std::int64_t(std::int32_t(index)), mesh->mNumVertices));
        tri[k] = welded[index];
      }
      triangles.push_back(tri);
    }
  }

  RowMatX3d vertices(positions.size(), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) vertices.row(v) = positions[v];
  RowMatX3i faces(triangles.size(), 3);
  for (std::size_t f = 0; f < triangles.size(); ++f)
    faces.row(f) << triangles[f][0], triangles[f][1], triangles[f][2];
  check_face_count(std::size_t(faces.rows()), what);
  return SurfaceMesh(std::move(vertices), std::move(faces), what);
}

void write_obj(const fs::path& path, const RowMatX3d& vertices, const RowMatX3i& faces) {
  check_faces_in_range(path, vertices, faces);
  fmt::memory_buffer buffer;
  fmt::format_to(std::back_inserter(buffer), "# cutwork surface mesh: {} vertices, {} faces\n",
                 vertices.rows(), faces.rows());
  // 17 significant digits: doubles survive the text round trip exactly.
  for (int v = 0; v < vertices.rows(); ++v)
    fmt::format_to(std::back_inserter(buffer), "v {:.17g} {:.17g} {:.17g}\n", vertices(v, 0),
                   vertices(v, 1), vertices(v, 2));
  for (int f = 0; f < faces.rows(); ++f)
    fmt::format_to(std::back_inserter(buffer), "f {} {} {}\n", faces(f, 0) + 1, faces(f, 1) + 1,
                   faces(f, 2) + 1);
  write_file_atomic(path, std::string_view(buffer.data(), buffer.size()));
}

void write_ply_with_face_fields(const fs::path& path, const SurfaceMesh& mesh,
                                const std::map<std::string, Eigen::VectorXd>& face_fields) {
  const int nv = mesh.num_vertices(), nf = mesh.num_faces();
  for (const auto& [name, field] : face_fields) {
    const bool valid_name =
        !name.empty() && std::none_of(name.begin(), name.end(), [](unsigned char c) {
          return std::isspace(c) || !std::isprint(c);
        });
    if (!valid_name)
      throw InternalError(fmt::format("{}: face field name '{}' is not a valid PLY property name "
                                   "(non-empty, printable, no spaces)",
                                   path.string(), name));
    if (field.size() != nf)
      throw InternalError(fmt::format("{}: face field '{}' has {} entries, expected one per face ({})",
                                   path.string(), name, field.size(), nf));
  }
  std::string out;
  out += "ply\nformat binary_little_endian 1.0\ncomment written by cutwork\n";
  out += fmt::format("element vertex {}\nproperty double x\nproperty double y\nproperty double z\n", nv);
  out += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", nf);
  for (const auto& [name, field] : face_fields) out += "property double " + name + "\n";
  out += "end_header\n";
  out.reserve(out.size() + std::size_t(nv) * 24 + std::size_t(nf) * (13 + 8 * face_fields.size()));
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) put_le<double>(out, V(v, k));
  for (int f = 0; f < nf; ++f) {
    put_le<std::uint8_t>(out, 3);
    for (int k = 0; k < 3; ++k) put_le<std::int32_t>(out, F(f, k));
    for (const auto& [name, field] : face_fields) put_le<double>(out, field[f]);
  }
  write_file_atomic(path, out);
}

}  // namespace cutwork

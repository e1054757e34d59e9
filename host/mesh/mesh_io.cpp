#include "host/mesh/mesh_io.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/mesh/mesh_file_checks.h"

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
        throw InputError(fmt::format("{}: cannot write: face {} index {} out of range [0,{})",
                                     path.string(), f, faces(f, k), vertices.rows()));
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
                     ext.empty() ? "no extension" : ext));
  }
  std::ifstream probe(path, std::ios::binary);
  if (!probe) fail("cannot be opened for reading (check its permissions)");
  const auto size = fs::file_size(path, ec);
  if (ec) fail("cannot be read (" + ec.message() + ")");
  if (size == 0) fail("file is empty");
  const std::string ext = lower_extension(path);
  if (ext == ".off" || ext == ".ply" || ext == ".stl") {
    std::stringstream content;
    content << probe.rdbuf();
    if (ext == ".off") check_off_structure(content.str(), what);
    else if (ext == ".ply") check_ply_structure(content.str(), what);
    else check_stl_structure(content.str(), what);
  }
  probe.close();

  // Only triangulation: assimp's repairing steps (FindDegenerates, FindInvalidData,
  // ValidateDataStructure fixes, JoinIdenticalVertices with normal splitting) would hide
  // problems that the SurfaceMesh validation must report.
  Assimp::Importer importer;
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(what, aiProcess_Triangulate);
  } catch (const std::exception& e) {
    fail(std::string("cannot be parsed: ") + e.what());
  }
  if (scene == nullptr) fail(std::string("cannot be parsed: ") + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    fail("cannot be parsed: assimp reports an incomplete scene");

  // All meshes of the file become one surface; vertices with identical positions are welded
  // (OBJ and STL arrive split per face corner). Welded vertices keep the order in which assimp
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
      throw InputError(fmt::format("{}: face field name '{}' is not a valid PLY property name "
                                   "(non-empty, printable, no spaces)",
                                   path.string(), name));
    if (field.size() != nf)
      throw InputError(fmt::format("{}: face field '{}' has {} entries, expected one per face ({})",
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

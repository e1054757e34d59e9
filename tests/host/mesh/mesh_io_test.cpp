#include "host/mesh/mesh_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/mesh/polygon_triangulation.h"
#include "tests/host/mesh/mesh_fixtures.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;

fs::path meshes() { return test::data_dir() / "meshes"; }

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void spit(const fs::path& p, const std::string& content) {
  std::ofstream out(p, std::ios::binary);
  out << content;
}

/// Same faces in the same order, each corner at the same position (vertex numbering may
/// differ: readers that split vertices per corner renumber them when welding).
void expect_same_surface(const SurfaceMesh& read, const RowMatX3d& vertices, const RowMatX3i& faces) {
  ASSERT_EQ(read.num_faces(), faces.rows());
  for (int f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(read.vertices().row(read.faces()(f, k)), vertices.row(faces(f, k))) << "face " << f << " corner " << k;
}

RowMatX3d float_rounded(const RowMatX3d& v) { return v.cast<float>().cast<double>(); }

/// Bit for bit (== would let -0 pass for +0).
void expect_same_bits(const RowMatX3d& read, const RowMatX3d& expected) {
  ASSERT_EQ(read.rows(), expected.rows());
  for (int v = 0; v < read.rows(); ++v)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(std::bit_cast<std::uint64_t>(read(v, c)), std::bit_cast<std::uint64_t>(expected(v, c)))
          << "vertex " << v << " coordinate " << c << ": read " << read(v, c) << ", written "
          << expected(v, c);
}

void expect_tetrahedron(const SurfaceMesh& m) {
  const auto t = test::tetrahedron();
  EXPECT_EQ(m.num_vertices(), 4);
  EXPECT_EQ(m.num_edges(), 6);
  EXPECT_EQ(m.euler_characteristic(), 2);
  EXPECT_TRUE(m.boundary_loops().empty());
  expect_same_surface(m, t.vertices, t.faces);
}

TEST(ReadMesh, EveryTextFormat) {
  for (const char* name : {"tetrahedron.obj", "tetrahedron.ply", "tetrahedron.off", "tetrahedron.stl"}) {
    SCOPED_TRACE(name);
    expect_tetrahedron(read_mesh(meshes() / name));
  }
}

TEST(ReadMesh, PolygonsAreTriangulatedAndGroupsWelded) {
  // quad_strip_relative.obj repeats the shared vertices in each object and uses relative indices.
  for (const char* name : {"quad_strip.obj", "quad_strip_relative.obj"}) {
    SCOPED_TRACE(name);
    const SurfaceMesh m = read_mesh(meshes() / name);
    EXPECT_EQ(m.num_faces(), 4);
    EXPECT_EQ(m.num_vertices(), 6);
    EXPECT_EQ(m.num_components(), 1);
    EXPECT_EQ(m.boundary_loops().size(), 1u);
    EXPECT_EQ(m.euler_characteristic(), 1);
    EXPECT_DOUBLE_EQ(m.face_areas().sum(), 2.0);
    for (int f = 0; f < 4; ++f) EXPECT_DOUBLE_EQ(m.face_normals()(f, 2), 1.0);
  }
}

TEST(ReadMesh, ConcavePolygonsAreTriangulatedInsideTheirOutline) {
  // Concave polygons (tinyobjloader's own triangulation puts triangles outside them) give
  // corners − 2 triangles that tile the polygon: all facing like it, their areas summing to the
  // polygon's (shoelace), none outside it.
  struct Polygon {
    const char* name;
    std::vector<std::array<double, 2>> corners;
  };
  const std::vector<Polygon> polygons{
      {"arrowhead", {{3, 0}, {-1, 0.5}, {-0.5, 0}, {-1, -0.5}}},
      {"L", {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}},
      {"U", {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}}},
      {"comb", {{0, 0}, {5, 0}, {5, 2}, {4, 2}, {4, 1}, {3, 1}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}},
      {"clockwise L", {{0, 3}, {1, 3}, {1, 1}, {2, 1}, {2, 0}, {0, 0}}},
  };
  const fs::path dir = test::temp_dir("mesh-io-concave");
  for (const Polygon& polygon : polygons) {
    SCOPED_TRACE(polygon.name);
    const int n = int(polygon.corners.size());
    std::string text;
    double shoelace = 0;
    for (int k = 0; k < n; ++k) {
      const auto& [x, y] = polygon.corners[std::size_t(k)];
      const auto& [x1, y1] = polygon.corners[std::size_t((k + 1) % n)];
      text += fmt::format("v {} {} 0\n", x, y);
      shoelace += 0.5 * (x * y1 - x1 * y);
    }
    text += "f";
    for (int k = 1; k <= n; ++k) text += fmt::format(" {}", k);
    spit(dir / "polygon.obj", text + "\n");
    const SurfaceMesh m = read_mesh(dir / "polygon.obj");
    ASSERT_EQ(m.num_faces(), n - 2);
    EXPECT_EQ(m.num_vertices(), n);
    EXPECT_NEAR(m.face_areas().sum(), std::abs(shoelace), 1e-12 * std::abs(shoelace));
    for (int f = 0; f < m.num_faces(); ++f)
      EXPECT_DOUBLE_EQ(m.face_normals()(f, 2), shoelace > 0 ? 1.0 : -1.0) << "face " << f;
    EXPECT_EQ(m.boundary_loops().size(), 1u);
    EXPECT_EQ(m.euler_characteristic(), 1);
  }
  // A warped (non-planar) quad, common in architectural meshes, is two triangles as before.
  spit(dir / "warped.obj", "v 0 0 0\nv 1 0 0.2\nv 1 1 0\nv 0 1 0.2\nf 1 2 3 4\n");
  const SurfaceMesh warped = read_mesh(dir / "warped.obj");
  EXPECT_EQ(warped.num_faces(), 2);
  for (int f = 0; f < 2; ++f) EXPECT_GT(warped.face_normals()(f, 2), 0.9);
  // The arrowhead as a file in the test data.
  const SurfaceMesh arrow = read_mesh(meshes() / "concave_quad.obj");
  EXPECT_EQ(arrow.num_faces(), 2);
  EXPECT_NEAR(arrow.face_areas().sum(), 1.75, 1e-15);
}

TEST(TriangulatePolygon, RefusesOutlinesThatAreNotSimple) {
  // A concave outline through two distinct vertices at one position (a fuzzing finding: CGAL's
  // face triangulation read freed memory on it) is refused; the same outline without the repeat
  // is triangulated.
  const std::vector<Vec3> repeated = {{0, 0, 0}, {3, 0, 0}, {3, 3, 0}, {2, 3, 0}, {2, 1, 0}, {2, 1, 0}, {1, 1, 0},
                                      {1, 3, 0}, {0, 3, 0}};
  EXPECT_TRUE(triangulate_polygon(repeated).empty());
  std::vector<Vec3> simple = repeated;
  simple.erase(simple.begin() + 5);
  EXPECT_EQ(triangulate_polygon(simple).size(), simple.size() - 2);
  // A bow tie (edges crossing) and a spike folding back along its edge are refused as well.
  EXPECT_TRUE(triangulate_polygon(std::vector<Vec3>{{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}).empty());
  EXPECT_TRUE(triangulate_polygon(std::vector<Vec3>{{0, 0, 0}, {2, 0, 0}, {1, 0, 0}, {1, 1, 0}}).empty());
}

TEST(ReadMesh, ObjSyntaxVariants) {
  // A UTF-8 byte order mark, CRLF and lone CR line ends, comments, blank lines, a leading '+',
  // exponents, extra vertex values (w, colour), v/vt/vn corners, relative indices, groups,
  // objects, smoothing groups, materials (the .mtl is never opened) and unknown statements.
  const fs::path dir = test::temp_dir("mesh-io-obj-syntax");
  spit(dir / "tet.obj",
       "\xEF\xBB\xBFv 0 0 0\r\n# header\r\n\r\nmtllib missing.mtl\r\n  v\t+1 0 0 1\r\n"
       "v 0 1e0 0 0.5 0.5 0.5\rv 0 0 10e-1\r\nvt 0 0\nvn 0 0 1\n"
       "o solid\ng a b\ns off\nusemtl none\nf 1/1/1 3/1/1 2/1/1\nf 1//1 2//1 4//1\n"
       "g c\nf -3/-1 -2/-1 -1/-1\ncstype bezier\nf 1 4 3  \n");
  expect_tetrahedron(read_mesh(dir / "tet.obj"));
}

std::string binary_stl(const RowMatX3d& v, const RowMatX3i& f, std::uint32_t declared) {
  std::string s(80, ' ');
  s.replace(0, 13, "binary cutwrk");  // must not start with "solid"
  auto put = [&](auto x) { s.append(reinterpret_cast<const char*>(&x), sizeof(x)); };
  put(declared);
  for (int i = 0; i < f.rows(); ++i) {
    for (int k = 0; k < 3; ++k) put(0.0f);  // normal (ignored)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) put(float(v(f(i, k), c)));
    put(std::uint16_t(0));
  }
  return s;
}

TEST(ReadMesh, BinaryStlWeldsTheTriangleSoup) {
  static_assert(std::endian::native == std::endian::little, "test writes native little endian");
  const fs::path dir = test::temp_dir("mesh-io-stl");
  const auto t = test::icosphere(2);
  spit(dir / "sphere.stl", binary_stl(t.vertices, t.faces, std::uint32_t(t.faces.rows())));
  const SurfaceMesh m = read_mesh(dir / "sphere.stl");
  EXPECT_EQ(m.num_vertices(), t.vertices.rows());  // welded back from 3 per face
  EXPECT_EQ(m.euler_characteristic(), 2);
  expect_same_surface(m, float_rounded(t.vertices), t.faces);
}

TEST(ReadMesh, BinaryPlyBothEndiannesses) {
  const fs::path dir = test::temp_dir("mesh-io-ply");
  const auto t = test::tetrahedron();
  for (bool little : {true, false}) {
    std::string s = std::string("ply\nformat ") + (little ? "binary_little_endian" : "binary_big_endian") +
                    " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
    auto put = [&](auto x) {
      auto bytes = std::bit_cast<std::array<char, sizeof(x)>>(x);
      if (little != (std::endian::native == std::endian::little)) std::reverse(bytes.begin(), bytes.end());
      s.append(bytes.data(), bytes.size());
    };
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c) put(float(t.vertices(i, c)));
    for (int i = 0; i < 4; ++i) {
      put(std::uint8_t(3));
      for (int k = 0; k < 3; ++k) put(std::int32_t(t.faces(i, k)));
    }
    const fs::path file = dir / (little ? "le.ply" : "be.ply");
    spit(file, s);
    SCOPED_TRACE(file.string());
    expect_tetrahedron(read_mesh(file));
    // Cut short inside the last face: the structure check reports it (assimp alone would not).
    spit(file, s.substr(0, s.size() - 5));
    try {
      read_mesh(file);
      ADD_FAILURE() << "truncated binary PLY accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()), file.string() +
                                           ": the file ends inside face 3 of the 4 declared in the PLY "
                                           "header (truncated file or wrong element count)");
    }
  }
}

TEST(WriteObj, RoundTripKeepsPositionsAndFaces) {
  const fs::path dir = test::temp_dir("mesh-io-obj");
  const auto t = test::bumpy_grid(12);
  write_obj(dir / "grid.obj", t.vertices, t.faces);
  const SurfaceMesh m = read_mesh(dir / "grid.obj");
  // Every vertex is used and distinct: the numbering survives too.
  expect_same_bits(m.vertices(), t.vertices);
  EXPECT_EQ(m.faces(), t.faces);
  // No temporary left beside the output.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);
}

TEST(WriteObj, DoublePositionsRoundTripExactly) {
  // OBJ is read in double precision, with a correctly rounded parser: every double that
  // write_obj writes (17 significant digits) comes back bit for bit.
  const fs::path dir = test::temp_dir("mesh-io-obj-double");
  auto t = test::icosphere(1);
  // Off the float grid: a third of the unit sphere, moved; one vertex nudged far below float
  // resolution.
  t.vertices = (t.vertices / 3.0).rowwise() + Eigen::RowVector3d(1e3 / 7.0, -2.0 / 3.0, 1e-5 / 3.0);
  t.vertices(0, 0) += 3e-10;
  ASSERT_NE(float_rounded(t.vertices), t.vertices);
  write_obj(dir / "sphere.obj", t.vertices, t.faces);
  // The text itself holds the doubles exactly (17 significant digits).
  std::istringstream text(slurp(dir / "sphere.obj"));
  int v = 0;
  for (std::string line; std::getline(text, line);) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream fields(line.substr(2));
    double x, y, z;
    fields >> x >> y >> z;
    ASSERT_EQ(Vec3(x, y, z), t.vertices.row(v).transpose()) << "vertex " << v;
    ++v;
  }
  EXPECT_EQ(v, t.vertices.rows());
  const SurfaceMesh m = read_mesh(dir / "sphere.obj");
  expect_same_bits(m.vertices(), t.vertices);
  EXPECT_EQ(m.faces(), t.faces);

  // Values that need all 17 digits, a subnormal, a negative zero, large and tiny magnitudes.
  RowMatX3d special(3, 3);
  special << 5e-324, -0.0, 0.1 + 0.2,  //
      1.0 / 3.0, 1e-300, -2.5e-17,     //
      -0.0, 1.0 - 0x1p-53, 123456789.12345679;
  const RowMatX3i triangle = (RowMatX3i(1, 3) << 0, 1, 2).finished();
  write_obj(dir / "special.obj", special, triangle);
  const SurfaceMesh s = read_mesh(dir / "special.obj");
  expect_same_bits(s.vertices(), special);
  EXPECT_EQ(s.faces(), triangle);
}

TEST(WriteObj, RejectsBadIndicesAndUnwritablePaths) {
  const auto t = test::square();
  RowMatX3i bad = t.faces;
  bad(1, 1) = 7;
  const fs::path dir = test::temp_dir("mesh-io-bad-write");
  EXPECT_THROW(write_obj(dir / "x.obj", t.vertices, bad), InternalError);
  EXPECT_FALSE(fs::exists(dir / "x.obj"));
  try {
    write_obj(dir / "no" / "such" / "dir.obj", t.vertices, t.faces);
    ADD_FAILURE() << "wrote into a missing directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((dir / "no" / "such" / "dir.obj").string()), std::string::npos);
  }
}

TEST(WritePly, FaceFieldsAreStoredAsLittleEndianDoubles) {
  const fs::path dir = test::temp_dir("mesh-io-ply-fields");
  const SurfaceMesh mesh = test::make(test::icosphere(1));
  const int nf = mesh.num_faces();
  Eigen::VectorXd alpha(nf), w(nf);
  for (int f = 0; f < nf; ++f) alpha[f] = 0.1 * f + 1.0 / 3.0, w[f] = -std::exp(-f);
  write_ply_with_face_fields(dir / "fields.ply", mesh, {{"alpha", alpha}, {"W", w}});

  const std::string s = slurp(dir / "fields.ply");
  const std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by cutwork\nelement vertex 42\n"
      "property double x\nproperty double y\nproperty double z\nelement face 80\n"
      "property list uchar int vertex_indices\nproperty double W\nproperty double alpha\nend_header\n";
  ASSERT_EQ(s.substr(0, header.size()), header);
  ASSERT_EQ(s.size(), header.size() + 42 * 24 + std::size_t(nf) * (1 + 12 + 16));
  std::size_t pos = header.size();
  auto get_double = [&] {
    double x;
    std::memcpy(&x, s.data() + pos, 8);
    pos += 8;
    return x;
  };
  for (int v = 0; v < 42; ++v)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(get_double(), mesh.vertices()(v, c));
  for (int f = 0; f < nf; ++f) {
    ASSERT_EQ(s[pos++], 3);
    for (int k = 0; k < 3; ++k) {
      std::int32_t i;
      std::memcpy(&i, s.data() + pos, 4);
      pos += 4;
      ASSERT_EQ(i, mesh.faces()(f, k));
    }
    ASSERT_EQ(get_double(), w[f]);  // std::map order: "W" < "alpha"
    ASSERT_EQ(get_double(), alpha[f]);
  }
  // And it is a PLY that read_mesh (assimp, plus the structure check) accepts.
  const SurfaceMesh back = read_mesh(dir / "fields.ply");
  EXPECT_EQ(back.vertices(), float_rounded(mesh.vertices()));
  EXPECT_EQ(back.faces(), mesh.faces());
}

TEST(WritePly, RejectsMismatchedFields) {
  const fs::path dir = test::temp_dir("mesh-io-ply-bad");
  const SurfaceMesh mesh = test::make(test::square());
  try {
    write_ply_with_face_fields(dir / "f.ply", mesh, {{"alpha", Eigen::VectorXd::Zero(3)}});
    ADD_FAILURE();
  } catch (const InternalError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir / "f.ply").string() + ": face field 'alpha' has 3 entries, expected one per face (2)");
  }
  EXPECT_THROW(write_ply_with_face_fields(dir / "f.ply", mesh, {{"two words", Eigen::VectorXd::Zero(2)}}),
               InternalError);
  EXPECT_FALSE(fs::exists(dir / "f.ply"));
}

TEST(IsMeshFile, KnownExtensionsAnyCase) {
  EXPECT_TRUE(is_mesh_file("a.obj"));
  EXPECT_TRUE(is_mesh_file("dir/b.PLY"));
  EXPECT_TRUE(is_mesh_file("c.Off"));
  EXPECT_TRUE(is_mesh_file("d.stl"));
  EXPECT_FALSE(is_mesh_file("e.json"));
  EXPECT_FALSE(is_mesh_file("obj"));
}

struct BadFile {
  const char* name;
  const char* problem;  ///< the message after "<path>: "
};

class ReadMeshRejects : public ::testing::TestWithParam<BadFile> {};

TEST_P(ReadMeshRejects, NamingFileAndProblem) {
  const fs::path file = meshes() / "bad" / GetParam().name;
  try {
    read_mesh(file);
    ADD_FAILURE() << file << " was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() + ": " + GetParam().problem);
  }
}

INSTANTIATE_TEST_SUITE_P(
    BadMeshes, ReadMeshRejects,
    ::testing::Values(
        BadFile{"nan.obj", "vertex 2 has a non-finite coordinate"},
        BadFile{"out_of_range.obj", "cannot be parsed: OBJ: vertex index out of range"},
        BadFile{"degenerate.obj", "face 1 has zero area"},
        BadFile{"repeated_index.obj", "face 1 repeats vertex 2"},
        BadFile{"duplicate_face.obj", "faces 0 and 2 are duplicates"},
        BadFile{"nonmanifold.obj", "edge (0,1) is shared by 3 faces (non-manifold): faces 0, 1, 2"},
        BadFile{"inconsistent_orientation.obj",
                "faces 0 and 1 both use edge 2->0 in the same direction (inconsistent orientation; "
                "flip one of them)"},
        BadFile{"empty.obj", "file is empty"},
        BadFile{"no_faces.obj", "no faces"},
        BadFile{"no_facets.stl", "no faces"},
        BadFile{"four_vertex_facet.stl", "facet 0 has 4 vertices (STL facets are triangles)"},
        BadFile{"line_element.obj",
                "face 0 has 2 vertices: point and line elements are not supported, only triangle "
                "and polygon faces"},
        BadFile{"point_element.obj",
                "face 1 has 1 vertices: point and line elements are not supported, only triangle "
                "and polygon faces"},
        BadFile{"negative_out_of_range.obj", "cannot be parsed: OBJ: vertex index out of range"},
        BadFile{"index_overflow.obj", "cannot be parsed: OBJ: vertex index out of range"},
        BadFile{"zero_index.obj",
                "cannot be parsed: OBJ line 5: face corner '0' has vertex index 0 (OBJ counts from 1)"},
        BadFile{"garbage_index.obj", "cannot be parsed: OBJ line 5: face corner '3x' is not a vertex index"},
        BadFile{"bad_coordinate.obj", "cannot be parsed: OBJ line 3: vertex coordinate 'zero' is not a number"},
        BadFile{"missing_coordinate.obj",
                "cannot be parsed: OBJ line 3: vertex has 2 coordinates, expected 3"},
        BadFile{"bowtie_quad.obj",
                "face 0 has 4 vertices and could not be triangulated (self-intersecting or degenerate "
                "polygon?)"},
        BadFile{"garbage.obj", "no faces"},
        BadFile{"garbage.ply",
                "cannot be parsed: Invalid .ply file: Incorrect magic number (expected 'ply' or 'PLY')."},
        BadFile{"mesh.xyz", "unknown mesh format '.xyz' (expected .obj, .ply, .off or .stl)"},
        BadFile{"missing.obj", "file not found"},
        BadFile{"out_of_range.ply", "face 0 index 99 out of range [0,3)"},
        BadFile{"negative_index.ply", "face 0 index -1 out of range [0,3)"},
        BadFile{"extra_data.ply",
                "data continues after the elements declared in the PLY header (3 vertex, 1 face): "
                "wrong element count?"},
        BadFile{"truncated.ply",
                "the PLY header declares 5 vertex elements, but the 26 bytes of data after the header hold "
                "at most 4 (at least 6 bytes each; truncated file or wrong element count)"},
        BadFile{"no_end_header.ply", "PLY header has no end_header line (truncated or not a PLY file)"},
        BadFile{"bare_property.ply", "PLY header line 7 'property': expected 'property <type> <name>'"},
        // A NUL inside a property name: assimp's PLY reader crashed on it (SEGV, found by fuzzing).
        BadFile{"nul_in_property_name.ply",
                "PLY header line 5 has a control byte 0x00 at column 16 (binary data in the header, or "
                "not a PLY file)"},
        // An element name that starts with digits: assimp read them as a count and allocated 62 GB
        // (out of memory under AddressSanitizer, found by fuzzing).
        BadFile{"element_name_with_leading_digits.ply",
                "PLY header line 4 'element 8888888888888vertex 4': an element name must start with a letter"},
        BadFile{"missing_y_property.ply", "the PLY vertex element has no 'y' property (positions are x, y and z)"},
        // Two format lines (binary, then ascii): this check read the data as ASCII, assimp as binary
        // and crashed (SEGV, found by fuzzing; ascii then binary leaked).
        BadFile{"two_format_lines.ply",
                "PLY header line 3 'format ascii 1.0': a second format line (the first is line 2)"},
        BadFile{"comment_only.off", "no OFF header (the file holds only blank or comment lines)"},
        BadFile{"out_of_range.off", "face 0 index 99 out of range [0,3)"},
        BadFile{"negative_index.off", "face 0 index -1 out of range [0,3)"},
        BadFile{"truncated.off",
                "the file ends before the 4 vertices and 1 faces declared in the OFF header (4 data "
                "lines found; truncated file or wrong counts)"},
        BadFile{"ten_corners.off",
                "face 0 has 10 vertices; OFF faces with more than 9 are not supported"},
        // Header counts beyond what the file can hold (issue 22: the face count crashed the OFF
        // check), refused before anything is read or allocated for them. A 7x7 grid each:
        // 49 vertices, 36 quads (OFF) or 72 triangles (PLY, STL).
        BadFile{"huge_face_count.off",
                "the OFF header declares 9223372036854775807 faces, but the file has only 85 data lines "
                "(truncated file or wrong counts)"},
        BadFile{"huge_vertex_count.off",
                "the OFF header declares 9223372036854775807 vertices, but the file has only 85 data lines "
                "(truncated file or wrong counts)"},
        BadFile{"huge_face_count_ascii.ply",
                "the PLY header declares 9223372036854775807 face elements, but the 1221 bytes of data after "
                "the header hold at most 611 (at least 2 bytes each; truncated file or wrong element count)"},
        BadFile{"huge_vertex_count_ascii.ply",
                "the PLY header declares 9223372036854775807 vertex elements, but the 1221 bytes of data after "
                "the header hold at most 203 (at least 6 bytes each; truncated file or wrong element count)"},
        BadFile{"huge_face_count_binary.ply",
                "the PLY header declares 9223372036854775807 face elements, but the 1524 bytes of data after "
                "the header hold at most 1524 (at least 1 byte each; truncated file or wrong element count)"},
        BadFile{"huge_vertex_count_binary.ply",
                "the PLY header declares 9223372036854775807 vertex elements, but the 1524 bytes of data after "
                "the header hold at most 127 (at least 12 bytes each; truncated file or wrong element count)"},
        BadFile{"huge_element_without_properties.ply",
                "the PLY header declares 9223372036854775807 padding elements without properties, more than "
                "the 1221 bytes of data after the header (wrong element count?)"},
        BadFile{"huge_facet_count.stl",
                "cannot be parsed: not an STL file: an ASCII STL starts with 'solid', and a binary STL "
                "declaring 4294967295 facets would be 214748364834 bytes long, not 3684"}),
    [](const ::testing::TestParamInfo<BadFile>& info) {
      std::string n = info.param.name;
      for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return n;
    });

TEST(ReadMesh, AsciiStlNumbersAreReadAsAssimpReadsThem) {
  // assimp reads a facet's numbers separated by spaces and tabs, ends a line at a form feed, CR or
  // NUL, and takes plain decimals only; on anything else it throws and leaks (the fuzzer found a
  // vertex "0 0 <form feeds>1"). The check refuses each such file with one line naming the facet;
  // a tab-separated, signed and exponent-written tetrahedron still reads.
  const fs::path dir = test::temp_dir("mesh-io-stl-numbers");
  auto stl = [](const std::string& third_vertex) {
    return "solid t\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   vertex " +
           third_vertex + "\n  endloop\n endfacet\nendsolid t\n";
  };
  for (const std::string& bad : {std::string("1 0 \f\f0"), std::string("1 0\f0"), std::string("1\v0 0"),
                                 std::string("0x1p0 0 0"), std::string("1 0 0,5"), std::string("1 0 \v0"),
                                 std::string("1 0 0\r0")}) {
    SCOPED_TRACE(bad);
    spit(dir / "bad.stl", stl(bad));
    try {
      read_mesh(dir / "bad.stl");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("ASCII STL facet 0"), std::string::npos) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
  }
  spit(dir / "good.stl", stl("1.0e0\t-0 +0."));
  EXPECT_EQ(read_mesh(dir / "good.stl").num_faces(), 1);
  // A NUL anywhere in an ASCII STL (the fuzzer: one ending a vertex's line, where assimp leaked) is
  // refused with its offset and line.
  for (const std::string& third : {std::string("1 0 0") + '\0', std::string("1 0") + '\0' + "0"}) {
    spit(dir / "nul.stl", stl(third));
    try {
      read_mesh(dir / "nul.stl");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("a NUL byte at offset"), std::string::npos) << what;
      EXPECT_NE(what.find("(line 6)"), std::string::npos) << what;
      EXPECT_EQ(what.find('\0'), std::string::npos);
    }
  }
  // Any other control byte but tab, LF and CR (the fuzzer: a form feed before a facet's first
  // "vertex", where assimp leaked) is refused with the facet, its offset and line.
  const std::string ff = "solid t\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 0 1 0\n   vertex 1 0 0\n"
                         "  endloop\n endfacet\n facet normal 0 0 1\n  outer loop\n  \fvertex 0 0 0\n   vertex 1 0 0\n"
                         "   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n";
  for (const char control : {'\f', '\v', '\x1b'}) {
    std::string text = ff;
    text[text.find('\f')] = control;
    spit(dir / "control.stl", text);
    try {
      read_mesh(dir / "control.stl");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(fmt::format("ASCII STL facet 1: a control byte 0x{:02x} at offset", int(control))),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("(line 11)"), std::string::npos) << what;
      EXPECT_EQ(what.find(control), std::string::npos);
    }
  }
}

TEST(ReadMesh, HeaderCountsAreCheckedAgainstTheFileSize) {
  // Every count of a small OFF, ASCII and binary PLY set to extreme values: one InputError naming
  // the file each time, never a crash, a hang or an allocation of the declared size (issue 22).
  const fs::path dir = test::temp_dir("mesh-io-header-counts");
  const std::vector<std::string> counts = {"5", "2147483647", "2147483648", "4294967295", "4294967296",
                                           "4294967300", "9223372036854775807", "9223372036854775808",
                                           "18446744073709551615", "-1"};
  auto expect_refused = [&](const fs::path& file) {
    SCOPED_TRACE(slurp(file).substr(0, 120));
    try {
      read_mesh(file);
      ADD_FAILURE() << file << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(file.string() + ": ", 0), 0u) << e.what();
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  };
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
  for (const std::string& c : counts) {
    spit(dir / "v.off", "OFF\n" + c + " 4 0\n" + vertices + "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
    expect_refused(dir / "v.off");
    spit(dir / "f.off", "OFF\n4 " + c + " 0\n" + vertices + "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
    expect_refused(dir / "f.off");
    for (const char* format : {"ascii", "binary_little_endian"}) {
      const bool ascii = std::string(format) == "ascii";
      std::string body;
      if (ascii) {
        body = vertices + "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
      } else {
        auto put = [&](auto x) { body.append(reinterpret_cast<const char*>(&x), sizeof(x)); };
        const auto t = test::tetrahedron();
        for (int i = 0; i < 4; ++i)
          for (int k = 0; k < 3; ++k) put(float(t.vertices(i, k)));
        for (int i = 0; i < 4; ++i) {
          put(std::uint8_t(3));
          for (int k = 0; k < 3; ++k) put(std::int32_t(t.faces(i, k)));
        }
      }
      for (int which : {0, 1, 2}) {
        const std::string header =
            std::string("ply\nformat ") + format + " 1.0\nelement vertex " + (which == 0 ? c : "4") +
            "\nproperty float x\nproperty float y\nproperty float z\nelement face " + (which == 1 ? c : "4") +
            "\nproperty list uchar int vertex_indices\n" + (which == 2 ? "element empty " + c + "\n" : "") +
            "end_header\n";
        spit(dir / "e.ply", header + body);
        if (which == 2 && c == "5") {  // five items of nothing fit: read as before
          expect_tetrahedron(read_mesh(dir / "e.ply"));
          continue;
        }
        expect_refused(dir / "e.ply");
      }
    }
  }
  // A list length beyond the bytes left is a truncated file (not a loop up to the length).
  spit(dir / "list.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uint int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n999999999 0 1 2\n");
  try {
    read_mesh(dir / "list.ply");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "list.ply").string() +
                                         ": the file ends inside face 0 of the 1 declared in the PLY header "
                                         "(truncated file or wrong element count)");
  }
  // The OFF counts each fit, together they do not: the combined message, no overflow.
  spit(dir / "sum.off", "OFF\n4 4 0\n" + vertices + "3 0 2 1\n3 0 1 3\n3 1 2 3\n");
  try {
    read_mesh(dir / "sum.off");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "sum.off").string() +
                                         ": the file ends before the 4 vertices and 4 faces declared in the OFF "
                                         "header (7 data lines found; truncated file or wrong counts)");
  }
  // A binary STL whose count says 0xFFFFFFFF facets (also from a header starting "solid").
  const auto t = test::tetrahedron();
  std::string stl = binary_stl(t.vertices, t.faces, 0xFFFFFFFFu);
  spit(dir / "count.stl", stl);
  expect_refused(dir / "count.stl");
  stl.replace(0, 5, "solid");
  spit(dir / "solid.stl", stl);
  expect_refused(dir / "solid.stl");
}

TEST(ReadMesh, DirectoryAndUnreadableFile) {
  const fs::path dir = test::temp_dir("mesh-io-dir");
  fs::create_directory(dir / "folder.obj");
  try {
    read_mesh(dir / "folder.obj");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "folder.obj").string() + ": is a directory, not a mesh file");
  }
}

TEST(ReadMesh, MalformedObjIsAnInputError) {
  // Random edits of valid OBJ text (and random bytes): each result loads or is an InputError.
  const fs::path dir = test::temp_dir("mesh-io-obj-mutants");
  const std::string seeds[] = {
      slurp(meshes() / "tetrahedron.obj"), slurp(meshes() / "quad_strip_relative.obj"),
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\nf 1 2 3 4\nf -5/1 -4/1 -1/1\nl 1 2\n"};
  const char alphabet[] = "0123456789 -+./\n\r\tvflpog#e";
  std::mt19937 rng(11);
  int loaded = 0;
  for (int it = 0; it < 3000; ++it) {
    std::string s = seeds[it % 3];
    for (int edits = 1 + int(rng() % 6); edits > 0; --edits) {
      const std::size_t pos = rng() % (s.size() + 1);
      const char c = rng() % 8 == 0 ? char(rng() % 256) : alphabet[rng() % (sizeof alphabet - 1)];
      switch (rng() % 3) {
        case 0: s.insert(pos, 1, c); break;
        case 1: if (pos < s.size()) s.erase(pos, 1 + rng() % 3); break;
        default: if (pos < s.size()) s[pos] = c;
      }
    }
    if (it % 100 == 0)
      for (char& c : s) c = char(rng() % 256);
    spit(dir / "mutant.obj", s);
    try {
      read_mesh(dir / "mutant.obj");
      ++loaded;
    } catch (const InputError& e) {
      ASSERT_EQ(std::string(e.what()).rfind((dir / "mutant.obj").string() + ": ", 0), 0u) << e.what();
    } catch (const std::exception& e) {
      FAIL() << "not an InputError: " << e.what() << "\n" << s;
    }
  }
  EXPECT_GT(loaded, 0);
}

TEST(ReadMesh, TruncatedBinaryStlIsRejected) {
  const fs::path dir = test::temp_dir("mesh-io-stl-short");
  const auto t = test::tetrahedron();
  // Declares 10 triangles but holds 4.
  spit(dir / "short.stl", binary_stl(t.vertices, t.faces, 10));
  try {
    read_mesh(dir / "short.stl");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind((dir / "short.stl").string() + ": cannot be parsed: ", 0), 0u) << what;
  }
}

}  // namespace
}  // namespace cutwork

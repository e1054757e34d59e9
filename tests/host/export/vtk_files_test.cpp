// fields.vtu and stencils.vtp: written, read back with libxml2 bit for bit, and rejected when
// they are not what cutwork writes.
#include "host/export/vtk_files.h"

#include <gtest/gtest.h>

#include <fstream>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/surfaces/generators.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;

SurfaceMesh small_plate() { return generate_shape("plate", {{"width", 0.2}, {"height", 0.1}}, 0.02); }

TEST(VtkFiles, UnstructuredGridRoundTripsExactly) {
  const SurfaceMesh mesh = small_plate();
  MeshFields fields;
  const Eigen::Index nf = mesh.num_faces(), nv = mesh.num_vertices();
  fields.face["alpha"] = Eigen::VectorXd::LinSpaced(nf, 0.1, 1.0);
  fields.face["W"] = Eigen::VectorXd::Random(nf).cwiseAbs() * 1e3 + Eigen::VectorXd::Constant(nf, 1.0 / 3.0);
  fields.vertex["displacement"] = RowMatX3d::Random(nv, 3) * 1e-3;
  const fs::path file = test::temp_dir("vtu") / "fields.vtu";
  write_vtu(file, mesh, fields);
  const VtuContents back = read_vtu(file);
  EXPECT_EQ(back.vertices, mesh.vertices());
  EXPECT_EQ(back.faces, mesh.faces());
  ASSERT_EQ(back.fields.face.size(), 2u);
  EXPECT_EQ(back.fields.face.at("alpha"), fields.face["alpha"]);
  EXPECT_EQ(back.fields.face.at("W"), fields.face["W"]);
  ASSERT_EQ(back.fields.vertex.size(), 1u);
  EXPECT_EQ(back.fields.vertex.at("displacement"), fields.vertex["displacement"]);
}

TEST(VtkFiles, WrongFieldSizesAreRejectedAndNothingIsWritten) {
  const SurfaceMesh mesh = small_plate();
  const fs::path file = test::temp_dir("vtu_bad") / "fields.vtu";
  MeshFields fields;
  fields.face["alpha"] = Eigen::VectorXd::Ones(mesh.num_faces() + 1);
  EXPECT_THROW(write_vtu(file, mesh, fields), InternalError);
  fields.face.clear();
  fields.vertex["u"] = RowMatX3d::Zero(mesh.num_vertices() - 1, 3);
  EXPECT_THROW(write_vtu(file, mesh, fields), InternalError);
  EXPECT_FALSE(fs::exists(file));
}

TEST(VtkFiles, ReaderRejectsWhatIsNotATriangleGrid) {
  const fs::path dir = test::temp_dir("vtu_reject");
  auto expect_rejected = [&](const std::string& name, const std::string& text, const std::string& fragment) {
    std::ofstream(dir / name) << text;
    try {
      read_vtu(dir / name);
      FAIL() << name << ": expected InputError";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  };
  expect_rejected("not_xml.vtu", "this is not < xml", "XML");
  expect_rejected("poly.vtu", "<VTKFile type=\"PolyData\"><PolyData/></VTKFile>", "UnstructuredGrid");
  const std::string quad =
      "<VTKFile type=\"UnstructuredGrid\"><UnstructuredGrid><Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">"
      "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 1 1 0 0 1 0"
      "</DataArray></Points><Cells>"
      "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>"
      "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>"
      "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">9</DataArray></Cells></Piece></UnstructuredGrid>"
      "</VTKFile>";
  expect_rejected("quad.vtu", quad, "not a triangle");
}

TEST(VtkFiles, PolylinesRoundTripClosed) {
  std::vector<RowMatX3d> lines(2);
  lines[0] = RowMatX3d::Random(5, 3);
  lines[1] = RowMatX3d::Random(3, 3);
  const fs::path file = test::temp_dir("vtp") / "stencils.vtp";
  write_vtp_polylines(file, lines, true, {{"stencil", Eigen::Vector2d(0, 1)}, {"type", Eigen::Vector2d(3, 1)}});
  const VtpContents back = read_vtp_polylines(file);
  ASSERT_EQ(back.lines.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(back.lines[i].rows(), lines[i].rows() + 1) << "closed: the first point again";
    EXPECT_EQ(back.lines[i].topRows(lines[i].rows()), lines[i]);
    EXPECT_EQ(back.lines[i].bottomRows(1), lines[i].topRows(1));
  }
  EXPECT_EQ(back.cell_fields.at("type"), Eigen::Vector2d(3, 1));
  EXPECT_EQ(back.cell_fields.at("stencil"), Eigen::Vector2d(0, 1));
}

}  // namespace
}  // namespace cutwork

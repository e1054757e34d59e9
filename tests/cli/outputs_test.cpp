// The designer's files from `cutwork design` / `simulate` and `cutwork render DIR`: fields.vtu
// agrees with fields.ply, the solid and its report, the pictures and their options.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "host/export/solid.h"
#include "host/export/vtk_files.h"
#include "host/render/pictures.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;
using test::run_cutwork;

using test::read_json;

/// The per-face double properties of a binary PLY as cutwork writes it (write_ply_with_face_fields).
std::map<std::string, Eigen::VectorXd> read_ply_face_fields(const fs::path& path, RowMatX3d* vertices) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  int nv = 0, nf = 0;
  std::vector<std::string> names;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream ls(line);
    std::string a, b, c;
    ls >> a >> b >> c;
    if (a == "element" && b == "vertex") nv = std::stoi(c);
    if (a == "element" && b == "face") nf = std::stoi(c);
    if (a == "property" && b == "double" && c != "x" && c != "y" && c != "z") names.push_back(c);
  }
  vertices->resize(nv, 3);
  in.read(reinterpret_cast<char*>(vertices->data()), std::streamsize(sizeof(double) * 3 * size_t(nv)));
  std::map<std::string, Eigen::VectorXd> fields;
  for (const auto& n : names) fields[n].resize(nf);
  for (int f = 0; f < nf; ++f) {
    char face[13];
    in.read(face, 13);
    for (const auto& n : names) in.read(reinterpret_cast<char*>(&fields[n][f]), sizeof(double));
  }
  EXPECT_TRUE(in.good()) << path;
  return fields;
}

TEST(CliOutputs, DesignWritesParaViewFieldsASolidAndPictures) {
  const fs::path dir = test::temp_dir("outputs_design");
  const fs::path out = dir / "plate";
  const auto r = run_cutwork("design plate --iterations 3 --device cpu --render-size 300x120 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"fields.vtu", "stencils.vtp", "cut_solid.stl", "cut_solid.3mf", "render_W.png",
                           "render_alpha.png", "render_design.png"}) {
    EXPECT_TRUE(fs::exists(out / name)) << name;
    EXPECT_NE(r.err.find(name), std::string::npos) << "the summary line lists " << name << ": " << r.err;
  }
  // fields.vtu holds exactly what fields.ply holds, plus the displacement per vertex.
  RowMatX3d ply_vertices;
  const auto ply = read_ply_face_fields(out / "fields.ply", &ply_vertices);
  const VtuContents vtu = read_vtu(out / "fields.vtu");
  EXPECT_EQ(vtu.vertices, ply_vertices);
  for (const char* name : {"alpha", "W", "W_pattern"}) {
    ASSERT_TRUE(vtu.fields.face.count(name)) << name;
    EXPECT_EQ(vtu.fields.face.at(name), ply.at(name)) << name;
  }
  ASSERT_TRUE(vtu.fields.vertex.count("displacement"));
  EXPECT_GT(vtu.fields.vertex.at("displacement").cwiseAbs().maxCoeff(), 0.0);
  const auto report = read_json(out / "report.json");
  EXPECT_EQ(report["device"]["requested"], "cpu");
  EXPECT_EQ(report["device"]["reason"], "--device cpu");
  EXPECT_EQ(report["device"]["render"], "cpu") << "the pictures follow --device";
  const VtpContents vtp = read_vtp_polylines(out / "stencils.vtp");
  EXPECT_EQ(vtp.lines.size(), report["stencils"]["count"].get<size_t>());
  // The solid: checked, written, and its volume is the cut area times the thickness.
  const auto& fab = report["fabrication"];
  EXPECT_TRUE(fab["solid"]["valid"].get<bool>()) << fab["solid"];
  EXPECT_NEAR(fab["solid"]["volume"].get<double>(), report["cut"]["area"].get<double>() * fab["thickness"].get<double>(),
              0.01 * fab["solid"]["volume"].get<double>());
  EXPECT_EQ(fab["min_feature"], 0.001);
  EXPECT_EQ(report["cut"]["tool_radius"], 0.0);  // the scene's fabrication.tool_radius: the drawn outlines
  EXPECT_EQ(fab["violations"].size(), fab["violation_count"].get<size_t>());
  const ThreeMfMesh m = read_3mf(out / "cut_solid.3mf");
  EXPECT_EQ(m.faces.rows(), fab["solid"]["triangles"].get<int>());
  for (const char* name : {"render_W.png", "render_alpha.png", "render_design.png"}) {
    const render::Image image = render::read_png(out / name);
    EXPECT_EQ(image.width, 300);
    EXPECT_EQ(image.height, 120);
  }

  // `cutwork render DIR` draws them again, with other views and sizes, into --out.
  const fs::path again = dir / "again";
  const auto rr = run_cutwork("render " + out.string() + " --view top,iso --field W,design --size 200x150 --device cpu --out " +
                              again.string());
  ASSERT_EQ(rr.exit_code, 0) << rr.err;
  EXPECT_NE(rr.err.find("(drawn on cpu)"), std::string::npos) << rr.err;
  EXPECT_TRUE(fs::exists(again / "render_W.png"));
  EXPECT_TRUE(fs::exists(again / "render_design.png"));
  EXPECT_FALSE(fs::exists(again / "render_alpha.png"));
  EXPECT_EQ(render::read_png(again / "render_W.png").width, 200);
  fs::remove_all(dir);
}

TEST(CliOutputs, SimulateWritesFieldsAndPicturesAndNoRenderSkipsThem) {
  const fs::path dir = test::temp_dir("outputs_simulate");
  const auto r = run_cutwork("simulate plate --render-size 200x150 --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* name : {"fields.vtu", "render_W.png", "render_alpha.png", "render_design.png"})
    EXPECT_TRUE(fs::exists(dir / "a" / name)) << name;
  const auto n = run_cutwork("simulate plate --no-render --out " + (dir / "b").string());
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_TRUE(fs::exists(dir / "b" / "fields.vtu"));
  for (const char* name : {"render_W.png", "render_alpha.png", "render_design.png"})
    EXPECT_FALSE(fs::exists(dir / "b" / name)) << name;
  fs::remove_all(dir);
}

TEST(CliOutputs, BadRenderOptionsAreOneLineAndExitTwo) {
  const fs::path dir = test::temp_dir("outputs_bad");
  const auto size = run_cutwork("simulate plate --render-size 12x9 --out " + (dir / "a").string());
  EXPECT_EQ(size.exit_code, 2);
  EXPECT_NE(size.err.find("--render-size"), std::string::npos) << size.err;
  EXPECT_FALSE(fs::exists(dir / "a" / "report.json"));
  const auto missing = run_cutwork("render " + (dir / "nothing").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("fields.vtu"), std::string::npos) << missing.err;
  ASSERT_EQ(run_cutwork("simulate plate --no-render --out " + (dir / "s").string()).exit_code, 0);
  const auto view = run_cutwork("render " + (dir / "s").string() + " --view diagonal");
  EXPECT_EQ(view.exit_code, 2);
  EXPECT_NE(view.err.find("diagonal"), std::string::npos) << view.err;
  const auto design = run_cutwork("render " + (dir / "s").string() + " --field design");
  EXPECT_EQ(design.exit_code, 2) << "a simulation folder has no cut.obj";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork

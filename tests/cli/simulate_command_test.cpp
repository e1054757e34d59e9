// `cutwork simulate`: the report and fields it writes for the built-in scenes, and bad supports or
// loads ending as one line on stderr, exit code 2 and nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include <Eigen/Core>

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "host/core/types.h"
#include "host/scene/load_case.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;
using test::run_cutwork;

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

using test::read_json;

/// The built-in plate scene as a document, to be modified into bad inputs.
nlohmann::json plate_scene() {
  const auto r = run_cutwork("show plate");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

/// The built-in plate's half y ∈ [−0.025, 0.025] on its symmetry plane y = −0.025, with half the
/// force on the plane: the whole plate (moved by −0.025 in y).
nlohmann::json half_plate_scene() {
  nlohmann::json half = plate_scene();
  half["mesh"]["params"]["height"] = 0.05;
  half["supports"].push_back(
      {{"type", "symmetry"}, {"axis", "y"}, {"select", {{"entity", "vertices"}, {"y", {{"below", -0.0249999}}}}}});
  half["loads"][0]["force"] = {0.0, 0.0, -0.5};
  half["loads"][0]["select"]["near"]["point"] = {0.1, -0.025, 0.0};
  return half;
}

void expect_failure_without_output(const std::string& args, const fs::path& out, const std::string& fragment) {
  const auto r = run_cutwork(args + " --out " + out.string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(fragment), std::string::npos) << "missing '" << fragment << "' in: " << r.err;
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_FALSE(fs::exists(out / "fields.ply"));
}

TEST(CliSimulate, WritesReportAndFieldsForTheBuiltinScenes) {
  const fs::path dir = test::temp_dir("simulate");
  for (const char* scene : {"plate", "pavilion", "bowl"}) {
    SCOPED_TRACE(scene);
    const fs::path out = dir / scene;
    const auto r = run_cutwork(std::string("simulate ") + scene + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = read_json(out / "report.json");
    EXPECT_EQ(report["scene"], scene);
    const auto& eq = report["equilibrium"];
    for (const char* key : {"max_displacement", "strain_energy", "compliance", "W_max", "newton_iterations",
                            "residual", "converged", "stop"})
      EXPECT_TRUE(eq.contains(key)) << key;
    EXPECT_TRUE(eq["converged"].get<bool>());
    EXPECT_TRUE(eq["stop"] == "residual" || eq["stop"] == "negligible_step" || eq["stop"] == "roundoff")
        << eq["stop"];
    EXPECT_GT(eq["max_displacement"].get<double>(), 0.0);
    EXPECT_GT(eq["strain_energy"].get<double>(), 0.0);
    EXPECT_GT(eq["compliance"].get<double>(), 0.0);
    EXPECT_GT(eq["W_max"].get<double>(), 0.0);
    for (const char* key : {"assembly", "factorization", "solve"}) EXPECT_TRUE(report["timings"].contains(key)) << key;
    EXPECT_GT(report["mesh"]["sim_triangles"].get<int>(), 0);
    // fields.ply: binary PLY with the per-face fields named in its header.
    std::ifstream ply(out / "fields.ply", std::ios::binary);
    std::string header, line;
    while (std::getline(ply, line) && line != "end_header") header += line + "\n";
    EXPECT_NE(header.find("property double alpha"), std::string::npos) << header;
    EXPECT_NE(header.find("property double W"), std::string::npos) << header;
    EXPECT_NE(header.find("element face " + std::to_string(report["mesh"]["sim_triangles"].get<int>())),
              std::string::npos)
        << header;
  }
  fs::remove_all(dir);
}

TEST(CliSimulate, BadSupportsAndLoadsAreOneLineErrors) {
  const fs::path dir = test::temp_dir("simulate_bad");
  auto scene_file = [&](const std::string& name, const nlohmann::json& doc) {
    const fs::path p = dir / (name + ".json");
    std::ofstream(p) << doc.dump(2);
    return p.string();
  };

  nlohmann::json doc = plate_scene();
  doc["supports"] = nlohmann::json::array();
  expect_failure_without_output("simulate " + scene_file("unsupported", doc), dir / "out1", "not supported");

  doc = plate_scene();
  doc["loads"][0]["force"] = {0.0, 0.0, 0.0};
  expect_failure_without_output("simulate " + scene_file("zero", doc), dir / "out2", "no load");

  doc = plate_scene();
  doc["loads"][0]["force"] = {0.0, 0.0, -1e6};
  expect_failure_without_output("simulate " + scene_file("overload", doc), dir / "out3", "can carry");

  // 500 N pushing the free end towards the clamp: ~20× the strip's Euler buckling load. Newton
  // can converge to the flat state, which is an unstable equilibrium: an error, not a result.
  doc = plate_scene();
  doc["loads"][0]["force"] = {-500.0, 0.0, 0.0};
  expect_failure_without_output("simulate " + scene_file("buckling", doc), dir / "out5", "unstable");

  expect_failure_without_output("simulate plate --stencils " + (dir / "stencils.json").string(), dir / "out4",
                                "stencils.json: no such file");
  fs::remove_all(dir);
}

// The built-in plate (clamped at x = −0.1, pulled down at the middle of its free side) is
// symmetric about y = 0, and the generator meshes it symmetrically: its half y ∈ [−0.025, 0.025]
// (the generator's 0.1 m by 0.05 m plate) on a symmetry plane at y = −0.025, carrying half the
// force on the half of the load patch on its side, is the whole — the report's compliance half of
// the whole's (to round-off: the half of the whole's mesh), its discretisation estimate's as well,
// and report.json names the plane. And a plane through the middle of the whole plate, which the
// mesh continues across, is refused on one line.
TEST(CliSimulate, AHalfOnASymmetryPlaneIsHalfTheWhole) {
  const fs::path dir = test::temp_dir("simulate_half");
  const nlohmann::json half = half_plate_scene();
  const fs::path half_file = dir / "half.json";
  std::ofstream(half_file) << half.dump(2);
  const auto h = run_cutwork("simulate " + half_file.string() + " --no-render --quiet --out " + (dir / "h").string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  const auto w = run_cutwork("simulate plate --no-render --quiet --out " + (dir / "w").string());
  ASSERT_EQ(w.exit_code, 0) << w.err;
  const auto hr = read_json(dir / "h" / "report.json"), wr = read_json(dir / "w" / "report.json");
  const double c_half = hr["equilibrium"]["compliance"].get<double>(), c_whole = wr["equilibrium"]["compliance"].get<double>();
  EXPECT_NEAR(2 * c_half, c_whole, 1e-9 * c_whole);
  EXPECT_NEAR(hr["equilibrium"]["max_displacement"].get<double>(), wr["equilibrium"]["max_displacement"].get<double>(),
              1e-9 * wr["equilibrium"]["max_displacement"].get<double>());
  EXPECT_NEAR(2 * hr["discretisation"]["compliance_extrapolated"].get<double>(),
              wr["discretisation"]["compliance_extrapolated"].get<double>(),
              1e-4 * wr["discretisation"]["compliance_extrapolated"].get<double>());
  EXPECT_EQ(hr["solver"]["symmetry_planes"], nlohmann::json({{"y", -0.025}})) << hr["solver"].dump();
  EXPECT_EQ(wr["solver"]["symmetry_planes"], nlohmann::json::object());

  nlohmann::json through = plate_scene();
  through["supports"].push_back(
      {{"type", "symmetry"}, {"axis", "y"}, {"select", {{"entity", "vertices"}, {"y", {{"above", -1e-9}, {"below", 1e-9}}}}}});
  const fs::path through_file = dir / "through.json";
  std::ofstream(through_file) << through.dump(2);
  expect_failure_without_output("simulate " + through_file.string(), dir / "t", "lies inside the surface");
  fs::remove_all(dir);
}

TEST(CliSimulate, AHalfOnASymmetryPlaneIsDesignedAsItsWhole) {
  // `design` of the plate's half: the whole's stencil size (about half the whole's count), every
  // stencil (1+s) r + g/2 or more from the plane — the ligament to its image is the minimum feature —
  // and some nearer than the (1+s) r + g a boundary would ask; the minimum-feature check reads the
  // whole (no violation at the plane).
  const fs::path dir = test::temp_dir("design_half");
  const nlohmann::json half = half_plate_scene();
  const fs::path half_file = dir / "half.json";
  std::ofstream(half_file) << half.dump(2);
  const auto h = run_cutwork("design " + half_file.string() + " --device cpu --no-render --quiet --out " + (dir / "h").string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  const auto w = run_cutwork("design plate --phases pattern --device cpu --no-render --quiet --out " + (dir / "w").string());
  ASSERT_EQ(w.exit_code, 0) << w.err;
  const auto hs = read_json(dir / "h" / "stencils.json")["stencils"];
  const auto ws = read_json(dir / "w" / "stencils.json")["stencils"];
  EXPECT_GT(hs.size(), 0.4 * ws.size());
  EXPECT_LT(hs.size(), 0.6 * ws.size());
  const auto report = read_json(dir / "h" / "report.json");
  const double g = report["fabrication"]["min_feature"].get<double>(), s = half["pattern"]["s"].get<double>();
  double margin = INFINITY;  // δ − (1+s) r, the least over the stencils
  for (const auto& st : hs)
    margin = std::min(margin, st["position"][1].get<double>() + 0.025 - (1 + s) * st["scale"].get<double>());
  EXPECT_GE(margin, 0.5 * g - 1e-9);
  EXPECT_LT(margin, g);
  EXPECT_EQ(report["fabrication"]["violation_count"].get<int>(), 0) << report["fabrication"].dump();
  fs::remove_all(dir);
}

TEST(CliSimulate, StencilsOfADesignReproduceItsEquilibrium) {
  // The pattern design of the plate, then its stencils.json simulated on its own: the same fill
  // ratios, so the same equilibrium as the design's report (Newton-converged, cold vs warm start).
  const fs::path dir = test::temp_dir("simulate_stencils");
  const auto d = run_cutwork("design plate --phases pattern --device cpu --out " + (dir / "design").string());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const auto design = read_json(dir / "design" / "report.json");
  const auto s = run_cutwork("simulate plate --device cpu --stencils " + (dir / "design" / "stencils.json").string() +
                             " --out " + (dir / "sim").string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto sim = read_json(dir / "sim" / "report.json");
  EXPECT_EQ(sim["fill_ratio"]["stencils"], design["stencils"]["count"]);
  const double w_design = design["structure"]["W_max_final"], w_sim = sim["equilibrium"]["W_max"];
  EXPECT_NEAR(w_sim, w_design, 1e-6 * w_design);
  const double m_design = design["structure"]["material_fraction_final"];
  const double m_sim = sim["fill_ratio"]["material_fraction"];
  EXPECT_NEAR(m_sim, m_design, 1e-12);
  EXPECT_LT(m_sim, 0.9);
  EXPECT_EQ(sim["device"]["kind"], "cpu");

  // The same stencils against another scene (other shapes): one line naming the problem.
  const auto other = run_cutwork("simulate bowl --device cpu --stencils " + (dir / "design" / "stencils.json").string() +
                                 " --out " + (dir / "bad").string());
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_EQ(count_lines(other.err), 1) << other.err;
  EXPECT_FALSE(fs::exists(dir / "bad" / "report.json"));
  fs::remove_all(dir);
}

// "lattice": "auto" (the default): simulate reads the lattice from the stencils it is given. A
// square grid of circles turned 30° on the plate (10 mm spacing, 3.5 mm radius): read as square
// along its own axis, so the compliance is the one the scene stating that lattice and axis gets
// (the same calibration and anisotropy), and not the hexagonal calibration's.
TEST(CliSimulate, AnAutoLatticeIsReadFromTheStencils) {
  const fs::path dir = test::temp_dir("simulate_auto_lattice");
  fs::create_directories(dir);
  const double angle = 30 * std::numbers::pi / 180;
  const Eigen::Vector2d a1(std::cos(angle), std::sin(angle)), a2(-a1.y(), a1.x());
  nlohmann::json stencils = nlohmann::json::array();
  for (int i = -15; i <= 15; ++i)
    for (int j = -15; j <= 15; ++j) {
      const Eigen::Vector2d p = 0.01 * (i * a1 + j * a2);
      if (std::abs(p.x()) > 0.08 || std::abs(p.y()) > 0.043) continue;
      stencils.push_back({{"type", "circle"}, {"position", {p.x(), p.y(), 0.0}}, {"scale", 0.0035}, {"angle", 0.0}});
    }
  const fs::path file = dir / "stencils.json";
  std::ofstream(file) << nlohmann::json{{"stencils", stencils}}.dump();
  std::string err;  // of the last run: its notes
  auto simulate = [&](const std::string& name, const nlohmann::json& mechanics) {
    nlohmann::json doc = plate_scene();
    for (const auto& [key, value] : mechanics.items()) doc["mechanics"][key] = value;
    const fs::path scene = dir / (name + ".json");
    std::ofstream(scene) << doc.dump(2);
    const auto r = run_cutwork("simulate " + scene.string() + " --device cpu --no-render --no-discretisation-estimate "
                               "--stencils " + file.string() + " --out " + (dir / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.err;
    err = r.err;
    return read_json(dir / name / "report.json");
  };
  // `check --stencils` says what simulate will model them as.
  const auto checked = run_cutwork("check plate --no-equilibrium --stencils " + file.string());
  EXPECT_EQ(checked.exit_code, 0) << checked.err;
  EXPECT_NE(checked.out.find("perforation lattice square"), std::string::npos) << checked.out;
  EXPECT_NE(checked.out.find("read from the stencils"), std::string::npos) << checked.out;
  const auto automatic = simulate("auto", nlohmann::json::object());
  const auto stated = simulate("square", {{"lattice", "square"}, {"lattice_axis", {a1.x(), a1.y(), 0.0}}});
  const auto hexagonal = simulate("hexagonal", {{"lattice", "hexagonal"}});
  const std::string hexagonal_err = err;
  // Stated to follow the orientation field, which on the plate lies along its length (x): the
  // lattice's axis x at every face, as stated [1, 0, 0] (30° off these stencils' axes).
  const auto by_field = simulate("field", {{"lattice", "square"}, {"lattice_axis", "field"}});
  const auto along_x = simulate("x", {{"lattice", "square"}, {"lattice_axis", {1.0, 0.0, 0.0}}});
  EXPECT_EQ(by_field["mechanics"]["lattice_axis"], "field");
  EXPECT_NEAR(by_field["lattice_order"]["axis_misfit_degrees"].get<double>(), 30.0, 1e-6);
  const double c_field = by_field["equilibrium"]["compliance"], c_x = along_x["equilibrium"]["compliance"];
  EXPECT_NEAR(c_field, c_x, 1e-8 * c_x);
  EXPECT_EQ(automatic["mechanics"]["lattice"], "square");
  EXPECT_EQ(automatic["mechanics"]["lattice_source"], "stencils");
  EXPECT_EQ(stated["mechanics"]["lattice_source"], "scene");
  const Vec3 axis(automatic["mechanics"]["lattice_axis"][0], automatic["mechanics"]["lattice_axis"][1],
                  automatic["mechanics"]["lattice_axis"][2]);
  EXPECT_GT(std::cos(4 * std::acos(std::min(1.0, std::abs(axis.dot(Vec3(a1.x(), a1.y(), 0)))))), 1 - 1e-9);
  EXPECT_EQ(automatic["lattice_order"]["stated"], "auto");
  EXPECT_EQ(automatic["lattice_order"]["used"], "square");
  const double c_auto = automatic["equilibrium"]["compliance"], c_square = stated["equilibrium"]["compliance"];
  const double c_hex = hexagonal["equilibrium"]["compliance"];
  std::printf("square grid at 30°: compliance auto %.6e, stated square %.6e, stated hexagonal %.6e\n", c_auto,
              c_square, c_hex);
  EXPECT_NEAR(c_auto, c_square, 1e-8 * c_square);
  EXPECT_GT(std::abs(c_hex / c_square - 1), 0.005);
  // The hexagonal statement is kept, and the report says the stencils disagree with it.
  EXPECT_NE(hexagonal_err.find("the stencils lie on a square lattice"), std::string::npos) << hexagonal_err;
  bool in_report = false;  // the report keeps the notes too
  for (const auto& n : hexagonal["notes"]) in_report |= n.get<std::string>().find("square lattice") != std::string::npos;
  EXPECT_TRUE(in_report) << hexagonal["notes"].dump();
  if (!HasFailure()) fs::remove_all(dir);
}

// A design reads "auto" from its pattern's layout, the one its structural phase starts from: the
// built-in table's circles exemplar is a square grid laid along y on its top (the table states
// `"lattice": "square", "lattice_axis": [0, 1, 0]`); without that statement the design reads the
// same lattice, with an axis a quarter turn of y or y itself on the top.
TEST(CliSimulate, ADesignReadsAnAutoLatticeFromItsPatternLayout) {
  const fs::path dir = test::temp_dir("design_auto_lattice");
  fs::create_directories(dir);
  const auto shown = run_cutwork("show table");
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  nlohmann::json doc = nlohmann::json::parse(shown.out);
  ASSERT_EQ(doc["mechanics"]["lattice"], "square");
  doc["mechanics"].erase("lattice");
  doc["mechanics"].erase("lattice_axis");
  const fs::path scene = dir / "table_auto.json";
  std::ofstream(scene) << doc.dump(2);
  const auto r = run_cutwork("design " + scene.string() + " --phases pattern --device cpu --no-render --out " +
                             (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = read_json(dir / "out" / "report.json");
  EXPECT_EQ(report["mechanics"]["lattice"], "square");
  EXPECT_EQ(report["mechanics"]["lattice_source"], "stencils");
  const auto& a = report["mechanics"]["lattice_axis"];
  const Vec3 axis(a[0], a[1], a[2]);
  // On the top (normal z) the axis's projection is along x or y.
  const Vec3 on_top(axis.x(), axis.y(), 0);
  ASSERT_GT(on_top.norm(), 0.5);
  EXPECT_GT(std::cos(4 * std::atan2(on_top.x(), on_top.y())), std::cos(4 * 5 * std::numbers::pi / 180)) << a.dump();
  EXPECT_EQ(report["pattern"]["lattice_order"]["used"], "square");
  if (!HasFailure()) fs::remove_all(dir);
}

TEST(CliSimulate, FactorsByShapeAndCornerAreReportedAndDesignAndSimulateAgree) {
  // A plate perforated by stars and circles (the pattern phase): report.json carries each shape's
  // own factors, the corner rule's nodes and radius (the scene's minimum feature), and W_peak —
  // read by shape and by corner from the stencils' cover — is the same number in the design's
  // report and in a simulation of its stencils.
  const fs::path dir = test::temp_dir("simulate_by_shape");
  nlohmann::json scene = plate_scene();
  scene["mechanics"]["stiffness"] = "homogenised";
  scene["stencils"] = nlohmann::json::array({{{"name", "star"}, {"kind", "star"}}, {{"name", "circle"}, {"kind", "circle"}}});
  scene["fabrication"]["min_feature"] = 0.0005;
  const fs::path scene_file = dir / "plate_stars.json";
  std::ofstream(scene_file) << scene.dump(2);
  const auto d = run_cutwork("design " + scene_file.string() + " --phases pattern --device cpu --no-render --out " +
                             (dir / "design").string());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const auto design = read_json(dir / "design" / "report.json");
  EXPECT_EQ(design["mechanics"]["corner_radius"], 0.0005);
  const auto& curve = design["mechanics"]["stiffness_curve"];
  ASSERT_EQ(curve["corner_nodes"].size(), size_t(kCornerNodes));
  EXPECT_EQ(curve["corner_nodes"][0], 0.0);
  EXPECT_EQ(curve["corner_nodes"][kCornerNodes - 1], 1.0);
  const size_t n = curve["alpha"].size();
  for (const char* shape : {"star", "circle"}) {
    SCOPED_TRACE(shape);
    ASSERT_TRUE(curve["concentration_by_shape"].contains(shape)) << curve["concentration_by_shape"];
    const auto& k = curve["concentration_by_shape"][shape];
    ASSERT_EQ(k["membrane_concentration"].size(), n);
    ASSERT_EQ(k["membrane_concentration_by_corner"].size(), n);
    for (size_t a = 0; a < n; ++a) {
      // Each shape's factor at most the worst shape's; node 0 of the corner table is the table by biaxiality.
      EXPECT_LE(k["membrane_concentration"][a].get<double>(), curve["membrane_concentration"][a].get<double>());
      ASSERT_EQ(k["membrane_concentration_by_corner"][a].size(), size_t(kCornerNodes * kBiaxialityNodes));
      for (int j = 0; j < kBiaxialityNodes; ++j)
        EXPECT_EQ(k["membrane_concentration_by_corner"][a][size_t(j)], k["membrane_concentration_by_biaxiality"][a][size_t(j)]);
    }
  }
  const std::string stencils = (dir / "design" / "stencils.json").string();
  const auto h = run_cutwork("simulate " + scene_file.string() + " --device cpu --no-render --stencils " + stencils +
                             " --out " + (dir / "simulate").string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  const auto sim = read_json(dir / "simulate" / "report.json");
  const double wp_design = design["structure"]["W_peak_max_final"], wp_sim = sim["equilibrium"]["W_peak_max"];
  EXPECT_NEAR(wp_sim, wp_design, 1e-6 * wp_design);
  EXPECT_GT(wp_sim, sim["equilibrium"]["W_max"].get<double>());
  // The thick plate's transition (the minimum feature over the thickness), reported with the
  // Kirchhoff plate's W_peak beside it, the same in both commands.
  const double thick_scale =
      scene["fabrication"]["min_feature"].get<double>() / scene["material"]["thickness"].get<double>();
  EXPECT_DOUBLE_EQ(sim["equilibrium"]["W_peak_thick_scale"].get<double>(), thick_scale);
  EXPECT_DOUBLE_EQ(design["structure"]["W_peak_thick_scale"].get<double>(), thick_scale);
  const double kirchhoff_design = design["structure"]["W_peak_kirchhoff_max_final"],
               kirchhoff_sim = sim["equilibrium"]["W_peak_kirchhoff_max"];
  EXPECT_NEAR(kirchhoff_sim, kirchhoff_design, 1e-6 * kirchhoff_design);
  EXPECT_NE(kirchhoff_sim, wp_sim);

  // The same stencils cut by a 0.5 mm tool (fabrication.tool_radius): the factors by corner are the
  // tool's (cells of the holes it cuts, at its nodes), read at the tool's radius; the stars' tips
  // are rounds of 0.5 mm, which concentrate more than the corner rule's rim outside 0.5 mm of them
  // (the default star's uniaxial K_m 148 at 1/32 of its radius against the corner rule's 11).
  scene["fabrication"]["tool_radius"] = 0.0005;
  const fs::path tool_file = dir / "plate_stars_tool.json";
  std::ofstream(tool_file) << scene.dump(2);
  const auto t = run_cutwork("simulate " + tool_file.string() + " --device cpu --no-render --stencils " + stencils +
                             " --out " + (dir / "tool").string());
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const auto tool = read_json(dir / "tool" / "report.json");
  EXPECT_EQ(tool["mechanics"]["tool_radius"], 0.0005);
  EXPECT_EQ(tool["mechanics"]["corner_radius"], 0.0005);
  const auto& tool_curve = tool["mechanics"]["stiffness_curve"];
  EXPECT_EQ(tool_curve["corner_factors"], "tool");
  EXPECT_EQ(curve["corner_factors"], "corner_rule");
  ASSERT_EQ(tool_curve["corner_nodes"].size(), size_t(kToolNodes));
  EXPECT_EQ(tool_curve["corner_nodes"][0], 1.0 / 64);
  EXPECT_EQ(tool_curve["membrane_ratio"], curve["membrane_ratio"]) << "the stiffness is the drawn holes'";
  const double wp_tool = tool["equilibrium"]["W_peak_max"];
  RecordProperty("W_peak", fmt::format("corner rule {:.4g}, tool {:.4g} J/m^2", wp_sim, wp_tool));
  // The largest face's W_peak rises (measured 19.9 → 23.9 J/m²: the plate's peak face is not all
  // star); without the tool's factors it would be the same number.
  EXPECT_GT(wp_tool, 1.05 * wp_sim);
  EXPECT_EQ(tool["equilibrium"]["W_max"], sim["equilibrium"]["W_max"]) << "the coarse model is the drawn one";
  fs::remove_all(dir);
}

TEST(CliSimulate, HomogenisedStiffnessSoftensThePerforatedShellAndIsReported) {
  // The plate's pattern design simulated under both fill stiffness rules: the homogenised rule
  // (perforated material is softer than its fill ratio says) gives a larger compliance; the design
  // and a simulation of its stencils agree under it too; the report names the rule and its curve.
  const fs::path dir = test::temp_dir("simulate_homogenised");
  nlohmann::json scene = plate_scene();
  scene["mechanics"]["stiffness"] = "homogenised";
  const fs::path scene_file = dir / "plate_homogenised.json";
  std::ofstream(scene_file) << scene.dump(2);
  const auto d = run_cutwork("design " + scene_file.string() + " --phases pattern --device cpu --no-render --out " +
                             (dir / "design").string());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  EXPECT_NE(d.err.find("ligament peak W_peak"), std::string::npos) << "the summary line gives W_peak: " << d.err;
  const auto design = read_json(dir / "design" / "report.json");
  EXPECT_EQ(design["mechanics"]["stiffness"], "homogenised");
  EXPECT_EQ(design["device"]["render"], "none") << "--no-render draws nothing";
  const auto& curve = design["mechanics"]["stiffness_curve"];
  ASSERT_TRUE(curve.contains("alpha")) << design["mechanics"];
  const size_t n = curve["alpha"].size();
  ASSERT_GE(n, 3u);
  EXPECT_EQ(curve["membrane_ratio"][n - 1], 1.0);
  for (size_t k = 0; k + 1 < n; ++k) {
    EXPECT_LT(curve["membrane_ratio"][k].get<double>(), 1.0);
    EXPECT_LT(curve["bending_ratio"][k].get<double>(), 1.0);
  }
  // The concentration factors W_peak uses, one per sample, every one above 1 (the α = 1 sample
  // is the dilute limit, Kirsch's hole).
  ASSERT_EQ(curve["membrane_concentration"].size(), n);
  ASSERT_EQ(curve["bending_concentration"].size(), n);
  for (size_t k = 0; k < n; ++k) {
    EXPECT_GT(curve["membrane_concentration"][k].get<double>(), 1.5);
    EXPECT_GT(curve["bending_concentration"][k].get<double>(), 1.5);
  }
  // And by biaxiality: a row per sample over the nodes ρ = −1 … 1, none above the worst state's.
  ASSERT_EQ(curve["biaxiality"].size(), size_t(kBiaxialityNodes));
  EXPECT_EQ(curve["biaxiality"][0], -1.0);
  EXPECT_EQ(curve["biaxiality"][kBiaxialityNodes - 1], 1.0);
  ASSERT_EQ(curve["membrane_concentration_by_biaxiality"].size(), n);
  ASSERT_EQ(curve["bending_concentration_by_biaxiality"].size(), n);
  for (size_t k = 0; k < n; ++k)
    for (const char* part : {"membrane", "bending"}) {
      const auto& row = curve[std::string(part) + "_concentration_by_biaxiality"][k];
      ASSERT_EQ(row.size(), size_t(kBiaxialityNodes));
      for (const auto& v : row) EXPECT_LE(v.get<double>(), curve[std::string(part) + "_concentration"][k].get<double>());
    }
  // The peak measure's threshold is reported with its measure.
  EXPECT_EQ(design["structure"]["measure"], "mean");

  const std::string stencils = (dir / "design" / "stencils.json").string();
  const auto h = run_cutwork("simulate " + scene_file.string() + " --device cpu --no-render --stencils " + stencils +
                             " --out " + (dir / "homogenised").string());
  ASSERT_EQ(h.exit_code, 0) << h.err;
  nlohmann::json linear_scene = plate_scene();
  linear_scene["mechanics"] = {{"stiffness", "linear"}, {"filter", "none"}};  // the paper's rule
  const fs::path linear_file = dir / "plate_linear.json";
  std::ofstream(linear_file) << linear_scene.dump(2);
  const auto l = run_cutwork("simulate " + linear_file.string() + " --device cpu --no-render --stencils " + stencils +
                             " --out " + (dir / "linear").string());
  ASSERT_EQ(l.exit_code, 0) << l.err;
  const auto hom = read_json(dir / "homogenised" / "report.json"), lin = read_json(dir / "linear" / "report.json");
  EXPECT_EQ(hom["solver"]["stiffness"], "homogenised");
  EXPECT_EQ(hom["device"]["render"], "none");
  EXPECT_EQ(hom["device"]["kind"], "cpu");
  EXPECT_EQ(lin["solver"]["stiffness"], "linear");
  const double w_design = design["structure"]["W_max_final"], w_sim = hom["equilibrium"]["W_max"];
  EXPECT_NEAR(w_sim, w_design, 1e-6 * w_design);
  // W_peak (peak_energy_density.h) only where the cell problems gave concentration factors (> 1).
  const double wp_design = design["structure"]["W_peak_max_final"], wp_sim = hom["equilibrium"]["W_peak_max"];
  EXPECT_NEAR(wp_sim, wp_design, 1e-6 * wp_design);
  EXPECT_GT(wp_sim, w_sim);
  // The state the factors were read at, at the W_peak face: ρ in [−1, 1].
  for (const char* part : {"membrane", "bending"}) {
    const double rho = hom["equilibrium"]["W_peak_biaxiality"][part];
    EXPECT_GE(rho, -1.0) << part;
    EXPECT_LE(rho, 1.0) << part;
    EXPECT_NEAR(rho, design["equilibrium"]["W_peak_biaxiality"][part].get<double>(), 1e-6) << part;
  }
  EXPECT_TRUE(lin["equilibrium"]["W_peak_max"].is_null());
  EXPECT_TRUE(lin["equilibrium"]["W_peak_biaxiality"]["membrane"].is_null());
  EXPECT_EQ(lin["equilibrium"]["W_peak_max_face"], -1);
  // The narrow ligaments' estimates (solvers/objective/ligament_peak.h): the design's and the
  // simulation's are the same (the same stencils, cut and W_peak), each at least its face's W_peak;
  // the linear rule has no W_peak and so no estimate.
  const auto& lig_design = design["structure"]["ligaments"];
  const auto& lig_sim = hom["ligaments"];
  ASSERT_TRUE(lig_design.is_object()) << design["structure"];
  EXPECT_EQ(lig_design["searched"], lig_sim["searched"]);
  const double wl_design = lig_design["W_ligament_max"], wl_sim = lig_sim["W_ligament_max"];
  EXPECT_NEAR(wl_sim, wl_design, 1e-6 * wl_design);
  EXPECT_TRUE(lig_design["rule"].is_string());
  for (const auto& w : lig_sim["worst"]) {
    EXPECT_GE(w["W"].get<double>(), w["W_peak_face"].get<double>());
    EXPECT_GE(w["factor"].get<double>(), 1.0);
    EXPECT_GT(w["width"].get<double>(), 0.0);
  }
  EXPECT_FALSE(lin.contains("ligaments"));
  EXPECT_GT(hom["equilibrium"]["compliance"].get<double>(), 1.02 * lin["equilibrium"]["compliance"].get<double>());

  scene["mechanics"]["stiffness"] = "periodic";
  std::ofstream(scene_file) << scene.dump(2);
  expect_failure_without_output("simulate " + scene_file.string(), dir / "bad", "/mechanics/stiffness");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork

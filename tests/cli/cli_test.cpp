// The `cutwork` command line: subcommands, help, exit codes, one-line errors, atomic outputs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "host/scene/scene.h"
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

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

using test::read_json;

// A bad input gives exit code 2 and exactly one line on stderr containing every fragment.
void expect_one_line_error(const test::CommandResult& r, std::initializer_list<std::string> fragments) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
}

TEST(Cli, HelpOnEverySubcommand) {
  for (const char* sub : {"scenes", "show", "check", "design", "simulate", "verify", "render", "sweep"}) {
    SCOPED_TRACE(sub);
    const auto r = run_cutwork(std::string(sub) + " --help");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
  }
  const auto r = run_cutwork("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"scenes", "show", "check", "design", "simulate", "verify", "render", "sweep"}) EXPECT_NE(r.out.find(sub), std::string::npos);
}

TEST(Cli, NoSubcommandOrUnknownOptionIsExitTwo) {
  expect_one_line_error(run_cutwork(""), {"subcommand"});
  expect_one_line_error(run_cutwork("design --frobnicate"), {"frobnicate"});
}

TEST(Cli, ScenesListsOneLineEach) {
  const auto r = run_cutwork("scenes");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(count_lines(r.out), int(builtin_scenes().size()));
  for (const auto& b : builtin_scenes()) EXPECT_NE(r.out.find(b.name), std::string::npos);
}

TEST(Cli, ShowPrintsACompleteSceneThatValidates) {
  const fs::path dir = test::temp_dir("show");
  for (const auto& b : builtin_scenes()) {
    SCOPED_TRACE(b.name);
    const auto r = run_cutwork("show " + b.name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto doc = nlohmann::json::parse(r.out);
    for (const char* key : {"mesh", "material", "supports", "loads", "stencils", "pattern", "structure"})
      EXPECT_TRUE(doc.contains(key)) << key;
    const fs::path file = dir / (b.name + ".json");
    write_text(file, r.out);
    const auto c = run_cutwork("check " + file.string());
    EXPECT_EQ(c.exit_code, 0) << c.err;
    EXPECT_NE(c.out.find("supports:"), std::string::npos) << c.out;
  }
  expect_one_line_error(run_cutwork("show nonesuch"), {"nonesuch", "pavilion"});
  fs::remove_all(dir);
}

TEST(Cli, CheckSummarisesAMesh) {
  const fs::path dir = test::temp_dir("check");
  // A flat 2×2-quad grid: the defaults pin a flat mesh's boundary, leaving the centre free.
  std::string grid;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) grid += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int a = 1 + i + 3 * j, b = a + 1, c = a + 4, d = a + 3;
      grid += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + "\nf " +
              std::to_string(a) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
    }
  write_text(dir / "grid.obj", grid);
  const auto r = run_cutwork("check " + (dir / "grid.obj").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("9 vertices, 8 faces"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Euler characteristic 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a plain mesh; using defaults"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("boundary vertices"), std::string::npos) << r.out;
  // Simulated on the grid divided three times (the first subdivision within 2% of converged: 51%,
  // 15%, 3.5%, 0.9% from 8 to 512 triangles), whose boundary has 64 vertices.
  EXPECT_NE(r.out.find("mesh.sim_subdivisions auto: simulating on the file's mesh divided 3 times (512 triangles)"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("supports: 64 fixed vertices"), std::string::npos) << r.out;
  // Two triangles: every vertex is on the boundary, so nothing is left to simulate — `check`
  // says so (it validates what a simulation needs), one line, exit 2.
  write_text(dir / "quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
  expect_one_line_error(run_cutwork("check " + (dir / "quad.obj").string()), {"every vertex"});
  fs::remove_all(dir);
}

TEST(Cli, BadInputsAreOneLineAndExitTwoAndWriteNothing) {
  const fs::path dir = test::temp_dir("bad");
  write_text(dir / "nan.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
  write_text(dir / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  write_text(dir / "broken.json", "{\"mesh\": {\"generator\": \"plate\"},");
  write_text(dir / "badkey.json", R"({"mesh": {"generator": "plate"}, "materiel": {}})");
  write_text(dir / "badrange.json", R"({"mesh": {"generator": "plate"}, "material": {"poisson_ratio": 0.9}})");
  write_text(dir / "nothing.json",
             R"({"mesh": {"generator": "plate"}, "supports": [{"select": {"z": {"above": 100}}}]})");
  write_text(dir / "notes.txt", "hello");
  struct Case {
    std::string arg;
    std::vector<std::string> fragments;
  } cases[] = {
      {(dir / "missing.obj").string(), {"missing.obj", "no such file"}},
      {(dir / "nan.obj").string(), {"nan.obj"}},
      {(dir / "range.obj").string(), {"range.obj"}},
      {(dir / "broken.json").string(), {"broken.json", "invalid JSON"}},
      {(dir / "badkey.json").string(), {"badkey.json", "/materiel", "unknown key"}},
      {(dir / "badrange.json").string(), {"badrange.json", "/material/poisson_ratio", "[0, 0.5)"}},
      {(dir / "nothing.json").string(), {"nothing.json", "/supports/0/select", "selects no"}},
      {(dir / "notes.txt").string(), {"notes.txt", "unknown file type"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.arg);
    expect_one_line_error(run_cutwork("check " + c.arg), {});
    const fs::path out = dir / "out";
    const auto r = run_cutwork("design " + c.arg + " --out " + out.string());
    std::initializer_list<std::string> none{};
    (void)none;
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(count_lines(r.err), 1) << r.err;
    for (const auto& f : c.fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << "a failed design must write nothing";
  }
  fs::remove_all(dir);
}

TEST(Cli, DesignWritesTheReportForEveryBuiltinScene) {
  const fs::path dir = test::temp_dir("design");
  for (const auto& b : builtin_scenes()) {
    SCOPED_TRACE(b.name);
    const fs::path out = dir / b.name;
    const auto r = run_cutwork("design " + b.name + " --quiet --phases none --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.err.empty()) << "--quiet prints nothing: " << r.err;
    const auto report = read_json(out / "report.json");
    EXPECT_EQ(report["scene"], b.name);
    for (const char* key : {"vertices", "triangles", "sim_vertices", "sim_triangles"})
      EXPECT_GT(report["mesh"][key].get<int>(), 0) << key;
    EXPECT_TRUE(report["timings"].is_object());
    // No temporary files are left behind by the atomic writes.
    for (const auto& entry : fs::directory_iterator(out))
      EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  }
  fs::remove_all(dir);
}

/// The faces and their per-face properties named in an ASCII or binary PLY header.
std::string ply_header(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string line, header;
  while (std::getline(in, line) && line != "end_header") header += line + "\n";
  return header;
}

TEST(Cli, DesignRunsThePipelineForEveryBuiltinScene) {
  // Every built-in scene through both phases (few iterations: this is about the product's
  // outputs; the optimisation itself is tested in tests/solvers/optimize).
  const fs::path dir = test::temp_dir("design_full");
  for (const auto& b : builtin_scenes()) {
    SCOPED_TRACE(b.name);
    const fs::path out = dir / b.name;
    const auto r = run_cutwork("design " + b.name + " --iterations 4 --device cpu --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.empty()) << "no progress display when stdout is not a terminal: " << r.out;
    const auto report = read_json(out / "report.json");
    for (const char* key : {"scene", "device", "mesh", "stencils", "phases", "structure", "timings", "cut"})
      EXPECT_TRUE(report.contains(key)) << key;
    EXPECT_EQ(report["device"]["kind"], "cpu");
    for (const char* key : {"kind", "name", "driver"}) EXPECT_TRUE(report["device"].contains(key)) << key;
    const auto& phases = report["phases"];
    ASSERT_GE(phases.size(), 1u);
    EXPECT_EQ(phases[0]["name"], "pattern");
    for (const auto& ph : phases)
      for (const char* key : {"name", "iterations", "seconds", "J_start", "J_end", "S_start", "S_end", "P_start",
                              "P_end"})
        EXPECT_TRUE(ph.contains(key)) << key;
    const bool has_structure = report["structure"]["objective"] != "none";
    EXPECT_EQ(phases.size(), has_structure ? 2u : 1u);
    for (const char* key : {"objective", "beta", "W_max_uncut", "W_max_pattern", "W_max_final", "compliance_pattern",
                            "compliance_final", "material_fraction_pattern", "material_fraction_final", "overlaps"})
      EXPECT_TRUE(report["structure"].contains(key)) << key;
    EXPECT_EQ(report["structure"]["overlaps"], 0);
    // The converging reference beside W_max (energy_density_reference.h): at most W_max.
    const auto& ref = report["structure"]["W_reference_uncut"];
    ASSERT_TRUE(ref.is_object());
    EXPECT_GT(ref["W"].get<double>(), 0);
    EXPECT_LE(ref["W"].get<double>(), report["structure"]["W_max_uncut"].get<double>());
    EXPECT_GE(ref["faces_excluded"].get<int>(), 0);
    EXPECT_GE(ref["area_excluded"].get<double>(), 0);
    EXPECT_GE(ref["W_max_over_W"].get<double>(), 1);
    // stencils.json holds the report's stencils.
    const auto stencils = read_json(out / "stencils.json");
    EXPECT_EQ(stencils["stencils"].size(), report["stencils"]["count"].get<size_t>());
    ASSERT_GT(stencils["stencils"].size(), 0u);
    for (const char* key : {"type", "position", "normal", "tangent", "scale", "angle", "bounding_radius"})
      EXPECT_TRUE(stencils["stencils"][0].contains(key)) << key;
    EXPECT_TRUE(stencils["shapes"].is_object());
    // fields.ply: the simulation mesh with per-face alpha and W.
    const std::string header = ply_header(out / "fields.ply");
    EXPECT_NE(header.find("element face " + std::to_string(report["mesh"]["sim_triangles"].get<int>())),
              std::string::npos) << header;
    EXPECT_NE(header.find(" alpha"), std::string::npos) << header;
    EXPECT_NE(header.find(" W"), std::string::npos) << header;
    // cut.obj: a mesh cutwork itself reads back (valid, manifold, consistently oriented). (Whether
    // the cut surface as a plain mesh carries the plain-mesh default loads is not the question.)
    const auto check = run_cutwork("check --no-equilibrium " + (out / "cut.obj").string());
    EXPECT_NE(check.out.find(std::to_string(report["cut"]["triangles"].get<int>()) + " faces"), std::string::npos)
        << check.out << check.err;
  }
  fs::remove_all(dir);
}

TEST(Cli, DesignPhasesPatternWritesThePatternDesign) {
  const fs::path dir = test::temp_dir("design_pattern");
  const auto r = run_cutwork("design plate --phases pattern --iterations 10 --quiet --device cpu --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
  const auto report = read_json(dir / "report.json");
  ASSERT_EQ(report["phases"].size(), 1u);
  EXPECT_EQ(report["phases"][0]["name"], "pattern");
  EXPECT_EQ(report["phases"][0]["iterations"], 10);
  EXPECT_EQ(report["structure"]["W_max_final"], report["structure"]["W_max_pattern"]);
  for (const char* f : {"stencils.json", "fields.ply", "cut.obj"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
  fs::remove_all(dir);
}

TEST(Cli, DesignDeviceChoices) {
  const fs::path dir = test::temp_dir("design_device");
  // An unknown device is a usage error naming the accepted values.
  const auto bad = run_cutwork("design plate --device tpu --out " + (dir / "bad").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--device"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad" / "report.json"));
  // With no Vulkan driver at all, auto falls back to the CPU with one warning line and vulkan
  // fails with one line (VK_DRIVER_FILES pointing nowhere hides every driver from the loader).
  const std::string no_driver = "env VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json ";
  const auto cmd = [&](const std::string& args) {
    return test::run_shell(no_driver + test::cutwork_binary().string() + " " + args);
  };
  const auto a = cmd("design plate --phases pattern --iterations 2 --device auto --out " + (dir / "auto").string());
  ASSERT_EQ(a.exit_code, 0) << a.err;
  EXPECT_EQ(read_json(dir / "auto" / "report.json")["device"]["kind"], "cpu");
  EXPECT_NE(a.err.find("warning"), std::string::npos) << a.err;
  const auto v = cmd("design plate --phases pattern --iterations 2 --device vulkan --out " + (dir / "vk").string());
  EXPECT_EQ(v.exit_code, 2);
  EXPECT_EQ(count_lines(v.err), 1) << v.err;
  EXPECT_FALSE(fs::exists(dir / "vk" / "report.json"));
  fs::remove_all(dir);
}

TEST(Cli, DesignDefaultsToThePavilion) {
  const fs::path dir = test::temp_dir("default");
  const auto r = run_cutwork("design --quiet --phases none --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(dir / "report.json")["scene"], "pavilion");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork

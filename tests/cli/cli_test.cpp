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

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

// A bad input gives exit code 2 and exactly one line on stderr containing every fragment.
void expect_one_line_error(const test::CommandResult& r, std::initializer_list<std::string> fragments) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
}

TEST(Cli, HelpOnEverySubcommand) {
  for (const char* sub : {"scenes", "show", "check", "design", "simulate"}) {
    SCOPED_TRACE(sub);
    const auto r = run_cutwork(std::string(sub) + " --help");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
  }
  const auto r = run_cutwork("--help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* sub : {"scenes", "show", "check", "design", "simulate"}) EXPECT_NE(r.out.find(sub), std::string::npos);
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
  EXPECT_NE(r.out.find("supports: 8 fixed vertices"), std::string::npos) << r.out;
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

TEST(Cli, DesignDefaultsToThePavilion) {
  const fs::path dir = test::temp_dir("default");
  const auto r = run_cutwork("design --quiet --phases none --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(dir / "report.json")["scene"], "pavilion");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace cutwork

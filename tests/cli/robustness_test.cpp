// Hostile inputs and crashing runs (issue 15): output folders hold one complete set, a second
// run into a folder fails at once (or waits), and each mutant input of tests/data/mutants gives
// one clear line and exit code 2 from `check` as well as from the commands that would run it.
// Every command runs under `timeout` so that a hang (a FIFO read, an unbounded loop) fails the
// test instead of blocking it.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "host/mesh/mesh_io.h"
#include "tests/solvers/support/test_meshes.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;

int count_lines(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// `cutwork ARGS`, killed after 60 s (a hang is a failure, not a stuck test suite).
test::CommandResult cutwork(const std::string& args) {
  return test::run_shell("timeout -s KILL 60 " + test::cutwork_binary().string() + " " + args);
}

void expect_one_line_error(const test::CommandResult& r, std::initializer_list<std::string> fragments) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << "missing '" << f << "' in: " << r.err;
}

fs::path mutant(const std::string& name) { return test::data_dir() / "mutants" / name; }

/// The visible entries of `dir` and the content of each file.
std::map<std::string, std::string> folder(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(dir)) files[e.path().filename().string()] = slurp(e.path());
  return files;
}

TEST(CliRobustness, ASecondRunIntoALockedFolderFailsAtOnceOrWaits) {
  const fs::path dir = test::temp_dir("robust_lock");
  // The test holds the folder's lock as a running cutwork would.
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);  // not inherited by the runs
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  for (const char* cmd : {"simulate plate", "design plate --phases none"}) {
    SCOPED_TRACE(cmd);
    expect_one_line_error(cutwork(std::string(cmd) + " --out " + dir.string()),
                          {dir.string(), "another cutwork run is writing into this folder", "--wait"});
    EXPECT_TRUE(fs::is_empty(dir)) << "the second run wrote nothing";
  }
  // With --wait it waits for the lock and then runs.
  std::thread release([fd] {
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    ::close(fd);
  });
  const auto r = cutwork("design plate --phases none --wait --out " + dir.string());
  release.join();
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("waiting for another cutwork run"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::exists(dir / "report.json"));
  fs::remove_all(dir);
}

TEST(CliRobustness, OutputFoldersHoldOneCompleteSet) {
  const fs::path dir = test::temp_dir("robust_sets");
  const fs::path out = dir / "out";
  // A design's set, then a simulation into the same folder: the design's stencils.json and
  // cut.obj go (they would be mixed with a report that is not theirs).
  ASSERT_EQ(cutwork("design plate --phases pattern --iterations 2 --device cpu --quiet --out " + out.string()).exit_code, 0);
  for (const char* f : {"report.json", "stencils.json", "fields.ply", "cut.obj", ".cutwork-outputs"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  fs::copy_file(out / "stencils.json", dir / "stencils.json");
  const auto s = cutwork("simulate plate --device cpu --quiet --no-render --stencils " +
                         (dir / "stencils.json").string() + " --out " + out.string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto after = folder(out);
  std::set<std::string> names;
  for (const auto& [name, text] : after) names.insert(name);
  // simulate --no-render's set: fields.ply, fields.vtu and report.json (last), with the manifest.
  EXPECT_EQ(names, (std::set<std::string>{".cutwork-outputs", "fields.ply", "fields.vtu", "report.json"}));
  EXPECT_EQ(after.at(".cutwork-outputs"), "fields.ply\nfields.vtu\n.cutwork-outputs\nreport.json\n");

  // A failed run into a folder holding a set leaves the set exactly as it was.
  const auto bad = cutwork("simulate plate --device cpu --stencils " + mutant("stencils_scale_1e308.json").string() +
                           " --out " + out.string());
  expect_one_line_error(bad, {"stencils_scale_1e308.json", "/stencils/0/scale"});
  EXPECT_EQ(folder(out), after);

  // A failed run into a new folder leaves nothing, not even the folder.
  expect_one_line_error(cutwork("design " + mutant("huge_count.json").string() + " --out " + (dir / "new").string()),
                        {"/pattern/count"});
  EXPECT_FALSE(fs::exists(dir / "new"));
  fs::remove_all(dir);
}

TEST(CliRobustness, StaleTemporariesOfDeadRunsAreCleanedUp) {
  const fs::path dir = test::temp_dir("robust_stale");
  std::ofstream(dir / ".stencils.json.tmp123456") << std::string(131072, 'x');
  fs::create_directory(dir / ".cutwork-staging.4000000");
  std::ofstream(dir / ".cutwork-staging.4000000" / "fields.ply") << "partial";
  ASSERT_EQ(cutwork("design plate --phases none --quiet --out " + dir.string()).exit_code, 0);
  EXPECT_FALSE(fs::exists(dir / ".stencils.json.tmp123456"));
  EXPECT_FALSE(fs::exists(dir / ".cutwork-staging.4000000"));
  fs::remove_all(dir);
}

/// The mutants: each is refused by `check` with the line `design` (and where it applies
/// `simulate`) gives, naming the file, the key and what is wrong.
TEST(CliRobustness, CheckRejectsWhatDesignRejects) {
  const fs::path out = test::temp_dir("robust_mutants");
  struct Case {
    std::string file;
    std::vector<std::string> fragments;
  } cases[] = {
      {"exemplar_unknown_key.json", {"/pattern/exemplar/"}},
      {"exemplar_unknown_type.json", {"/pattern/exemplar", "nonesuch"}},
      {"duplicate_key.json", {"duplicate_key.json", "invalid JSON", "'name' appears twice"}},
      {"huge_scale.json", {"/pattern/scale", "stencils", "--max-stencils"}},
      {"huge_count.json", {"/pattern/count", "10000000", "--max-stencils"}},
      {"sim_edge_length.json", {"/mesh", "sim_edge_length must be"}},
      {"missing_sizing_file.json", {"missing_sizing.txt", "no such file"}},
      {"not_an_stl.stl", {"not_an_stl.stl", "cannot be parsed: not an STL file", "facets"}},
      // Header counts that lie (issue 22): checked against the file's size before anything is read.
      {"huge_face_count.off", {"huge_face_count.off", "declares 9223372036854775807 faces"}},
      {"huge_vertex_count_binary.ply", {"declares 9223372036854775807 vertex elements"}},
      {"huge_facet_count.stl", {"declaring 4294967295 facets"}},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string file = mutant(c.file).string();
    const auto checked = cutwork("check " + file);
    expect_one_line_error(checked, {});
    const auto designed = cutwork("design " + file + " --iterations 2 --device cpu --out " + (out / "d").string());
    expect_one_line_error(designed, {});
    for (const auto& f : c.fragments) {
      EXPECT_NE(checked.err.find(f), std::string::npos) << "check: missing '" << f << "' in: " << checked.err;
      EXPECT_NE(designed.err.find(f), std::string::npos) << "design: missing '" << f << "' in: " << designed.err;
    }
    EXPECT_FALSE(fs::exists(out / "d"));
  }
  // stencils.json mutants: `check --stencils` says what `simulate --stencils` says.
  for (const auto& [file, key] : {std::pair<std::string, std::string>{"stencils_scale_1e308.json", "/stencils/0/scale"},
                                  {"stencils_far_away.json", "/stencils/0/position"}}) {
    SCOPED_TRACE(file);
    const auto checked = cutwork("check plate --stencils " + mutant(file).string());
    const auto simulated =
        cutwork("simulate plate --device cpu --stencils " + mutant(file).string() + " --out " + (out / "s").string());
    expect_one_line_error(checked, {file, key});
    expect_one_line_error(simulated, {file, key});
    EXPECT_FALSE(fs::exists(out / "s"));
  }
  fs::remove_all(out);
}

TEST(CliRobustness, HostileFilesAreOneBoundedLine) {
  const fs::path dir = test::temp_dir("robust_hostile");
  // 60,000 levels of nesting in the exemplar (once a stack overflow in the scene parser).
  {
    nlohmann::json doc = nlohmann::json::parse(slurp(mutant("exemplar_unknown_key.json")));
    doc["pattern"]["exemplar"] = {{"domain", "DEEP"}};
    std::string deep = doc.dump();
    deep.replace(deep.find("\"DEEP\""), 6, std::string(60000, '[') + std::string(60000, ']'));
    std::ofstream(dir / "deep.json") << deep;
  }
  expect_one_line_error(cutwork("check " + (dir / "deep.json").string()), {"deep.json", "nested more than 64 levels"});
  // A FIFO named like a mesh and like a scene: refused, not read (reading would block).
  for (const char* name : {"x.obj", "x.json"}) {
    ASSERT_EQ(::mkfifo((dir / name).c_str(), 0600), 0);
    expect_one_line_error(cutwork("check " + (dir / name).string()), {name, "not a regular file"});
  }
  // A 1 MB unknown key: the error line names it, shortened.
  {
    nlohmann::json doc = nlohmann::json::parse(slurp(mutant("huge_count.json")));
    doc["pattern"].erase("count");
    doc[std::string(1 << 20, 'k')] = 1;
    std::ofstream(dir / "long_key.json") << doc.dump();
  }
  const auto r = cutwork("check " + (dir / "long_key.json").string());
  expect_one_line_error(r, {"long_key.json", "unknown key", "(1048576 characters)"});
  EXPECT_LT(r.err.size(), 2100u);
  // A 200 kB description is not echoed whole by `check`.
  {
    nlohmann::json doc = nlohmann::json::parse(slurp(mutant("huge_count.json")));
    doc["pattern"].erase("count");
    doc["description"] = std::string(200000, 'd');
    std::ofstream(dir / "long_description.json") << doc.dump();
  }
  const auto c = cutwork("check " + (dir / "long_description.json").string());
  EXPECT_EQ(c.exit_code, 0) << c.err;
  EXPECT_LT(c.out.size(), 5000u);
  fs::remove_all(dir);
}

// A shell a millionth as thick as its triangles has a rest stiffness that is singular in double
// precision: its bending stiffness, (h/ℓ)² of its membrane's, is lost. That is said as what it is
// (a thickness, perhaps in the wrong unit), not as missing supports; a hundred times thicker it
// factorises and is simply too weak for the load: not even its smallest load step is carried, which
// is said without the "0.0% ... 0 m" the message used to print.
TEST(CliRobustness, AShellTooThinForItsMeshIsSaidToBe) {
  const fs::path dir = test::temp_dir("robust_thin");
  nlohmann::json doc = nlohmann::json::parse(cutwork("show plate").out);
  doc["material"]["thickness"] = 1e-10;
  std::ofstream(dir / "thin.json") << doc.dump();
  const std::string run = "simulate " + (dir / "thin.json").string() + " --no-render --no-discretisation-estimate --out ";
  expect_one_line_error(cutwork(run + (dir / "a").string()),
                        {"the shell is too thin for its mesh", "thickness 1e-10 m", "check the thickness"});
  EXPECT_FALSE(fs::exists(dir / "a"));
  doc["material"]["thickness"] = 1e-8;
  std::ofstream(dir / "thin.json") << doc.dump();
  const auto weak = cutwork(run + (dir / "b").string());
  expect_one_line_error(weak, {"the structure can carry none of the load (not even 0.002 of it: at that fraction"});
  EXPECT_EQ(weak.err.find("too thin"), std::string::npos) << weak.err;
  fs::remove_all(dir);
}

// A part's mesh drawn in millimetres (what a printer's STL usually is) given plainly is read as
// metres: a 0.6 m dome becomes 600 m across, which 3 mm of PA12 cannot hold up. The one line says
// so and how to read it; the same file in millimetres through a scene is the dome it is.
TEST(CliRobustness, APlainMeshInMillimetresIsSaidToBeReadAsMetres) {
  const fs::path dir = test::temp_dir("robust_mm");
  const SurfaceMesh dome = test::spherical_cap(6, 24);
  write_obj(dir / "dome_mm.obj", dome.vertices() * 1000.0, dome.faces());
  for (const std::string& command : {std::string("check"), "simulate --out " + (dir / "out").string()})
    expect_one_line_error(cutwork(command + " " + (dir / "dome_mm.obj").string()),
                          {"the structure can carry", "(it is 600 m across: coordinates are read as metres",
                           "\"unit\": \"mm\""});
  EXPECT_FALSE(fs::exists(dir / "out"));
  std::ofstream(dir / "dome.json") << nlohmann::json{
      {"mesh", {{"file", "dome_mm.obj"}, {"unit", "mm"}}},
      {"supports", {{{"type", "pinned"}, {"select", {{"entity", "vertices"}, {"z", {{"below", 1e-6}}}}}}}},
      {"loads", {{{"type", "self_weight"}}}}};
  const auto ok = cutwork("check " + (dir / "dome.json").string());
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE(ok.out.find("carries the whole load"), std::string::npos) << ok.out;
  // A run that fails for another reason says nothing of units.
  const auto other = cutwork("check " + (dir / "dome.json").string() + " --max-faces 3");
  EXPECT_EQ(other.err.find("metres"), std::string::npos) << other.err;
  fs::remove_all(dir);
}

TEST(CliRobustness, LimitsAreSettings) {
  // The limits name their setting, and raising it lets the request through to the next check.
  expect_one_line_error(cutwork("check plate --max-faces 1000"), {"max_faces = 1000"});
  expect_one_line_error(cutwork("check " + (test::data_dir() / "meshes" / "tetrahedron.obj").string() + " --max-faces 3"),
                        {"tetrahedron.obj", "has 4 faces, more than the limit of 3", "--max-faces"});
  expect_one_line_error(cutwork("check plate --max-stencils 10"), {"about 300 stencils", "limit of 10"});
  const fs::path out = test::temp_dir("robust_limits") / "out";
  expect_one_line_error(cutwork("design " + mutant("huge_scale.json").string() + " --max-stencils 10 --out " + out.string()),
                        {"/pattern/scale", "limit of 10"});
  EXPECT_FALSE(fs::exists(out));
  fs::remove_all(out.parent_path());
  const auto r = cutwork("check plate");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("about 300 stencils (estimated)"), std::string::npos) << r.out;
}

TEST(CliRobustness, RealValuedOptionsRefuseWhatIsNotAFiniteNumber) {
  // CLI11's range checks let NaN through (every comparison with it is false): `verify
  // --edge-length nan` ran, `--max-factor-gb nan` switched the limit off, `--tool-radius nan` cut
  // as drawn. Each real-valued option now refuses nan, inf and words in one line, before any work.
  const fs::path dir = test::temp_dir("robust_finite");
  const std::string out = " --out " + (dir / "out").string();
  const std::string design = "design plate --phases none" + out;
  for (const char* bad : {"nan", "inf", "-inf", "NaN", "one"}) {
    SCOPED_TRACE(bad);
    const std::string v = std::string(" ") + bad;
    expect_one_line_error(cutwork(design + " --checkpoint-every" + v), {"--checkpoint-every", bad});
    expect_one_line_error(cutwork(design + " --max-factor-gb" + v), {"--max-factor-gb", bad});
    for (const char* option : {"--edge-length", "--tolerance", "--elements-across", "--tool-radius"})
      expect_one_line_error(cutwork("verify " + (dir / "no-design").string() + " " + option + v), {option, bad});
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

TEST(CliRobustness, ProgressLinesOnStderrWithoutATerminal) {
  const fs::path out = test::temp_dir("robust_progress");
  // Every update as a line (the interval is 5 s by default; short runs print none).
  const auto r = test::run_shell("CUTWORK_PROGRESS_SECONDS=0 timeout -s KILL 60 " + test::cutwork_binary().string() +
                                 " design plate --iterations 3 --device cpu --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find("cutwork: pattern   initialised:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("cutwork: structure round"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos) << "plain lines, no terminal control";
  const auto quiet = cutwork("design plate --iterations 3 --device cpu --quiet --out " + out.string());
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  const auto normal = cutwork("design plate --iterations 3 --device cpu --out " + out.string());
  EXPECT_EQ(normal.err.find("cutwork: pattern"), std::string::npos) << "a run shorter than 5 s prints none";
  fs::remove_all(out);
}

TEST(CliRobustness, TheFactorSizeIsEstimatedBeforeFactorising) {
  const auto r = cutwork("check plate");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("stiffness factor"), std::string::npos) << r.out;
  const fs::path out = test::temp_dir("robust_factor") / "out";
  for (const std::string& cmd : {std::string("check plate"), "simulate plate --out " + out.string(),
                                "design plate --iterations 2 --device cpu --out " + out.string()}) {
    SCOPED_TRACE(cmd);
    expect_one_line_error(cutwork(cmd + " --max-factor-gb 1e-6"),
                          {"stiffness factor", "more than the limit of 1e-06 GB", "--max-factor-gb"});
    EXPECT_FALSE(fs::exists(out));
  }
  fs::remove_all(out.parent_path());
}

}  // namespace
}  // namespace cutwork

// `cutwork check`: the uncut shell's equilibrium is part of the check, so a load the shell cannot
// carry is found before any design work, with the message design and simulate give.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>

#include <fmt/format.h>

#include "host/scene/scene.h"
#include "tests/support/test_support.h"

namespace cutwork {
namespace {
namespace fs = std::filesystem;
using test::run_cutwork;

/// A 1.7 m canopy: the paraboloid z = 0.5((x/L + 1/2)² + (y/L)²) over a square of side L on an
/// n×n grid, lowest at the middle of one side.
void write_canopy(const fs::path& file, int n = 24) {
  std::ofstream out(file);
  const double L = 1.7;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -L / 2 + L * i / n, y = -L / 2 + L * j / n;
      out << fmt::format("v {:.9g} {:.9g} {:.9g}\n", x, y, 0.5 * ((x / L + 0.5) * (x / L + 0.5) + (y / L) * (y / L)));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i + 1;
      out << fmt::format("f {} {} {}\nf {} {} {}\n", v, v + 1, v + n + 2, v, v + n + 2, v + n + 1);
    }
}

/// The canopy in PA12 of `thickness`, pinned where z < 0.01 (a few vertices at the middle of
/// one side), under self-weight and 5 N on a 0.1 m patch at the far side.
fs::path canopy_scene(const fs::path& dir, double thickness) {
  write_canopy(dir / "canopy.obj");
  const fs::path scene = dir / fmt::format("canopy_{}.json", thickness);
  std::ofstream(scene) << fmt::format(R"({{
  "mesh": {{"file": "canopy.obj"}},
  "material": {{"youngs_modulus": 1.7e9, "poisson_ratio": 0.4, "thickness": {}, "density": 1010}},
  "supports": [{{"type": "pinned", "select": {{"entity": "vertices", "z": {{"below": 0.01}}}}}}],
  "loads": [{{"type": "self_weight"}},
            {{"type": "point", "force": [0, 0, -5], "select": {{"near": {{"point": [0.85, 0, 0.5], "radius": 0.1}}}}}}],
  "stencils": [{{"name": "circle", "kind": "circle"}}]
}})",
                                                    thickness);
  return scene;
}

int count_lines(const std::string& s) { return int(std::count(s.begin(), s.end(), '\n')); }

TEST(CheckCommand, EveryBuiltinSceneCarriesItsLoadUncut) {
  for (const auto& b : builtin_scenes()) {
    SCOPED_TRACE(b.name);
    const auto r = run_cutwork("check " + b.name);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("uncut equilibrium: carries the whole load; compliance "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\nok\n"), std::string::npos) << r.out;
  }
}

TEST(CheckCommand, ALoadTheUncutShellCannotCarryIsExitTwoWithTheCarriedFraction) {
  const fs::path dir = test::temp_dir("check_canopy");
  // 3 mm carries the load (the control: the same scene, only thinner, fails).
  const auto thick = run_cutwork("check " + canopy_scene(dir, 0.006).string());
  ASSERT_EQ(thick.exit_code, 0) << thick.err;
  EXPECT_NE(thick.out.find("carries the whole load"), std::string::npos) << thick.out;

  const fs::path scene = canopy_scene(dir, 0.002);
  const auto r = run_cutwork("check " + scene.string());
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_EQ(count_lines(r.err), 1) << r.err;
  EXPECT_EQ(r.out, "") << "nothing printed before the error";
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.err, m, std::regex(R"(can carry only ([0-9.]+)% of the load)"))) << r.err;
  const double fraction = std::stod(m[1]);
  EXPECT_GT(fraction, 0.0);
  EXPECT_LT(fraction, 100.0);
  // The same line as the pipeline's own uncut equilibrium (simulate solves it first, as design does).
  const auto sim = run_cutwork("simulate " + scene.string() + " --no-render --out " + (dir / "sim").string());
  EXPECT_EQ(sim.exit_code, 2) << sim.err;
  EXPECT_EQ(sim.err, r.err);
  EXPECT_FALSE(fs::exists(dir / "sim" / "report.json"));
  // --no-equilibrium validates only.
  const auto only = run_cutwork("check --no-equilibrium " + scene.string());
  EXPECT_EQ(only.exit_code, 0) << only.err;
  EXPECT_NE(only.out.find("uncut equilibrium: not solved (--no-equilibrium)"), std::string::npos) << only.out;
}

TEST(CheckCommand, ABuiltinNameIsNotShadowedByAFolderOfThatName) {
  // `cutwork design plate --out plate` makes the folder `plate` before it reads the scene name.
  const fs::path dir = test::temp_dir("shadowed_builtin");
  fs::create_directories(dir / "plate");
  const auto r = test::run_shell("cd " + dir.string() + " && " + test::cutwork_binary().string() +
                                 " design plate --phases none --out plate");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "plate" / "report.json"));
  const auto c = test::run_shell("cd " + dir.string() + " && " + test::cutwork_binary().string() +
                                 " check plate --no-equilibrium");
  EXPECT_EQ(c.exit_code, 0) << c.err;
  // A folder that is no built-in name is still an error naming it.
  fs::create_directories(dir / "somewhere");
  const auto bad = run_cutwork("check " + (dir / "somewhere").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("is a directory"), std::string::npos) << bad.err;
}

TEST(CheckCommand, DesignAndSimulateReportTheirDiscretisationError) {
  const fs::path dir = test::temp_dir("discretisation_report");
  const auto d = run_cutwork("design sheet --iterations 2 --no-render --quiet --out " + (dir / "d").string());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const auto report = test::read_json(dir / "d" / "report.json");
  ASSERT_TRUE(report.contains("discretisation")) << report.dump();
  for (const char* which : {"uncut", "final"}) {
    const auto& e = report["discretisation"][which];
    // h, h/2, h/4, and h/8 where those have not settled and their cautious estimate exceeds 2%.
    EXPECT_GE(e["levels"].size(), 3u) << e.dump();
    EXPECT_LE(e["levels"].size(), 4u) << e.dump();
    EXPECT_NEAR(e["levels"][1]["edge_length"].get<double>(), 0.025, 1e-12);
    EXPECT_TRUE(e["estimated_error"].is_number()) << e.dump();
    EXPECT_TRUE(e["converged"].is_boolean());
  }
  // The final design's W_peak is read on every level with its factors: the sheet's one hole, which
  // the triangles resolve (no factor), has its rim averaged over the rim faces, which a finer level
  // reads closer to the rim's peak (0.0526, 0.0585, 0.0629 J/m²; the conforming peak 0.0634), and
  // the run says so in a note. The uncut shell's levels read no W_peak.
  const auto& final_levels = report["discretisation"]["final"]["levels"];
  for (size_t k = 1; k < final_levels.size(); ++k)
    EXPECT_GT(final_levels[k]["W_peak"].get<double>(), final_levels[k - 1]["W_peak"].get<double>()) << k;
  EXPECT_NEAR(final_levels[0]["W_peak"].get<double>(), report["structure"]["W_peak_max_final"].get<double>(),
              1e-12 * final_levels[0]["W_peak"].get<double>());
  EXPECT_GT(report["discretisation"]["final"]["W_peak_change"].get<double>(), 0.05);
  EXPECT_TRUE(report["discretisation"]["uncut"]["levels"][1]["W_peak"].is_null());
  bool noted = false;
  for (const auto& note : report["notes"])
    noted = noted || note.get<std::string>().find("the ligament peak W_peak is not converged on the simulation mesh") !=
                         std::string::npos;
  EXPECT_TRUE(noted) << report["notes"].dump();
  const auto s = run_cutwork("simulate plate --no-render --quiet --out " + (dir / "s").string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto sim = test::read_json(dir / "s" / "report.json");
  ASSERT_TRUE(sim.contains("discretisation"));
  EXPECT_EQ(sim["discretisation"]["method"], "regenerated");
  // The uncut plate converges (6.350, 6.324, 6.309 mJ at 0.01, 0.005, 0.0025 m).
  EXPECT_TRUE(sim["discretisation"]["converged"].get<bool>()) << sim["discretisation"].dump();
  // Its clamped short side is the same 0.1 m of line on every level.
  EXPECT_TRUE(sim["discretisation"]["supports_consistent"].get<bool>());
  EXPECT_EQ(sim["discretisation"]["support_change"].get<double>(), 0.0);
  for (const auto& level : sim["discretisation"]["levels"]) {
    EXPECT_NEAR(level["supports"]["clamped"]["length"].get<double>(), 0.1, 1e-12) << level.dump();
    EXPECT_EQ(level["supports"]["clamped"]["area"].get<double>(), 0.0);
  }
  const auto off = run_cutwork("simulate plate --no-render --quiet --no-discretisation-estimate --out " +
                               (dir / "off").string());
  ASSERT_EQ(off.exit_code, 0) << off.err;
  EXPECT_FALSE(test::read_json(dir / "off" / "report.json").contains("discretisation"));
}

TEST(CheckCommand, TheDefaultPlatesDesignIsConvergedOnItsOwnMaterial) {
  // The plate's default design (270 stencils about as large as its 10 mm triangles, homogenised
  // and cell-filtered): its material held on the refinements changes the compliance by 0.2% and
  // 0.1% (8.392, 8.411, 8.401 mJ), converged. With the stencils' fill ratios computed again on each
  // refined mesh the levels sat in the filter's transition to resolved holes (8.392, 8.417,
  // 8.221 mJ) and read 4.5%, not converged, where verify measured the design within 1.5% of the cut
  // plate. simulate --stencils of the same design holds the same material and reads the same levels.
  const fs::path dir = test::temp_dir("discretisation_plate");
  const auto d = run_cutwork("design plate --device cpu --no-render --quiet --out " + (dir / "d").string());
  ASSERT_EQ(d.exit_code, 0) << d.err;
  const auto final_design = test::read_json(dir / "d" / "report.json")["discretisation"]["final"];
  EXPECT_TRUE(final_design["converged"].get<bool>()) << final_design.dump();
  EXPECT_LT(final_design["estimated_error"].get<double>(), 0.01) << final_design.dump();
  const auto s = run_cutwork("simulate plate --device cpu --no-render --quiet --stencils " +
                             (dir / "d" / "stencils.json").string() + " --out " + (dir / "s").string());
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const auto simulated = test::read_json(dir / "s" / "report.json")["discretisation"];
  ASSERT_EQ(simulated["levels"].size(), final_design["levels"].size()) << simulated.dump();
  for (size_t k = 0; k < simulated["levels"].size(); ++k)
  {
    EXPECT_NEAR(simulated["levels"][k]["compliance"].get<double>(), final_design["levels"][k]["compliance"].get<double>(),
                1e-6 * final_design["levels"][k]["compliance"].get<double>())
        << k;
    // W_peak read with the same carried factors on both (2.901, 2.706, 2.830 J/m²).
    EXPECT_NEAR(simulated["levels"][k]["W_peak"].get<double>(), final_design["levels"][k]["W_peak"].get<double>(),
                1e-6 * final_design["levels"][k]["W_peak"].get<double>())
        << k;
  }
  EXPECT_EQ(simulated["converged"], final_design["converged"]);
}

}  // namespace
}  // namespace cutwork

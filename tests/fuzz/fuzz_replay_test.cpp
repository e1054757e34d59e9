// Every fuzz target over its seed corpus (tests/fuzz/corpus/<target>) and over the inputs that
// once crashed it (tests/data/fuzz-regressions/<target>): each must return normally. This is the
// regression half of fuzzing and runs with any compiler; the search half is the libFuzzer build.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <vector>

#include "tests/fuzz/fuzz_support.h"
#include "tests/support/test_support.h"

namespace {
namespace fs = std::filesystem;
using Target = int (*)(const std::uint8_t*, std::size_t);

/// Runs `target` over every file of the target's corpus and regression folders; returns how many.
int replay(const std::string& name, Target target) {
  int inputs = 0;
  for (const fs::path& dir : {fs::path(CUTWORK_FUZZ_CORPUS_DIR) / name,
                              cutwork::test::data_dir() / "fuzz-regressions" / name}) {
    if (!fs::is_directory(dir)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file()) files.push_back(e.path());
    std::sort(files.begin(), files.end());
    for (const auto& f : files) {
      SCOPED_TRACE(f.string());
      std::ifstream in(f, std::ios::binary);
      std::stringstream ss;
      ss << in.rdbuf();
      const std::string data = ss.str();
      EXPECT_EQ(target(reinterpret_cast<const std::uint8_t*>(data.data()), data.size()), 0);
      ++inputs;
    }
  }
  return inputs;
}

TEST(FuzzReplay, Scene) { EXPECT_GE(replay("scene", fuzz_scene), 8); }
TEST(FuzzReplay, StencilsJson) { EXPECT_GE(replay("stencils_json", fuzz_stencils_json), 1); }
TEST(FuzzReplay, MeshObj) { EXPECT_GE(replay("mesh_obj", fuzz_mesh_obj), 1); }
TEST(FuzzReplay, MeshPly) { EXPECT_GE(replay("mesh_ply", fuzz_mesh_ply), 1); }
TEST(FuzzReplay, MeshOff) { EXPECT_GE(replay("mesh_off", fuzz_mesh_off), 1); }
TEST(FuzzReplay, MeshStl) { EXPECT_GE(replay("mesh_stl", fuzz_mesh_stl), 1); }

}  // namespace

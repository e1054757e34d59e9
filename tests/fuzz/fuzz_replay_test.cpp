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

TEST(FuzzHeaderCounts, RewriteTheCountTheSelectorPicks) {
  using cutwork::fuzz::mesh_fuzz_input;
  using cutwork::fuzz::mutate_header_counts;
  const std::string tag(cutwork::fuzz::kHeaderMutationTag);
  // OFF: the counts after the magic (and an nOFF's dimension), comments skipped.
  const std::string off = "OFF # c\n# more\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  EXPECT_EQ(mutate_header_counts(".off", off, 0x1A),
            "OFF # c\n# more\n3 9223372036854775807 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(mutate_header_counts(".off", off, 0x02), "OFF # c\n# more\n2 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(mutate_header_counts(".off", off, 0x3E), mutate_header_counts(".off", off, 0x0E));  // modulo 3
  EXPECT_EQ(mutate_header_counts(".off", "nOFF 3 4 2\n", 0x1D), "nOFF 3 4 18446744073709551616\n");
  EXPECT_EQ(mutate_header_counts(".off", "4 2\n", 0x15), "4 4294967298\n");  // headerless
  // PLY: the element lines' counts, in order; nothing after end_header.
  const std::string ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nelement face 1\n"
                          "property list uchar int vertex_indices\nend_header\nelement x 5\n";
  EXPECT_EQ(mutate_header_counts(".ply", ply, 0x0C).substr(0, 57),
            "ply\nformat ascii 1.0\nelement vertex 18446744073709551615\n");
  EXPECT_NE(mutate_header_counts(".ply", ply, 0x1B).find("element face 9223372036854775808\n"), std::string::npos);
  EXPECT_NE(mutate_header_counts(".ply", ply, 0x2B).find("element vertex 9223372036854775808\n"), std::string::npos);
  EXPECT_NE(mutate_header_counts(".ply", ply, 0x1B).find("end_header\nelement x 5\n"), std::string::npos);
  // STL: the binary facet count, little endian; too short a file is left alone.
  std::string stl(84 + 50, '\0');
  stl[80] = 1;
  const std::string mutated = mutate_header_counts(".stl", stl, 0x08);
  EXPECT_EQ(mutated.substr(80, 4), std::string(4, '\xFF'));
  EXPECT_EQ(mutated.substr(84), stl.substr(84));
  EXPECT_EQ(mutate_header_counts(".stl", "solid x\nendsolid x\n", 0x08), "solid x\nendsolid x\n");
  // Only tagged inputs are mutated, and only for OFF, PLY and STL.
  EXPECT_EQ(mesh_fuzz_input(".off", off), off);
  EXPECT_EQ(mesh_fuzz_input(".off", tag + "\x1A" + off), mutate_header_counts(".off", off, 0x1A));
  EXPECT_EQ(mesh_fuzz_input(".obj", tag + "\x1A" + off), tag + "\x1A" + off);
}

}  // namespace

// The rasteriser's Vulkan twin (host/render/rasterizer_vk.h, raster.comp) against its CPU twin
// on the same seeded scenes, through the interface pictures.cpp uses (render::Rasterizer), and
// the pictures composed from it against the stored reference. Validation layer on, zero
// messages required (VulkanTest); without a Vulkan device the tests skip (fail under
// CUTWORK_REQUIRE_VULKAN=1).
//
// Parity contract. Both twins run the same arithmetic in double (rasterizer.h), so on an IEEE
// double device the pixels are the same: on lavapipe the test demands bit-identical images.
// On other devices Vulkan allows double division and sqrt a few ULP of error, so:
//  - per pixel, a channel may differ by kChannelTolerance = 1 level (a shaded colour rounded the
//    other way by the sqrt in |n̂·l|);
//  - beyond that, at most kEdgeFraction = 0.5% of the pixels may differ: samples whose centre
//    lies on a triangle edge within round-off can fall to the neighbouring triangle (the
//    barycentric division), and two triangles at the same depth within a float ULP can swap.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/render/pictures.h"
#include "host/render/rasterizer.h"
#include "host/render/rasterizer_vk.h"
#include "host/surfaces/generators.h"
#include "host/vulkan/backend.h"
#include "host/vulkan/context.h"
#include "tests/host/render/render_fixtures.h"
#include "tests/host/vulkan/vk_test_support.h"

namespace cutwork::test {
namespace {

using render::Field;
using render::PictureOptions;
using render::Rasterizer;
using render::View;

constexpr int kChannelTolerance = 1;
constexpr double kEdgeFraction = 0.005;

std::vector<Rgb> random_colours(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Rgb> c(n);
  for (Rgb& x : c) x = {u(rng), u(rng), u(rng)};
  return c;
}

/// `n` random triangles in [−1, 1]³ (edges up to ~0.6): they overlap and interpenetrate.
struct TriangleSoup {
  RowMatX3d V;
  RowMatX3i F;
  TriangleSoup(int n, unsigned seed) : V(3 * n, 3), F(n, 3) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> centre(-0.8, 0.8), offset(-0.3, 0.3);
    for (int t = 0; t < n; ++t) {
      const Vec3 c(centre(rng), centre(rng), centre(rng));
      for (int k = 0; k < 3; ++k) {
        V.row(3 * t + k) = (c + Vec3(offset(rng), offset(rng), offset(rng))).transpose();
        F(t, k) = 3 * t + k;
      }
    }
  }
};

ViewSetup framing(const RowMatX3d& V, View view) {
  ViewSetup s;
  s.view = view;
  for (Eigen::Index v = 0; v < V.rows(); ++v) s.frame.extend(V.row(v).transpose());
  return s;
}

class RasterizerVkTest : public VulkanTest {
 protected:
  Rasterizer device_twin() { return Rasterizer::for_backend(vulkan_backend(shared_ctx())); }

  /// Renders with both twins and holds them to the parity contract; returns the device's image.
  Image expect_parity(const Rasterizer& vk, const RowMatX3d& V, const RowMatX3i& F, const std::vector<Rgb>& colours,
                      const ViewSetup& setup, int width, int height) {
    const Image cpu = render::rasterize(V, F, colours, setup, width, height);
    const Image gpu = vk.rasterize(V, F, colours, setup, width, height);
    const ImageDiff d = compare(cpu, gpu, kChannelTolerance);
    if (is_lavapipe(ctx())) {
      EXPECT_EQ(d.differing, 0u) << "an IEEE double device gives the CPU twin's pixels; worst " << d.worst;
    }
    EXPECT_LE(double(d.beyond), kEdgeFraction * double(d.pixels)) << "worst channel difference " << d.worst;
    EXPECT_EQ(cpu.width, gpu.width);
    EXPECT_EQ(cpu.height, gpu.height);
    return gpu;
  }
};

TEST_F(RasterizerVkTest, MatchesTheCpuTwinOnTheBowlInEveryViewAndSize) {
  const Rasterizer vk = device_twin();
  ASSERT_TRUE(vk.on_device());
  EXPECT_EQ(vk.kind_name(), "vulkan");
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.02);
  const std::vector<Rgb> colours = random_colours(size_t(bowl.num_faces()), 14);
  for (View view : {View::Iso, View::Front, View::Top, View::Side})
    for (auto [w, h] : {std::pair{160, 120}, std::pair{97, 61}}) {
      SCOPED_TRACE(std::string(render::to_string(view)) + " " + std::to_string(w) + "x" + std::to_string(h));
      const Image image = expect_parity(vk, bowl.vertices(), bowl.faces(), colours, framing(bowl.vertices(), view), w, h);
      EXPECT_GT(stats(image).non_white, 0.05) << "the bowl is drawn";
    }
}

TEST_F(RasterizerVkTest, MatchesTheCpuTwinWhereTrianglesInterpenetrate) {
  const Rasterizer vk = device_twin();
  for (unsigned seed : {3u, 4u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const TriangleSoup soup(400, seed);
    const std::vector<Rgb> colours = random_colours(400, seed + 100);
    for (View view : {View::Iso, View::Top}) {
      ViewSetup setup = framing(soup.V, view);
      setup.background = {0.2, 0.3, 0.4};
      const Image image = expect_parity(vk, soup.V, soup.F, colours, setup, 180, 140);
      EXPECT_GT(stats(image).mean[0], 10.0);
    }
  }
}

// The same surface twice, in two colours: every sample is a depth tie, and both twins give it to
// the lower face index, so the picture is the first copy's alone.
TEST_F(RasterizerVkTest, DepthTiesGoToTheLowerFaceIndex) {
  const Rasterizer vk = device_twin();
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.03);
  const Eigen::Index nf = bowl.num_faces();
  RowMatX3i twice(2 * nf, 3);
  twice << bowl.faces(), bowl.faces();
  std::vector<Rgb> colours(size_t(2 * nf), Rgb{0.9, 0.1, 0.1});
  std::fill(colours.begin() + nf, colours.end(), Rgb{0.1, 0.1, 0.9});
  const ViewSetup setup = framing(bowl.vertices(), View::Iso);
  const Image both = expect_parity(vk, bowl.vertices(), twice, colours, setup, 120, 90);
  const std::vector<Rgb> first(colours.begin(), colours.begin() + nf);
  const Image alone = render::rasterize(bowl.vertices(), bowl.faces(), first, setup, 120, 90);
  EXPECT_EQ(both.pixels, alone.pixels);
}

TEST_F(RasterizerVkTest, LargeTrianglesEmptyMeshesAndRepeatedCallsReuseTheBuffers) {
  const Rasterizer vk = device_twin();
  // Two triangles filling the frame (one invocation visits ~80k samples) and one off-screen.
  RowMatX3d V(7, 3);
  V << -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 40, 40, 0, 41, 40, 0, 40, 41, 0;
  RowMatX3i F(3, 3);
  F << 0, 1, 2, 0, 2, 3, 4, 5, 6;
  ViewSetup setup;
  setup.view = View::Top;
  setup.frame = Eigen::AlignedBox3d(Vec3(-1, -1, 0), Vec3(1, 1, 0));
  const std::vector<Rgb> colours = {{0.5, 0.6, 0.7}, {0.7, 0.6, 0.5}, {1, 0, 0}};
  expect_parity(vk, V, F, colours, setup, 150, 130);
  // No faces: the background everywhere.
  setup.background = {0.25, 0.5, 0.75};
  const Image empty = vk.rasterize(RowMatX3d(0, 3), RowMatX3i(0, 3), {}, setup, 33, 17);
  ASSERT_EQ(empty.pixels.size(), size_t(33 * 17));
  for (uint32_t p : empty.pixels) ASSERT_EQ(p, render::pack(setup.background));
  // Bad input is refused before the device sees it, as the CPU twin refuses it.
  RowMatX3i bad(1, 3);
  bad << 0, 1, 7;
  EXPECT_THROW(vk.rasterize(V, bad, {{1, 1, 1}}, setup, 10, 10), InputError);
  EXPECT_THROW(render::rasterize(V, bad, {{1, 1, 1}}, setup, 10, 10), InputError);
  EXPECT_THROW(vk.rasterize(V, F, colours, setup, 0, 10), InputError);
}

TEST_F(RasterizerVkTest, ASecondPanelOfTheSameMeshUploadsOnlyTheView) {
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.02);
  const std::vector<Rgb> colours = random_colours(size_t(bowl.num_faces()), 5);
  render::RasterizerVk vk(shared_ctx());
  vk.rasterize(bowl.vertices(), bowl.faces(), colours, framing(bowl.vertices(), View::Iso), 64, 48);
  const size_t first = vk.last_report().upload_bytes;
  EXPECT_GE(first, size_t(bowl.vertices().size()) * sizeof(double));
  vk.rasterize(bowl.vertices(), bowl.faces(), colours, framing(bowl.vertices(), View::Top), 64, 48);
  EXPECT_LE(vk.last_report().upload_bytes, sizeof(render::RasterViewVk)) << "the mesh and colours stay on the device";
  ASSERT_EQ(vk.last_report().dispatches.size(), 4u) << "clear, depth, winner, resolve";
}

// The discrete-GPU memory path (device-local buffers, staging copies) on any device.
class RasterizerVkStagingTest : public RasterizerVkTest {
 protected:
  vulkan::ContextOptions options() const override {
    vulkan::ContextOptions o = validated_options();
    o.force_staging = true;
    o.max_workgroups_per_dispatch = 7;  // chunked launches
    return o;
  }
};

TEST_F(RasterizerVkStagingTest, MatchesTheCpuTwinThroughStagingAndChunkedLaunches) {
  const Rasterizer vk = device_twin();
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.03);
  const std::vector<Rgb> colours = random_colours(size_t(bowl.num_faces()), 21);
  expect_parity(vk, bowl.vertices(), bowl.faces(), colours, framing(bowl.vertices(), View::Iso), 90, 70);
}

// The pictures composed from the device's panels: the requested size, not blank, different per
// field, the CPU twin's pictures within the parity contract, and the stored reference within the
// CPU path's tolerance.
TEST_F(RasterizerVkTest, PicturesFromTheDeviceMatchTheCpuPicturesAndTheReference) {
  const BowlFields bowl;
  PictureOptions cpu;
  cpu.width = 240;
  cpu.height = 150;
  PictureOptions gpu = cpu;
  gpu.rasterizer = device_twin();
  std::vector<Stats> per_field;
  for (Field f : {Field::EnergyDensity, Field::FillRatio, Field::Design}) {
    SCOPED_TRACE(std::string(render::to_string(f)));
    const Image a = render::draw_picture(bowl.fields(), f, cpu), b = render::draw_picture(bowl.fields(), f, gpu);
    EXPECT_EQ(b.width, 240);
    EXPECT_EQ(b.height, 150);
    const ImageDiff d = compare(a, b, kChannelTolerance);
    if (is_lavapipe(ctx())) {
      EXPECT_EQ(d.differing, 0u);
    }
    EXPECT_LE(double(d.beyond), kEdgeFraction * double(d.pixels));
    per_field.push_back(stats(b));
    EXPECT_GT(per_field.back().non_white, 0.05);
  }
  EXPECT_NE(per_field[0].mean[0], per_field[1].mean[0]);
  EXPECT_NE(per_field[1].mean[2], per_field[2].mean[2]);
  const Image panel = gpu.rasterizer.rasterize(bowl.mesh.vertices(), bowl.mesh.faces(), bowl.energy_colours(),
                                               bowl.iso_setup(), 200, 150);
  expect_matches_reference(panel, "bowl_W_iso.png");
}

// `cutwork simulate --device vulkan` draws its pictures on the device and says so in report.json;
// `cutwork render DIR --device vulkan` says so on stderr. The validation layer watches both runs.
TEST_F(RasterizerVkTest, TheCommandsRenderOnTheDeviceTheyWereGiven) {
  const std::filesystem::path dir = temp_dir("render_vk");
  const std::string env = "CUTWORK_VK_VALIDATION=1 ";
  const CommandResult sim = run_shell(env + cutwork_binary().string() + " simulate plate --device vulkan " +
                                      "--render-size 200x150 --out " + (dir / "s").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_EQ(sim.err.find("vulkan validation"), std::string::npos) << sim.err;
  const nlohmann::json report = read_json(dir / "s" / "report.json");
  EXPECT_EQ(report["device"]["kind"], "vulkan");
  EXPECT_EQ(report["device"]["render"], "vulkan");
  EXPECT_GT(stats(render::read_png(dir / "s" / "render_W.png")).non_white, 0.05);
  const CommandResult r = run_shell(env + cutwork_binary().string() + " render " + (dir / "s").string() +
                                    " --device vulkan --field W --size 200x150 --out " + (dir / "r").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("drawn on vulkan"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("vulkan validation"), std::string::npos) << r.err;
  // The same picture as the one simulate drew: the same twin on the same fields.
  const ImageDiff d = compare(render::read_png(dir / "s" / "render_W.png"), render::read_png(dir / "r" / "render_W.png"), 0);
  EXPECT_EQ(d.differing, 0u);
}

}  // namespace
}  // namespace cutwork::test

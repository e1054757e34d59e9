// The CPU rasteriser: coverage equals projected area, the nearer surface wins, views look where
// they say, and the number of threads changes nothing.
#include "host/render/rasterizer.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <limits>

#include "host/core/error.h"
#include "host/surfaces/generators.h"

namespace cutwork::render {
namespace {

int count_not(const Image& image, uint32_t colour) {
  int n = 0;
  for (uint32_t p : image.pixels) n += p != colour;
  return n;
}

TEST(Rasterizer, CoverageMatchesTheProjectedArea) {
  // A square covering the middle half of the frame box's extent, seen from the top.
  RowMatX3d V(4, 3);
  V << -0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0;
  RowMatX3i F(2, 3);
  F << 0, 1, 2, 0, 2, 3;
  ViewSetup setup;
  setup.view = View::Top;
  setup.frame = Eigen::AlignedBox3d(Vec3(-1, -1, 0), Vec3(1, 1, 0));
  setup.fill = 1.0;
  const Image image = rasterize(V, F, {{1, 0, 0}, {1, 0, 0}}, setup, 200, 200);
  // The frame (2 × 2) fills 200 px: the square is 100 × 100 px.
  EXPECT_NEAR(count_not(image, 0xFFFFFFFFu), 100 * 100, 2 * 100);
  // Lit from above at |n·l| < 1: red, darker than full.
  const uint32_t centre = image.at(100, 100);
  EXPECT_GT((centre >> 16) & 0xFF, 150u);
  EXPECT_EQ(centre & 0xFF, 0u);
}

TEST(Rasterizer, TheNearerSurfaceWinsAndViewsLookWhereTheySay) {
  // Two horizontal squares: red at z = 1 above blue at z = 0.
  RowMatX3d V(8, 3);
  V << -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, -0.5, -0.5, 1, 0.5, -0.5, 1, 0.5, 0.5, 1, -0.5, 0.5, 1;
  RowMatX3i F(4, 3);
  F << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7;
  const std::vector<Rgb> colours = {{0, 0, 1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}};
  ViewSetup setup;
  setup.frame = Eigen::AlignedBox3d(Vec3(-1, -1, 0), Vec3(1, 1, 1));
  setup.view = View::Top;
  const Image top = rasterize(V, F, colours, setup, 100, 100);
  EXPECT_GT((top.at(50, 50) >> 16) & 0xFF, 100u) << "red on top";
  EXPECT_EQ(top.at(50, 50) & 0xFF, 0u);
  EXPECT_GT(top.at(10, 50) & 0xFF, 100u) << "blue around it";
  // From the front both are edge-on: almost nothing is drawn.
  setup.view = View::Front;
  EXPECT_LT(count_not(rasterize(V, F, colours, setup, 100, 100), 0xFFFFFFFFu), 300);
  setup.view = View::Iso;
  EXPECT_GT(count_not(rasterize(V, F, colours, setup, 100, 100), 0xFFFFFFFFu), 2000);
}

TEST(Rasterizer, ThreadsChangeNothing) {
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.02);
  std::vector<Rgb> colours(size_t(bowl.num_faces()));
  for (size_t f = 0; f < colours.size(); ++f) colours[f] = {double(f % 7) / 7, 0.5, double(f % 3) / 3};
  ViewSetup setup;
  for (Eigen::Index v = 0; v < bowl.num_vertices(); ++v) setup.frame.extend(bowl.vertices().row(v).transpose());
  const Image many = rasterize(bowl.vertices(), bowl.faces(), colours, setup, 160, 120);
  Image one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = rasterize(bowl.vertices(), bowl.faces(), colours, setup, 160, 120);
  }
  EXPECT_EQ(one.pixels, many.pixels);
}

TEST(Rasterizer, BadInputsAreRejected) {
  RowMatX3d V = RowMatX3d::Zero(3, 3);
  RowMatX3i F(1, 3);
  F << 0, 1, 2;
  ViewSetup setup;
  EXPECT_THROW(rasterize(V, F, {}, setup, 10, 10), InputError);
  EXPECT_THROW(rasterize(V, F, {{1, 1, 1}}, setup, 0, 10), InputError);
  RowMatX3i out_of_range(1, 3);
  out_of_range << 0, 1, 3;
  EXPECT_THROW(rasterize(V, out_of_range, {{1, 1, 1}}, setup, 10, 10), InputError);
  RowMatX3d not_finite = V;
  not_finite(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(rasterize(not_finite, F, {{1, 1, 1}}, setup, 10, 10), InputError);
  EXPECT_THROW(parse_view("diagonal"), InputError);
  for (View v : {View::Iso, View::Front, View::Top, View::Side}) EXPECT_EQ(parse_view(to_string(v)), v);
}

// The interface pictures.cpp draws through: the CPU twin by default and for a CPU backend (the
// Vulkan twin's parity is tests/host/render/rasterizer_vk_test.cpp).
TEST(Rasterizer, TheDefaultAndTheCpuBackendDrawWithTheCpuTwin) {
  const SurfaceMesh bowl = generate_shape("bowl", {}, 0.03);
  const std::vector<Rgb> colours(size_t(bowl.num_faces()), Rgb{0.3, 0.6, 0.9});
  ViewSetup setup;
  for (Eigen::Index v = 0; v < bowl.num_vertices(); ++v) setup.frame.extend(bowl.vertices().row(v).transpose());
  const Rasterizer plain, cpu = Rasterizer::for_backend(cpu_backend());
  EXPECT_FALSE(cpu.on_device());
  EXPECT_EQ(cpu.kind_name(), "cpu");
  const Image direct = rasterize(bowl.vertices(), bowl.faces(), colours, setup, 80, 60);
  EXPECT_EQ(plain.rasterize(bowl.vertices(), bowl.faces(), colours, setup, 80, 60).pixels, direct.pixels);
  EXPECT_EQ(cpu.rasterize(bowl.vertices(), bowl.faces(), colours, setup, 80, 60).pixels, direct.pixels);
  ComputeBackend no_context;
  no_context.kind = ComputeBackend::Kind::Vulkan;
  EXPECT_THROW(Rasterizer::for_backend(no_context), DeviceError) << "a Vulkan backend needs its context";
}

}  // namespace
}  // namespace cutwork::render

// The pictures: requested size, not blank, different per field, the paper's colour convention,
// and one known configuration against a stored reference image (tests/data/render/).
#include "host/render/pictures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/surfaces/generators.h"
#include "tests/host/render/render_fixtures.h"
#include "tests/support/test_support.h"

namespace cutwork::render {
namespace {
namespace fs = std::filesystem;

using test::BowlFields;
using test::stats;
using test::Stats;

TEST(Pictures, EnergyColoursFollowThePapersConvention) {
  const double beta = 1000, top = 3000;
  const Rgb at = energy_colour(beta, beta, top), low = energy_colour(0, beta, top), high = energy_colour(top, beta, top);
  EXPECT_GT(at.g, at.r);
  EXPECT_GT(at.g, at.b) << "green around beta";
  EXPECT_GT(low.b, low.r);
  EXPECT_GT(low.b, low.g) << "blue below";
  EXPECT_GT(high.r, high.g);
  EXPECT_GT(high.r, high.b) << "red above";
  // Without a threshold green sits mid-scale.
  const Rgb mid = energy_colour(1500, std::nan(""), top);
  EXPECT_NEAR(mid.g, at.g, 1e-12);
  const Rgb solid = fill_colour(1.0), empty = fill_colour(0.0);
  EXPECT_GT(solid.r + solid.g + solid.b, 1.2 + (empty.r + empty.g + empty.b)) << "solid is bright, cut away is dark";
}

TEST(Pictures, HaveTheRequestedSizeAreNotBlankAndDifferPerField) {
  const BowlFields bowl;
  PictureOptions o;
  o.width = 200;
  o.height = 150;
  std::vector<Stats> per_field;
  for (Field f : {Field::EnergyDensity, Field::FillRatio, Field::Design}) {
    SCOPED_TRACE(std::string(to_string(f)));
    const Image image = draw_picture(bowl.fields(), f, o);
    EXPECT_EQ(image.width, 200);
    EXPECT_EQ(image.height, 150);
    per_field.push_back(stats(image));
    EXPECT_GT(per_field.back().non_white, 0.05);
    EXPECT_LT(per_field.back().non_white, 0.9);
  }
  auto distance = [](const Stats& a, const Stats& b) {
    return std::abs(a.mean[0] - b.mean[0]) + std::abs(a.mean[1] - b.mean[1]) + std::abs(a.mean[2] - b.mean[2]);
  };
  EXPECT_GT(distance(per_field[0], per_field[1]), 3.0);
  EXPECT_GT(distance(per_field[0], per_field[2]), 3.0);
  EXPECT_GT(distance(per_field[1], per_field[2]), 3.0);
}

TEST(Pictures, WritePicturesWritesPngsThatReadBack) {
  const BowlFields bowl;
  PictureOptions o;
  o.width = 200;
  o.height = 150;
  o.views = {View::Iso, View::Top};
  const fs::path dir = test::temp_dir("pictures");
  const auto written = write_pictures(dir, bowl.fields(), {Field::EnergyDensity, Field::FillRatio, Field::Design}, o);
  ASSERT_EQ(written.size(), 3u);
  EXPECT_EQ(written[0].filename(), "render_W.png");
  EXPECT_EQ(written[1].filename(), "render_alpha.png");
  EXPECT_EQ(written[2].filename(), "render_design.png");
  for (const auto& p : written) {
    const Image back = read_png(p);
    EXPECT_EQ(back.width, 200);
    EXPECT_EQ(back.height, 150);
  }
  EXPECT_EQ(read_png(written[0]).pixels, draw_picture(bowl.fields(), Field::EnergyDensity, o).pixels)
      << "PNG is lossless";
  EXPECT_THROW(read_png(dir / "missing.png"), InputError);
  o.width = 10;
  EXPECT_THROW(draw_picture(bowl.fields(), Field::FillRatio, o), InputError);
}

// The rasterised energy-density view of the bowl against tests/data/render/bowl_W_iso.png, to
// the tolerance stated at test::expect_matches_reference (rasterizer_vk_test.cpp holds the
// Vulkan twin's picture to the same reference and tolerance).
TEST(Pictures, KnownConfigurationMatchesTheStoredReference) {
  const BowlFields bowl;
  const Image image = rasterize(bowl.mesh.vertices(), bowl.mesh.faces(), bowl.energy_colours(), bowl.iso_setup(), 200, 150);
  test::expect_matches_reference(image, "bowl_W_iso.png");
}

}  // namespace
}  // namespace cutwork::render

// The pictures: requested size, not blank, different per field, the paper's colour convention,
// and one known configuration against a stored reference image (tests/data/render/).
#include "host/render/pictures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/surfaces/generators.h"
#include "tests/support/test_support.h"

namespace cutwork::render {
namespace {
namespace fs = std::filesystem;

struct BowlFields {
  SurfaceMesh mesh = generate_shape("bowl", {}, 0.02);
  Eigen::VectorXd W, alpha;
  BowlFields() {
    // A smooth energy density rising with height and a fill ratio varying around the bowl.
    const Eigen::Index nf = mesh.num_faces();
    W.resize(nf);
    alpha.resize(nf);
    for (Eigen::Index f = 0; f < nf; ++f) {
      const Vec3 c = (mesh.vertices().row(mesh.faces()(f, 0)) + mesh.vertices().row(mesh.faces()(f, 1)) +
                      mesh.vertices().row(mesh.faces()(f, 2)))
                         .transpose() /
                     3.0;
      W[f] = 100.0 * (1.0 + 20.0 * c.z());
      alpha[f] = 0.5 + 0.5 * std::sin(20.0 * c.x());
    }
  }
  DesignFields fields() const {
    DesignFields d;
    d.sim_vertices = &mesh.vertices();
    d.sim_faces = &mesh.faces();
    d.energy_density = W;
    d.fill_ratio = alpha;
    d.beta = 0.6 * W.maxCoeff();
    d.cut_vertices = &mesh.vertices();
    d.cut_faces = &mesh.faces();
    d.title = "bowl";
    return d;
  }
};

struct Stats {
  double non_white = 0;  ///< fraction of pixels that are not white
  double mean[3] = {0, 0, 0};
};

Stats stats(const Image& image) {
  Stats s;
  for (uint32_t p : image.pixels) {
    s.non_white += (p & 0xFFFFFF) != 0xFFFFFF;
    s.mean[0] += (p >> 16) & 0xFF;
    s.mean[1] += (p >> 8) & 0xFF;
    s.mean[2] += p & 0xFF;
  }
  const double n = double(image.pixels.size());
  s.non_white /= n;
  for (double& m : s.mean) m /= n;
  return s;
}

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

// The rasterised energy-density view of the bowl against tests/data/render/bowl_W_iso.png.
// The panel is cutwork's own rasteriser (no text, no fonts), so it is reproducible across
// machines up to floating-point rounding at triangle edges: at most 1% of the pixels may differ
// by more than 8 levels in some channel, and the mean difference must stay below 0.5 levels.
// CUTWORK_UPDATE_REFERENCE_IMAGES=1 rewrites the reference (then inspect it before committing).
TEST(Pictures, KnownConfigurationMatchesTheStoredReference) {
  const BowlFields bowl;
  std::vector<Rgb> colours(size_t(bowl.W.size()));
  const double beta = 0.6 * bowl.W.maxCoeff();
  for (size_t f = 0; f < colours.size(); ++f) colours[f] = energy_colour(bowl.W[Eigen::Index(f)], beta, bowl.W.maxCoeff());
  ViewSetup setup;
  for (Eigen::Index v = 0; v < bowl.mesh.num_vertices(); ++v) setup.frame.extend(bowl.mesh.vertices().row(v).transpose());
  const Image image = rasterize(bowl.mesh.vertices(), bowl.mesh.faces(), colours, setup, 200, 150);
  const fs::path reference = test::data_dir() / "render" / "bowl_W_iso.png";
  if (const char* update = std::getenv("CUTWORK_UPDATE_REFERENCE_IMAGES"); update && std::string(update) == "1")
    write_file_atomic(reference, encode_png(image));
  const Image ref = read_png(reference);
  ASSERT_EQ(ref.width, image.width);
  ASSERT_EQ(ref.height, image.height);
  int differing = 0;
  double total = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    int worst = 0;
    for (int shift : {0, 8, 16}) {
      const int d = std::abs(int((ref.pixels[i] >> shift) & 0xFF) - int((image.pixels[i] >> shift) & 0xFF));
      worst = std::max(worst, d);
      total += d;
    }
    differing += worst > 8;
  }
  EXPECT_LE(differing, int(0.01 * double(ref.pixels.size())));
  EXPECT_LT(total / (3.0 * double(ref.pixels.size())), 0.5);
  EXPECT_GT(stats(image).non_white, 0.1) << "the reference must show the bowl";
}

}  // namespace
}  // namespace cutwork::render

#pragma once
/// Shared by the picture tests of both rasteriser twins (pictures_test.cpp, rasterizer_vk_test.cpp):
/// the bowl with smooth fields, pixel statistics, image differences and the reference check.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "host/core/atomic_file.h"
#include "host/render/pictures.h"
#include "host/surfaces/generators.h"
#include "tests/support/test_support.h"

namespace cutwork::test {

using render::DesignFields;
using render::Image;
using render::Rgb;
using render::ViewSetup;

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
  /// The energy-density colours of the reference configuration (β = 0.6 W_max).
  std::vector<Rgb> energy_colours() const {
    std::vector<Rgb> colours(size_t(W.size()));
    const double beta = 0.6 * W.maxCoeff();
    for (size_t f = 0; f < colours.size(); ++f) colours[f] = render::energy_colour(W[Eigen::Index(f)], beta, W.maxCoeff());
    return colours;
  }
  /// The iso view framing the whole bowl.
  ViewSetup iso_setup() const {
    ViewSetup setup;
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) setup.frame.extend(mesh.vertices().row(v).transpose());
    return setup;
  }
};

struct Stats {
  double non_white = 0;  ///< fraction of pixels that are not white
  double mean[3] = {0, 0, 0};
};

inline Stats stats(const Image& image) {
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

/// How two images of the same size differ, channel by channel (levels 0–255).
struct ImageDiff {
  size_t pixels = 0;
  size_t differing = 0;        ///< pixels with some channel differing at all
  size_t beyond = 0;           ///< pixels with some channel differing by more than `tolerance`
  int worst = 0;               ///< largest channel difference
  double mean = 0;             ///< mean channel difference
};

inline ImageDiff compare(const Image& a, const Image& b, int tolerance) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  ImageDiff d;
  d.pixels = std::min(a.pixels.size(), b.pixels.size());
  double total = 0;
  for (size_t i = 0; i < d.pixels; ++i) {
    int worst = 0;
    for (int shift : {0, 8, 16}) {
      const int c = std::abs(int((a.pixels[i] >> shift) & 0xFF) - int((b.pixels[i] >> shift) & 0xFF));
      worst = std::max(worst, c);
      total += c;
    }
    d.differing += worst > 0;
    d.beyond += worst > tolerance;
    d.worst = std::max(d.worst, worst);
  }
  d.mean = d.pixels > 0 ? total / (3.0 * double(d.pixels)) : 0.0;
  return d;
}

/// The stored-reference check of tests/data/render/<name> (the same for both twins): the panel is
/// cutwork's own rasteriser (no text, no fonts), so it is reproducible across machines up to
/// floating-point rounding at triangle edges: at most 1% of the pixels may differ by more than
/// 8 levels in some channel, and the mean difference must stay below 0.5 levels.
/// CUTWORK_UPDATE_REFERENCE_IMAGES=1 rewrites the reference (then inspect it before committing).
inline void expect_matches_reference(const Image& image, const std::string& name) {
  const std::filesystem::path reference = data_dir() / "render" / name;
  if (const char* update = std::getenv("CUTWORK_UPDATE_REFERENCE_IMAGES"); update && std::string(update) == "1")
    write_file_atomic(reference, render::encode_png(image));
  const Image ref = render::read_png(reference);
  ASSERT_EQ(ref.width, image.width);
  ASSERT_EQ(ref.height, image.height);
  const ImageDiff d = compare(ref, image, 8);
  EXPECT_LE(d.beyond, size_t(0.01 * double(d.pixels)));
  EXPECT_LT(d.mean, 0.5);
  EXPECT_GT(stats(image).non_white, 0.1) << "the reference must show the bowl";
}

}  // namespace cutwork::test

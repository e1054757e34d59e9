// Parity of the clip kernel's Vulkan twin (kernels/clip/clip.comp via host/vulkan) with the TBB
// twin, to the tolerance stated in host/vulkan/clip_fill_vk.h: on real scenes (pavilion, bowl)
// and on hand-made polygon/triangle pairs that stress the clipping (combs, a "C", 2048-vertex
// polygons, shared edges and vertices, tiny and huge triangles), with early exits on and off,
// derivatives on and off, both memory paths and chunked launches. Validation layer on, zero
// messages required (VulkanTest).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "bench/clip_scenario.h"
#include "host/stencil/stencil_shape.h"  // kMaxStencilPolygonVertices
#include "host/vulkan/clip_fill_vk.h"
#include "host/vulkan/context.h"
#include "kernels/clip/clip.h"
#include "tests/host/vulkan/vk_test_support.h"
#include "tests/kernels/clip/clip_vk_parity.h"

namespace cutwork::test {
namespace {

using kernels::ClipInputs;
using kernels::ClipOptions;
using kernels::ClipResult;
using Poly = std::vector<double>;  // x0, y0, x1, y1, … CCW
using Tri = std::array<double, 6>;

std::vector<ClipResult> run_cpu(const ClipInputs& in, const ClipOptions& options) {
  std::vector<ClipResult> r(in.pairs.size());
  kernels::ClipWorkspace ws;
  kernels::clip_tbb(in, options, r, ws);
  return r;
}

std::vector<ClipResult> run_gpu(vulkan::ClipFillVk& vk, const ClipInputs& in,
                                const ClipOptions& options) {
  std::vector<ClipResult> r(in.pairs.size());
  vk.clip(in, options, r);
  return r;
}

// --- real scenes -------------------------------------------------------------------------------

class ClipVkTest : public VulkanTest {};

TEST_F(ClipVkTest, MatchesTbbTwinOnThePavilion) {
  const ClipScenario scene("pavilion", 0.05, 1500, 7);
  const ClipInputs in = scene.inputs();
  vulkan::ClipFillVk vk(shared_ctx());
  const ParityStats st = expect_clip_parity(run_cpu(in, {}), run_gpu(vk, in, {}), in);
  EXPECT_GT(st.partial, 2000u) << "the scene should exercise the clipping path";
}

TEST_F(ClipVkTest, MatchesTbbTwinOnTheBowlWithAndWithoutDerivativesAndExits) {
  const ClipScenario scene("bowl", 0.03, 600, 11);
  const ClipInputs in = scene.inputs();
  vulkan::ClipFillVk vk(shared_ctx());
  for (int derivatives : {1, 0}) {
    for (int exits : {1, 0}) {
      SCOPED_TRACE("derivatives " + std::to_string(derivatives) + ", early exits " +
                   std::to_string(exits));
      const ClipOptions options{derivatives, exits};
      const std::vector<ClipResult> gpu = run_gpu(vk, in, options);
      expect_clip_parity(run_cpu(in, options), gpu, in);
      if (derivatives == 0) {
        for (const ClipResult& r : gpu)
          for (double d : r.d_fraction) ASSERT_EQ(d, 0.0);
      }
    }
  }
}

// --- hand-made polygon / triangle pairs ----------------------------------------------------------

// Stencils at the origin of the plane z = 0 with axes x, y and scale 1: the equidistant
// projection is then the identity on the plane (w = (x, y) exactly), so each face is a triangle
// given directly in the stencil's reference frame.
struct PlanarSetup {
  std::vector<double> vertices;
  std::vector<int32_t> faces;
  std::vector<kernels::ClipShape> shapes;
  std::vector<double> polygons;
  std::vector<kernels::ClipStencil> stencils;
  std::vector<kernels::ClipPair> pairs;

  ClipInputs inputs() const { return {vertices, faces, shapes, polygons, stencils, pairs}; }

  void add_triangle(const Tri& t) {
    const int32_t base = int32_t(vertices.size() / 3);
    for (int k = 0; k < 3; ++k) vertices.insert(vertices.end(), {t[2 * k], t[2 * k + 1], 0.0});
    faces.insert(faces.end(), {base, base + 1, base + 2});
  }

  void add_shape(const Poly& p) {
    kernels::ClipShape s{};
    s.polygon_offset = int32_t(polygons.size() / 2);
    s.polygon_count = int32_t(p.size() / 2);
    s.area = area(p);
    s.inner_radius = inner_radius(p);
    polygons.insert(polygons.end(), p.begin(), p.end());
    shapes.push_back(s);
    // A stencil using it; its frame moves with q (∂c/∂q = I) so the derivatives are non-trivial.
    kernels::ClipStencil st{};
    st.axis_x[0] = 1.0;
    st.axis_y[1] = 1.0;
    st.d_origin[0] = st.d_origin[4] = st.d_origin[8] = 1.0;
    st.scale = 1.0;
    st.shape = int32_t(shapes.size() - 1);
    stencils.push_back(st);
  }

  void all_pairs() {
    pairs.clear();
    for (int32_t f = 0; f < int32_t(faces.size() / 3); ++f)
      for (int32_t s = 0; s < int32_t(stencils.size()); ++s) pairs.push_back({s, f});
  }

  static double area(const Poly& p) {
    const size_t n = p.size() / 2;
    double a = 0;
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      a += p[2 * i] * p[2 * j + 1] - p[2 * j] * p[2 * i + 1];
    }
    return 0.5 * a;
  }
  // Largest origin-centred disk inside p (0 when the origin is outside), shrunk by a hair as
  // the host does (host/stencil/stencil_shape.cpp).
  static double inner_radius(const Poly& p) {
    const size_t n = p.size() / 2;
    bool inside = false;
    double d2 = 1e300;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
      const double xi = p[2 * i], yi = p[2 * i + 1], xj = p[2 * j], yj = p[2 * j + 1];
      if ((yi > 0) != (yj > 0) && 0 < (xj - xi) * (0 - yi) / (yj - yi) + xi) inside = !inside;
      d2 = std::min(d2, kernels::origin_segment_distance2(xi, yi, xj, yj));
    }
    return inside ? std::sqrt(d2) * (1 - 1e-12) : 0.0;
  }
};

Poly regular(int n, double r = 1.0) {
  Poly p;
  for (int i = 0; i < n; ++i) {
    p.push_back(r * std::cos(2 * std::numbers::pi * i / n));
    p.push_back(r * std::sin(2 * std::numbers::pi * i / n));
  }
  return p;
}

// Star-shaped about the origin with random radii: simple, usually very non-convex.
Poly random_star(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> radius(0.2, 1.0);
  Poly p;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n, r = radius(rng);
    p.push_back(r * std::cos(a));
    p.push_back(r * std::sin(a));
  }
  return p;
}

// A comb with `notches` deep notches (parallel edges, many crossings per triangle edge).
Poly comb(int notches) {
  Poly p{-0.7, -0.6, 0.7, -0.6, 0.7, 0.6};
  const double w = 1.4 / (2 * notches + 1);
  for (int i = notches - 1; i >= 0; --i) {
    const double a = -0.7 + w * (2 * i + 1), b = a + w;
    p.insert(p.end(), {b, 0.6, b, -0.5, a, -0.5, a, 0.6});
  }
  p.insert(p.end(), {-0.7, 0.6});
  return p;
}

// A "C": the origin lies outside the polygon.
Poly c_shape(int segments) {
  Poly p;
  const double a0 = 0.6, a1 = 2 * std::numbers::pi - 0.6;
  for (int i = 0; i <= segments; ++i) {
    const double a = a0 + (a1 - a0) * i / segments;
    p.insert(p.end(), {std::cos(a), std::sin(a)});
  }
  for (int i = segments; i >= 0; --i) {
    const double a = a0 + (a1 - a0) * i / segments;
    p.insert(p.end(), {0.5 * std::cos(a), 0.5 * std::sin(a)});
  }
  return p;
}

Tri random_triangle(std::mt19937& rng, double extent, double size) {
  std::uniform_real_distribution<double> c(-extent, extent), d(-size, size);
  for (;;) {
    const double cx = c(rng), cy = c(rng);
    Tri t{cx + d(rng), cy + d(rng), cx + d(rng), cy + d(rng), cx + d(rng), cy + d(rng)};
    const double a = kernels::orient2(t[0], t[1], t[2], t[3], t[4], t[5]);
    if (std::abs(a) < 0.02 * size * size) continue;
    if (a < 0) {
      std::swap(t[2], t[4]);
      std::swap(t[3], t[5]);
    }
    return t;
  }
}

PlanarSetup adversarial_setup() {
  PlanarSetup s;
  std::mt19937 rng(99);
  s.add_shape(comb(40));
  s.add_shape(c_shape(64));
  s.add_shape(random_star(rng, 7));
  s.add_shape(random_star(rng, kMaxStencilPolygonVertices));  // the largest polygon accepted
  s.add_shape(regular(1024));
  s.add_shape({-0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5, 0.5});  // axis-aligned square
  // Random triangles from tiny to larger than the stencil.
  for (double size : {1e-6, 1e-3, 0.05, 0.3, 1.0, 3.0})
    for (int i = 0; i < 25; ++i) s.add_triangle(random_triangle(rng, 1.1, size));
  // Shared edges and vertices with the square; a corner exactly at the stencil centre
  // (the projection's on-axis case); a triangle containing the whole bounding circle.
  s.add_triangle({-0.5, -0.5, 0.5, -0.5, 0.5, 0.5});
  s.add_triangle({-0.5, -0.5, 0.5, 0.5, -0.5, 0.5});
  s.add_triangle({0.0, 0.0, 0.5, 0.0, 0.0, 0.5});
  s.add_triangle({-0.5, 0.0, 0.5, 0.0, 0.0, 0.5});
  s.add_triangle({-3.0, -2.0, 3.0, -2.0, 0.0, 4.0});
  s.add_triangle({0.5, -0.25, 0.75, 0.0, 0.5, 0.25});  // a corner on the square's edge
  s.all_pairs();
  return s;
}

TEST_F(ClipVkTest, AdversarialPolygonsAndTriangles) {
  const PlanarSetup s = adversarial_setup();
  const ClipInputs in = s.inputs();
  vulkan::ClipFillVk vk(shared_ctx());
  for (int exits : {1, 0}) {
    SCOPED_TRACE("early exits " + std::to_string(exits));
    const ClipOptions options{1, exits};
    const ParityStats st = expect_clip_parity(run_cpu(in, options), run_gpu(vk, in, options), in);
    EXPECT_GT(st.partial, 300u);
  }
}

TEST_F(ClipVkTest, InconsistentInputsAreRejectedBeforeTheyReachTheDevice) {
  PlanarSetup s = adversarial_setup();
  vulkan::ClipFillVk vk(shared_ctx());
  std::vector<ClipResult> r(s.pairs.size());
  s.pairs[3].face = int32_t(s.faces.size());  // past the last face
  EXPECT_THROW(vk.clip(s.inputs(), {}, r), std::invalid_argument);
  s = adversarial_setup();
  s.stencils[1].shape = 77;
  EXPECT_THROW(vk.clip(s.inputs(), {}, r), std::invalid_argument);
  s = adversarial_setup();
  s.faces[5] = -1;
  EXPECT_THROW(vk.clip(s.inputs(), {}, r), std::invalid_argument);
  // And the runner is still usable afterwards.
  s = adversarial_setup();
  expect_clip_parity(run_cpu(s.inputs(), {}), run_gpu(vk, s.inputs(), {}), s.inputs());
}

// --- the discrete-GPU memory path and chunked launches, on any device ----------------------------

class ClipVkStagingChunkedTest : public VulkanTest {
 protected:
  vulkan::ContextOptions options() const override {
    vulkan::ContextOptions o = validated_options();
    o.force_staging = true;
    o.max_workgroups_per_dispatch = 5;
    return o;
  }
};

TEST_F(ClipVkStagingChunkedTest, MatchesTbbTwin) {
  EXPECT_TRUE(ctx().uses_staging());
  const ClipScenario scene("pavilion", 0.08, 300, 3);
  const ClipInputs in = scene.inputs();
  vulkan::ClipFillVk vk(shared_ctx(), 32);
  expect_clip_parity(run_cpu(in, {}), run_gpu(vk, in, {}), in);
  ASSERT_EQ(vk.last_report().dispatches.size(), 1u);
  EXPECT_GT(vk.last_report().dispatches[0].chunks, 1u);
}

}  // namespace
}  // namespace cutwork::test

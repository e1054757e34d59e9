// Tests of the fill kernel: the segmented reduction against a direct per-face sum, the clamp
// (value and zero derivative), the pull-back against a dense product, and the twins bit for bit.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/fill/fill.h"

namespace cutwork::kernels {
namespace {

struct FillSetup {
  int faces = 0, stencils = 0;
  std::vector<ClipPair> pairs;         // sorted by (face, stencil)
  std::vector<ClipResult> clip;
  std::vector<int32_t> face_offsets;   // #F+1
  std::vector<int32_t> stencil_pairs;  // grouped by stencil
  std::vector<int32_t> stencil_offsets;
};

// Random sparse pairs; fractions mostly small, some faces heavily covered (so they clamp).
FillSetup random_setup(unsigned seed, int faces, int stencils) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1), g(-3, 3);
  FillSetup s;
  s.faces = faces;
  s.stencils = stencils;
  s.face_offsets.push_back(0);
  for (int f = 0; f < faces; ++f) {
    const int count = f % 7 == 0 ? 0 : int(u(rng) * 5);
    std::vector<int> chosen;
    for (int k = 0; k < count; ++k) chosen.push_back(int(u(rng) * stencils));
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
    for (int st : chosen) {
      s.pairs.push_back({st, f});
      ClipResult r{};
      r.fraction = f % 5 == 0 ? 0.6 : 0.3 * u(rng);
      for (double& d : r.d_fraction) d = g(rng);
      s.clip.push_back(r);
    }
    s.face_offsets.push_back(int32_t(s.pairs.size()));
  }
  s.stencil_offsets.assign(size_t(stencils) + 1, 0);
  for (const ClipPair& p : s.pairs) ++s.stencil_offsets[size_t(p.stencil) + 1];
  for (int i = 0; i < stencils; ++i) s.stencil_offsets[size_t(i) + 1] += s.stencil_offsets[size_t(i)];
  s.stencil_pairs.resize(s.pairs.size());
  std::vector<int32_t> cursor(s.stencil_offsets.begin(), s.stencil_offsets.end() - 1);
  for (size_t i = 0; i < s.pairs.size(); ++i) {
    s.stencil_pairs[size_t(cursor[size_t(s.pairs[i].stencil)]++)] = int32_t(i);
  }
  return s;
}

TEST(FillKernel, MatchesDirectSumAndClamps) {
  const FillSetup s = random_setup(1, 500, 60);
  std::vector<double> alpha(size_t(s.faces)), d_alpha(5 * s.pairs.size(), -7.0);
  fill_ref({s.clip, s.face_offsets}, {}, {alpha, d_alpha});
  int clamped = 0, empty = 0;
  for (int f = 0; f < s.faces; ++f) {
    double covered = 0;
    for (int32_t i = s.face_offsets[size_t(f)]; i < s.face_offsets[size_t(f) + 1]; ++i) {
      covered += s.clip[size_t(i)].fraction;
    }
    const bool clamp = 1 - covered <= 1e-4;
    EXPECT_EQ(alpha[size_t(f)], clamp ? 1e-4 : 1 - covered) << f;
    clamped += clamp;
    empty += s.face_offsets[size_t(f)] == s.face_offsets[size_t(f) + 1];
    for (int32_t i = s.face_offsets[size_t(f)]; i < s.face_offsets[size_t(f) + 1]; ++i) {
      for (int k = 0; k < 5; ++k) {
        EXPECT_EQ(d_alpha[5 * size_t(i) + size_t(k)], clamp ? 0.0 : -s.clip[size_t(i)].d_fraction[k]);
      }
    }
  }
  EXPECT_GT(clamped, 10);
  EXPECT_GT(empty, 10);
  for (int f = 0; f < s.faces; f += 7) EXPECT_EQ(alpha[size_t(f)], 1.0);
}

TEST(FillKernel, ClampIsInclusiveAtTheBound) {
  // Two pairs summing to exactly 1 − min_fill: clamped (α = min_fill, zero derivative).
  FillParams params;
  params.min_fill = 0.25;
  std::vector<ClipResult> clip(2);
  clip[0].fraction = 0.5;
  clip[1].fraction = 0.25;
  clip[0].d_fraction[0] = clip[1].d_fraction[0] = 1.0;
  const std::vector<int32_t> offsets{0, 2};
  std::vector<double> alpha(1), d_alpha(10, 9.0);
  fill_ref({clip, offsets}, params, {alpha, d_alpha});
  EXPECT_EQ(alpha[0], 0.25);
  EXPECT_EQ(d_alpha[0], 0.0);
  EXPECT_EQ(d_alpha[5], 0.0);
  clip[1].fraction = 0.2;  // now 1 − 0.7 = 0.3 > 0.25: not clamped
  fill_ref({clip, offsets}, params, {alpha, d_alpha});
  EXPECT_DOUBLE_EQ(alpha[0], 0.3);
  EXPECT_EQ(d_alpha[0], -1.0);
}

TEST(FillKernel, PullbackMatchesDenseProduct) {
  const FillSetup s = random_setup(2, 400, 50);
  std::vector<double> alpha(size_t(s.faces)), d_alpha(5 * s.pairs.size());
  fill_ref({s.clip, s.face_offsets}, {}, {alpha, d_alpha});
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<double> g_alpha(size_t(s.faces));
  for (double& g : g_alpha) g = u(rng);
  std::vector<double> g_params(5 * size_t(s.stencils), -1.0);
  const FillPullbackInputs in{s.pairs, d_alpha, s.stencil_pairs, s.stencil_offsets};
  fill_pullback_ref(in, g_alpha, g_params);
  // Dense Jacobian J (#F × 5#S), then Jᵀ g.
  std::vector<double> dense(size_t(s.faces) * 5 * size_t(s.stencils), 0.0);
  for (size_t i = 0; i < s.pairs.size(); ++i) {
    for (int k = 0; k < 5; ++k) {
      dense[size_t(s.pairs[i].face) * 5 * size_t(s.stencils) + 5 * size_t(s.pairs[i].stencil) +
            size_t(k)] += d_alpha[5 * i + size_t(k)];
    }
  }
  for (int c = 0; c < 5 * s.stencils; ++c) {
    double sum = 0, mag = 0;
    for (int f = 0; f < s.faces; ++f) {
      const double term = dense[size_t(f) * 5 * size_t(s.stencils) + size_t(c)] * g_alpha[size_t(f)];
      sum += term;
      mag += std::abs(term);
    }
    EXPECT_NEAR(g_params[size_t(c)], sum, 1e-14 * (1 + mag)) << c;
  }
}

TEST(FillKernel, ReferenceAndTbbTwinsAgreeBitForBit) {
  const FillSetup s = random_setup(4, 20000, 900);
  std::vector<double> a_ref(size_t(s.faces)), d_ref(5 * s.pairs.size());
  std::vector<double> a_tbb(size_t(s.faces)), d_tbb(5 * s.pairs.size());
  fill_ref({s.clip, s.face_offsets}, {}, {a_ref, d_ref});
  fill_tbb({s.clip, s.face_offsets}, {}, {a_tbb, d_tbb});
  EXPECT_EQ(std::memcmp(a_ref.data(), a_tbb.data(), a_ref.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(d_ref.data(), d_tbb.data(), d_ref.size() * sizeof(double)), 0);

  std::vector<double> g_alpha(size_t(s.faces));
  for (size_t f = 0; f < g_alpha.size(); ++f) g_alpha[f] = std::sin(double(f));
  std::vector<double> p_ref(5 * size_t(s.stencils)), p_tbb(p_ref.size()), p_one(p_ref.size());
  const FillPullbackInputs in{s.pairs, d_ref, s.stencil_pairs, s.stencil_offsets};
  fill_pullback_ref(in, g_alpha, p_ref);
  fill_pullback_tbb(in, g_alpha, p_tbb);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    fill_pullback_tbb(in, g_alpha, p_one);
  }
  EXPECT_EQ(std::memcmp(p_ref.data(), p_tbb.data(), p_ref.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(p_ref.data(), p_one.data(), p_ref.size() * sizeof(double)), 0);
}

TEST(FillKernel, DerivativesOffLeavesJacobianUntouched) {
  const FillSetup s = random_setup(5, 50, 10);
  std::vector<double> alpha(size_t(s.faces));
  FillParams params;
  params.derivatives = 0;
  fill_tbb({s.clip, s.face_offsets}, params, {alpha, {}});
  for (double a : alpha) EXPECT_GE(a, 1e-4);
}

}  // namespace
}  // namespace cutwork::kernels

// Broad phase: BVH queries against the brute-force twin, the incremental rebuild, the CSR
// layouts, and completeness of the candidate set on curved meshes (the evaluator's α equals
// an all-pairs evaluation through the same kernels).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "host/surfaces/generators.h"
#include "host/stencil/broad_phase.h"
#include "host/stencil/fill_ratio.h"

namespace cutwork {
namespace {

struct Placement {
  std::vector<Vec3> centers;
  std::vector<double> scales;
};

Placement random_placement(const SurfaceMesh& mesh, int n, double smin, double smax, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> face(0, mesh.num_faces() - 1);
  std::uniform_real_distribution<double> u(0, 1), s(smin, smax);
  Placement p;
  for (int i = 0; i < n; ++i) {
    const int f = face(rng);
    const double a = u(rng), b = u(rng) * (1 - a);
    Vec3 c = (1 - a - b) * mesh.vertices().row(mesh.faces()(f, 0)).transpose() +
             a * mesh.vertices().row(mesh.faces()(f, 1)).transpose() +
             b * mesh.vertices().row(mesh.faces()(f, 2)).transpose();
    p.centers.push_back(c);
    p.scales.push_back(s(rng));
  }
  return p;
}

bool same_pairs(const std::vector<kernels::ClipPair>& a, const std::vector<kernels::ClipPair>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](auto x, auto y) {
           return x.stencil == y.stencil && x.face == y.face;
         });
}

std::set<std::pair<int, int>> as_set(const std::vector<kernels::ClipPair>& v) {
  std::set<std::pair<int, int>> s;
  for (const auto& p : v) s.insert({p.stencil, p.face});
  return s;
}

void expect_consistent_layout(const BroadPhase& bp, int faces, int stencils) {
  const auto& pairs = bp.pairs();
  ASSERT_EQ(bp.face_offsets().size(), size_t(faces) + 1);
  ASSERT_EQ(bp.stencil_offsets().size(), size_t(stencils) + 1);
  EXPECT_EQ(bp.face_offsets().back(), int(pairs.size()));
  for (int f = 0; f < faces; ++f)
    for (int i = bp.face_offsets()[size_t(f)]; i < bp.face_offsets()[size_t(f) + 1]; ++i)
      EXPECT_EQ(pairs[size_t(i)].face, f);
  for (size_t i = 1; i < pairs.size(); ++i)
    EXPECT_TRUE(pairs[i - 1].face < pairs[i].face ||
                (pairs[i - 1].face == pairs[i].face && pairs[i - 1].stencil < pairs[i].stencil));
  std::vector<int> seen(pairs.size(), 0);
  for (int s = 0; s < stencils; ++s) {
    int last_face = -1;
    for (int j = bp.stencil_offsets()[size_t(s)]; j < bp.stencil_offsets()[size_t(s) + 1]; ++j) {
      const int i = bp.stencil_pairs()[size_t(j)];
      EXPECT_EQ(pairs[size_t(i)].stencil, s);
      EXPECT_GT(pairs[size_t(i)].face, last_face);
      last_face = pairs[size_t(i)].face;
      ++seen[size_t(i)];
    }
  }
  for (int c : seen) EXPECT_EQ(c, 1);
}

TEST(BroadPhase, MatchesBruteForce) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  const Placement p = random_placement(mesh, 40, 0.005, 0.04, 1);
  BroadPhaseOptions opt;
  opt.slack = 0;
  BroadPhase bp(bvh, opt);
  EXPECT_EQ(bp.update(p.centers, p.scales), 40);
  EXPECT_TRUE(same_pairs(bp.pairs(), candidate_pairs_brute_force(mesh, p.centers, p.scales, opt.margin)));
  expect_consistent_layout(bp, mesh.num_faces(), 40);
  EXPECT_GT(bp.pairs().size(), 400u);
}

TEST(BroadPhase, IncrementalRebuildRequeriesOnlyMovedStencils) {
  const SurfaceMesh mesh = generate_shape("bowl", {}, 0.01);
  const FaceBvh bvh(mesh);
  Placement p = random_placement(mesh, 30, 0.01, 0.03, 2);
  BroadPhase bp(bvh);  // default slack
  EXPECT_EQ(bp.update(p.centers, p.scales), 30);
  EXPECT_EQ(bp.update(p.centers, p.scales), 0);
  // Small moves (within the slack): nothing re-queried, the set still covers what is needed.
  for (size_t i = 0; i < p.centers.size(); ++i) p.centers[i].x() += 0.05 * p.scales[i];
  EXPECT_EQ(bp.update(p.centers, p.scales), 0);
  auto needed = as_set(candidate_pairs_brute_force(mesh, p.centers, p.scales, bp.options().margin));
  auto have = as_set(bp.pairs());
  EXPECT_TRUE(std::includes(have.begin(), have.end(), needed.begin(), needed.end()));
  // Three stencils jump (one also grows): exactly those are re-queried.
  const Placement far = random_placement(mesh, 3, 0.01, 0.03, 3);
  for (int k = 0; k < 3; ++k) p.centers[size_t(5 * k)] = far.centers[size_t(k)];
  p.scales[7] *= 1.5;
  EXPECT_EQ(bp.update(p.centers, p.scales), 4);
  needed = as_set(candidate_pairs_brute_force(mesh, p.centers, p.scales, bp.options().margin));
  have = as_set(bp.pairs());
  EXPECT_TRUE(std::includes(have.begin(), have.end(), needed.begin(), needed.end()));
  // …and nothing beyond the queried balls (slack included).
  const auto loose = as_set(candidate_pairs_brute_force(
      mesh, p.centers, p.scales, (1 + bp.options().margin) * (1 + bp.options().slack) * 1.06 - 1));
  EXPECT_TRUE(std::includes(loose.begin(), loose.end(), have.begin(), have.end()));
  expect_consistent_layout(bp, mesh.num_faces(), 30);
  // A different stencil count re-queries everything.
  p.centers.pop_back();
  p.scales.pop_back();
  EXPECT_EQ(bp.update(p.centers, p.scales), 29);
  expect_consistent_layout(bp, mesh.num_faces(), 29);
}

/// α through the evaluator against α from every (stencil, face) pair through the kernels.
void expect_complete(const SurfaceMesh& mesh, double smin, double smax, unsigned seed) {
  const FaceBvh bvh(mesh);
  StencilLibrary lib;
  lib.add(make_builtin_stencil("flower", {}, "flower"));
  lib.add(make_builtin_stencil("heart", {}, "heart"));
  const Placement p = random_placement(mesh, 12, smin, smax, seed);
  std::vector<StencilParams> st;
  for (size_t i = 0; i < p.centers.size(); ++i)
    st.push_back({p.centers[i], p.scales[i], 0.3 * double(i), int(i % 2)});
  FillRatioEvaluator ev(bvh, lib);
  ev.evaluate(st);

  const AxisTangentField field;
  std::vector<kernels::ClipStencil> records;
  for (const StencilParams& s : st) {
    FrameJacobian J;
    const Frame fr = compute_frame(bvh, field, s.position, &J);
    records.push_back(make_clip_stencil(fr, J, s.scale, s.angle, s.type));
  }
  std::vector<kernels::ClipPair> all;
  std::vector<int32_t> offsets{0};
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int s = 0; s < int(st.size()); ++s) all.push_back({s, f});
    offsets.push_back(int32_t(all.size()));
  }
  kernels::ClipInputs in{{mesh.vertices().data(), size_t(mesh.vertices().size())},
                         {mesh.faces().data(), size_t(mesh.faces().size())},
                         lib.clip_shapes(),
                         lib.packed_polygons(),
                         records,
                         all};
  std::vector<kernels::ClipResult> results(all.size());
  kernels::ClipWorkspace ws;
  kernels::clip_tbb(in, {}, results, ws);
  std::vector<double> alpha(size_t(mesh.num_faces())), d_alpha(5 * all.size());
  kernels::fill_tbb({results, offsets}, {}, {alpha, d_alpha});
  int partial = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    EXPECT_NEAR(ev.alpha()[f], alpha[size_t(f)], 1e-14) << "face " << f;
    partial += alpha[size_t(f)] < 1 && alpha[size_t(f)] > 1e-4;
  }
  EXPECT_GT(partial, 50);
}

TEST(BroadPhase, CandidateSetIsCompleteOnTheBowl) {
  expect_complete(generate_shape("bowl", {}, 0.01), 0.01, 0.05, 4);
}

TEST(BroadPhase, CandidateSetIsCompleteOnThePavilion) {
  expect_complete(generate_shape("pavilion", {}, 0.2), 0.2, 0.9, 5);
}

}  // namespace
}  // namespace cutwork

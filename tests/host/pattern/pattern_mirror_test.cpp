// The pattern on symmetry planes (host/pattern/pattern_mirror.h): a half (quarter) with its mirror
// images is its mirrored whole — the packing objective and PatternEnergy are the whole's divided by
// its number of copies, term by term, with exact gradients; admissibility is the whole's (a stencil
// keeps (1+s) r + g/2 from a plane, not the boundary's (1+s) r + g); the initialisations fill up to
// the plane without overlapping an image; the automatic scale and ε are the whole's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "host/mesh/mirror.h"
#include "host/pattern/det.h"
#include "host/pattern/overlaps.h"
#include "host/pattern/packing_objective.h"
#include "host/pattern/pattern_context.h"
#include "host/pattern/pattern_energy.h"
#include "host/pattern/poisson_disk.h"
#include "host/scene/scene.h"
#include "pattern_test_util.h"

namespace cutwork {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// A mesh mirrored in each plane of `planes` in turn (the whole a half or quarter stands for).
SurfaceMesh mirrored_whole(const SurfaceMesh& half, const Vec3& planes) {
  RowMatX3d v = half.vertices();
  RowMatX3i f = half.faces();
  for (int a = 0; a < 3; ++a)
    if (std::isfinite(planes[a])) {
      MirroredMesh m = mirror_across_plane(v, f, a, planes[a], 1e-9);
      v = m.vertices;
      f = m.faces;
    }
  return SurfaceMesh(v, f, "whole");
}

/// The layout's positions and scales followed by their images (in every reflection).
void mirrored_layout(const PatternMirror& mirror, const RowMatX3d& q, const Eigen::VectorXd& r, RowMatX3d& wq,
                     Eigen::VectorXd& wr) {
  const int S = int(q.rows()), copies = 1 + mirror.num_reflections();
  wq.resize(S * copies, 3);
  wr.resize(S * copies);
  for (int k = -1; k < mirror.num_reflections(); ++k)
    for (int i = 0; i < S; ++i) {
      const int row = (k + 1) * S + i;
      wq.row(row) = (k < 0 ? Vec3(q.row(i).transpose()) : mirror.image(q.row(i).transpose(), k)).transpose();
      wr[row] = r[i];
    }
}

/// S stencils on the plate [0, w] × [0, h] (z = 0), radii about `r`, many within reach of the planes
/// x = 0 and y = 0 and of the boundary, none on a plane.
void layout_near_the_planes(int S, double w, double h, double r, PatternRng& rng, RowMatX3d& q,
                            Eigen::VectorXd& scales) {
  q.resize(S, 3);
  scales.resize(S);
  for (int i = 0; i < S; ++i) {
    const double x = i % 3 == 0 ? rng.uniform(0.05 * r, 3 * r) : rng.uniform(0.05 * r, w - 0.05 * r);
    const double y = i % 4 == 0 ? rng.uniform(0.05 * r, 3 * r) : rng.uniform(0.05 * r, h - 0.05 * r);
    q.row(i) << x, y, 0.0;
    scales[i] = r * rng.uniform(0.7, 1.3);
  }
}

TEST(PatternMirror, ReflectionsAndImagePairsMatchTheBruteForceTwin) {
  const PatternMirror mirror(Vec3(0.5, kNaN, -0.2), Vec3(1.0, 0.0, 0.3));
  ASSERT_EQ(mirror.num_reflections(), 3);
  EXPECT_EQ(mirror.side(0), 1);
  EXPECT_EQ(mirror.side(1), 0);
  EXPECT_EQ(mirror.side(2), 1);
  const Vec3 p(0.7, 0.1, 0.0);
  int singles = 0;
  for (int k = 0; k < 3; ++k) {
    singles += mirror.single(k);
    const Vec3 y = mirror.image(p, k);
    EXPECT_LT((mirror.image(y, k) - p).norm(), 1e-15);  // an involution
    EXPECT_EQ(y.y(), p.y());
  }
  EXPECT_EQ(singles, 2);

  PatternRng rng(7);
  RowMatX3d pos(200, 3);
  for (int i = 0; i < 200; ++i) pos.row(i) << rng.uniform(0.5, 1.5), rng.uniform(0, 1), rng.uniform(-0.2, 0.8);
  for (double cutoff : {0.05, 0.2}) {
    const auto fast = image_pairs(mirror, pos, cutoff), slow = image_pairs_brute_force(mirror, pos, cutoff);
    ASSERT_EQ(fast.size(), slow.size()) << cutoff;
    ASSERT_GT(fast.size(), cutoff > 0.1 ? 100u : 4u);
    for (size_t n = 0; n < fast.size(); ++n) {
      EXPECT_EQ(fast[n].i, slow[n].i);
      EXPECT_EQ(fast[n].j, slow[n].j);
      EXPECT_EQ(fast[n].k, slow[n].k);
      EXPECT_NEAR(fast[n].distance, slow[n].distance, 1e-15);
    }
  }
  EXPECT_TRUE(image_pairs(PatternMirror(), pos, 0.2).empty());
}

TEST(PatternMirror, PackingObjectiveOfAHalfAndAQuarterIsTheirWholesShare) {
  // Every term of (5) on the half (quarter) with images equals the mirrored whole's divided by 2 (4),
  // on layouts where collisions with images, own images and the boundary are all active.
  const double w = 0.1, h = 0.06, r = 0.006;
  const SurfaceMesh half = test::flat_plate(w, h, 0.005);
  for (const Vec3& planes : {Vec3(0.0, kNaN, kNaN), Vec3(0.0, 0.0, kNaN)}) {
    const PatternMirror mirror(planes, Vec3(w / 2, h / 2, 0));
    const SurfaceMesh whole = mirrored_whole(half, planes);
    const BoundaryPolylines half_boundary(half, 0.02, &mirror), whole_boundary(whole, 0.02);
    PackingSettings st;
    st.unit = r;
    st.epsilon = 0.02;
    PatternRng rng(3);
    RowMatX3d q, wq;
    Eigen::VectorXd s, ws;
    layout_near_the_planes(40, w, h, r, rng, q, s);
    mirrored_layout(mirror, q, s, wq, ws);
    PackingTerms part, all;
    const double v_half = packing_objective(q, s, st, half_boundary, nullptr, nullptr, nullptr, &part, &mirror);
    const double v_whole = packing_objective(wq, ws, st, whole_boundary, nullptr, nullptr, nullptr, &all);
    const double copies = 1 + mirror.num_reflections();
    ASSERT_GT(part.collision, 1.0);
    ASSERT_GT(part.boundary, 1.0);
    // A stencil's pair with its own image is the whole's collision, the model's boundary term (at q).
    EXPECT_NEAR(copies * (part.collision + part.boundary), all.collision + all.boundary, 1e-11 * all.collision);
    EXPECT_NEAR(copies * part.repulsion, all.repulsion, 1e-11 * std::abs(all.repulsion));
    EXPECT_NEAR(copies * part.growth, all.growth, 1e-12 * std::abs(all.growth));
    EXPECT_NEAR(copies * v_half, v_whole, 1e-11 * std::abs(v_whole));
    // Without the images the half is not its whole's share: the plane would be a boundary.
    PackingTerms plain;
    packing_objective(q, s, st, BoundaryPolylines(half, 0.02), nullptr, nullptr, nullptr, &plain);
    EXPECT_GT(std::abs(copies * plain.total() - all.total()), 1e-3 * std::abs(all.total()));
  }
}

TEST(PatternMirror, ImageTermsGradients) {
  // Central differences of every term with images (two planes), positions also beyond a plane
  // (the plane term's signed distance pushes them back).
  const double w = 0.1, h = 0.06, r = 0.006;
  const PatternMirror mirror(Vec3(0.0, 0.0, kNaN), Vec3(w / 2, h / 2, 0));
  PatternRng rng(11);
  RowMatX3d q0;
  Eigen::VectorXd s0;
  layout_near_the_planes(24, w, h, r, rng, q0, s0);
  q0(1, 0) = -0.3 * r;  // beyond the plane x = 0
  q0(2, 2) = 0.2 * r;   // off the surface
  const double unit = r, eps = 0.02, safety = 0.2, gap = 0.4 * r;
  const double cutoff = packing_cutoff(s0, safety, eps, gap) * 1.5;  // fixed while differencing
  const char* names[] = {"image collision", "plane collision", "image repulsion"};
  for (int which = 0; which < 3; ++which) {
    const test::TermFn term = [&](const RowMatX3d& q, const Eigen::VectorXd& s, RowMatX3d* pq, Eigen::VectorXd* ps) {
      const auto pairs = image_pairs(mirror, q, cutoff);
      if (which == 0) return image_collision_objective(mirror, q, s, safety, unit, pairs, pq, ps, gap);
      if (which == 1) return plane_collision_objective(mirror, q, s, safety, unit, pq, ps, gap);
      return image_repulsion_objective(mirror, q, eps, unit, pairs, pq);
    };
    ASSERT_GT(std::abs(term(q0, s0, nullptr, nullptr)), 1e-3) << names[which] << " is not active";
    EXPECT_TRUE(test::check_term(term, q0, s0, 1e-7 * r, names[which]));
  }
}

TEST(PatternMirror, OverlapsKeepHalfTheGapFromAPlane) {
  // A stencil keeps (1+s) r + g/2 from a plane (the ligament to its image is g), where a boundary
  // asks (1+s) r + g; a stencil and another's image obey the pair rule.
  const double w = 0.1, h = 0.06, r = 0.005, safety = 0.2, gap = 0.002;
  const SurfaceMesh half = test::flat_plate(w, h, 0.005);
  const SizingField ones(Eigen::VectorXd::Ones(half.num_vertices()));
  PatternSurface mirrored(half, OrientationFieldOptions{}, ones, 0.02, Vec3(0.0, kNaN, kNaN));
  PatternSurface plain(half, OrientationFieldOptions{}, ones, 0.02);
  auto at = [&](double x, double y, double scale) {
    PlacedStencil p;
    p.position = Vec3(x, y, 0);
    p.where = mirrored.project(p.position).where;
    p.scale = scale;
    return p;
  };
  // Admissible on the plane with 0.6 g to spare from it; a boundary would want the full g.
  StencilLayout layout = {at((1 + safety) * r + 0.6 * gap, h / 2, r)};
  EXPECT_FALSE(find_overlaps(mirrored, layout, safety, gap).any());
  EXPECT_EQ(find_overlaps(plain, layout, safety, gap).boundary, 1);
  // 0.4 g: the ligament to its own image is 0.8 g.
  layout = {at((1 + safety) * r + 0.4 * gap, h / 2, r)};
  for (const OverlapReport& rep : {find_overlaps(mirrored, layout, safety, gap),
                                   find_overlaps_brute_force(mirrored, layout, safety, gap)}) {
    EXPECT_EQ(rep.images, 1);
    EXPECT_EQ(rep.boundary, 0);
    EXPECT_EQ(rep.pairs, 0);
  }
  EXPECT_EQ(resolve_overlaps(mirrored, layout, safety, Eigen::VectorXd::Zero(1), gap), 0);
  const double delta = (1 + safety) * r + 0.4 * gap;
  EXPECT_NEAR(layout[0].scale, (2 * delta - gap) / (2 * (1 + safety)), 1e-9 * r);
  EXPECT_FALSE(find_overlaps(mirrored, layout, safety, gap).any());

  // Two stencils by the plane, too close to one another: one pair of the model (their images are
  // farther apart than they are: a point and another's image are never nearer than the two points).
  layout = {at(delta + gap, h / 2, r), at(delta + gap, h / 2 + 2 * (1 + safety) * r, r)};
  const OverlapReport two = find_overlaps(mirrored, layout, safety, gap);
  EXPECT_EQ(two.pairs, 1);
  EXPECT_EQ(two.images, 0);
}

TEST(PatternMirror, InitialisationsFillUpToThePlaneAndTheirWholeIsAdmissible) {
  // Poisson disk and DET growth on a quarter: the layout with its images is admissible on the
  // mirrored whole, and stencils come as near the planes as they come to one another.
  const double w = 0.12, h = 0.08;
  const Vec3 planes(0.0, 0.0, kNaN);
  const SurfaceMesh half = test::flat_plate(w, h, 0.004);
  const SurfaceMesh whole = mirrored_whole(half, planes);
  const SizingField ones(Eigen::VectorXd::Ones(half.num_vertices()));
  const SizingField whole_ones(Eigen::VectorXd::Ones(whole.num_vertices()));
  PatternSurface surface(half, OrientationFieldOptions{}, ones, 0.02, planes);
  PatternSurface whole_surface(whole, OrientationFieldOptions{}, whole_ones, 0.02);
  EXPECT_DOUBLE_EQ(surface.length(), whole_surface.length());
  const double safety = 0.2;

  auto check = [&](const StencilLayout& layout, double unit, const char* what) {
    ASSERT_GT(layout.size(), 20u) << what;
    RowMatX3d wq;
    Eigen::VectorXd wr;
    mirrored_layout(surface.mirror(), layout_positions(layout), layout_scales(layout), wq, wr);
    StencilLayout wl;
    for (int i = 0; i < wq.rows(); ++i) {
      PlacedStencil p;
      p.position = wq.row(i).transpose();
      p.where = whole_surface.project(p.position).where;
      p.scale = wr[i];
      wl.push_back(p);
    }
    const OverlapReport rep = find_overlaps_brute_force(whole_surface, wl, safety);
    EXPECT_FALSE(rep.any()) << what << ": " << rep.pairs << " pairs, " << rep.boundary << " at the boundary";
    // Up to the plane: the nearest centre to each plane is within 2 (1+s) r of it.
    for (int a = 0; a < 2; ++a) {
      double nearest = INFINITY;
      for (const auto& p : layout) nearest = std::min(nearest, p.position[a]);
      EXPECT_LT(nearest, 2 * (1 + safety) * unit) << what << " axis " << a;
      EXPECT_GE(nearest, (1 + safety) * unit * (1 - 1e-12)) << what << " axis " << a;
    }
  };

  PatternRng rng(5);
  PoissonDiskOptions o;
  o.unit = 0.004;
  o.safety = safety;
  StencilLayout disk;
  poisson_disk_sample(surface, disk, rng, o);
  check(disk, o.unit, "Poisson disk");

  DetSettings st;
  st.sigma = 0.03;
  st.unit = st.sigma * 0.06;
  st.symmetry = 1;
  st.safety = safety;
  const Exemplar ex = builtin_exemplar("packing");
  const DetExemplar det(ex, std::vector<int>(ex.type_names.size(), 0), st);
  StencilLayout grown;
  det_grow(det, surface, grown, rng, DetGrowthOptions{});
  double smallest = INFINITY;
  for (const auto& p : grown) smallest = std::min(smallest, p.scale);
  check(grown, smallest, "DET growth");
}

TEST(PatternMirror, PatternEnergyOfAHalfIsTheWholesShare) {
  // PatternEnergy (projection, tether, every packing term) on a half plate with its plane against the
  // mirrored whole; its gradient through the projection by central differences.
  const double w = 0.1, h = 0.06, r = 0.006;
  const Vec3 planes(kNaN, 0.0, kNaN);
  const SurfaceMesh half = test::flat_plate(w, h, 0.005);
  const SurfaceMesh whole = mirrored_whole(half, planes);
  PatternSurface surface(half, OrientationFieldOptions{}, SizingField(Eigen::VectorXd::Ones(half.num_vertices())),
                         0.02, planes);
  PatternSurface whole_surface(whole, OrientationFieldOptions{},
                               SizingField(Eigen::VectorXd::Ones(whole.num_vertices())), 0.02);
  PatternEnergySettings es;
  es.unit = r;
  es.epsilon = 0.02;
  es.gap = 0.3 * r;
  const PatternEnergy energy(surface, es), whole_energy(whole_surface, es);
  PatternRng rng(9);
  RowMatX3d q, wq;
  Eigen::VectorXd s, ws;
  layout_near_the_planes(30, w, h, r, rng, q, s);
  mirrored_layout(surface.mirror(), q, s, wq, ws);
  PatternTerms part, all;
  const double v = energy.evaluate(q, s, Eigen::VectorXi::Zero(q.rows()), nullptr, nullptr, &part);
  const double vw = whole_energy.evaluate(wq, ws, Eigen::VectorXi::Zero(wq.rows()), nullptr, nullptr, &all);
  ASSERT_GT(part.collision, 1.0);
  ASSERT_GT(part.boundary, 1.0);
  EXPECT_NEAR(2 * (part.collision + part.boundary), all.collision + all.boundary, 1e-11 * all.collision);
  EXPECT_NEAR(2 * part.repulsion, all.repulsion, 1e-11 * std::abs(all.repulsion));
  EXPECT_NEAR(2 * v, vw, 1e-11 * std::abs(vw));

  q(0, 2) = 0.1 * r;   // off the surface: the tether
  q(1, 1) = -0.2 * r;  // beyond the plane: the plane term at q
  const test::TermFn term = [&](const RowMatX3d& qq, const Eigen::VectorXd& ss, RowMatX3d* pq, Eigen::VectorXd* ps) {
    return energy.evaluate(qq, ss, Eigen::VectorXi::Zero(qq.rows()), pq, ps);
  };
  EXPECT_TRUE(test::check_term(term, q, s, 1e-7 * r, "pattern energy on a symmetry plane", 1e-5));
}

TEST(PatternMirror, DetNeighbourhoodsReachAcrossThePlane) {
  // DET on a half plate: a stencil's neighbourhood holds the images within its radius, so it is
  // matched as the same stencil of the mirrored whole is (same neighbours, exemplar element, rotation
  // and cost); the energy's gradient through the images by central differences; the type vote
  // counts an image's votes for its stencil.
  const double w = 0.12, h = 0.06;
  const Vec3 planes(kNaN, 0.0, kNaN);
  const SurfaceMesh half = test::flat_plate(w, h, 0.004);
  const SurfaceMesh whole = mirrored_whole(half, planes);
  OrientationFieldOptions fo;
  fo.mirror_planes = planes;
  PatternSurface surface(half, fo, SizingField(Eigen::VectorXd::Ones(half.num_vertices())), 0.02, planes);
  PatternSurface whole_surface(whole, OrientationFieldOptions{}, SizingField(Eigen::VectorXd::Ones(whole.num_vertices())),
                               0.02);
  DetSettings ds;
  ds.sigma = 0.03;
  ds.unit = ds.sigma * 0.06;
  ds.safety = 0.2;
  const Exemplar ex = builtin_exemplar("mix");
  std::vector<int> types(ex.type_names.size());
  for (size_t t = 0; t < types.size(); ++t) types[t] = int(t);
  const DetExemplar det(ex, types, ds);
  PatternRng rng(4);
  StencilLayout layout;
  det_grow(det, surface, layout, rng, DetGrowthOptions{});
  const int S = int(layout.size());
  ASSERT_GT(S, 20);
  StencilLayout whole_layout = layout;
  for (const PlacedStencil& p : layout) {
    PlacedStencil m = p;
    m.position = surface.mirror().image(p.position, 0);
    m.where = whole_surface.project(m.position).where;
    whole_layout.push_back(m);
  }
  PatternEnergySettings es;
  es.kind = PatternKind::Exemplar;
  es.unit = ds.unit;
  es.safety = ds.safety;
  PatternEnergy energy(surface, es, &det), whole_energy(whole_surface, es, &det);
  energy.rematch(layout);
  whole_energy.rematch(whole_layout);
  ASSERT_FALSE(energy.image_sources().empty());
  int across = 0;
  for (int i = 0; i < S; ++i) {
    const DetNeighborhood& a = energy.neighborhoods()[size_t(i)];
    const DetNeighborhood& b = whole_energy.neighborhoods()[size_t(i)];
    ASSERT_EQ(a.outputs.size(), b.outputs.size()) << "stencil " << i;
    EXPECT_EQ(a.center, b.center) << "stencil " << i;
    EXPECT_EQ(a.rotation, b.rotation) << "stencil " << i;
    EXPECT_NEAR(a.cost, b.cost, 1e-9 * std::max(1.0, b.cost)) << "stencil " << i;
    across += std::any_of(a.outputs.begin(), a.outputs.end(), [&](int j) { return j >= S; });
  }
  EXPECT_GT(across, 3);

  RowMatX3d q = layout_positions(layout);
  const Eigen::VectorXd scales = layout_scales(layout);
  const Eigen::VectorXi t = layout_types(layout);
  for (int i = 0; i < S; ++i) q(i, 0) += 0.05 * ds.unit * std::sin(3.0 * i);  // off the matched positions
  // The whole energy: DET with its images, collision, plane and boundary terms.
  const test::TermFn term = [&](const RowMatX3d& qq, const Eigen::VectorXd& ss, RowMatX3d* pq, Eigen::VectorXd* ps) {
    return energy.evaluate(qq, ss, t, pq, ps);
  };
  EXPECT_TRUE(test::check_term(term, q, scales, 1e-7 * ds.unit, "DET energy with images", 1e-5));

  // The vote: as in the whole, where an image's neighbourhood votes for the stencil as the stencil's
  // does for the image when the match is mirrored. The whole's image neighbourhoods are matched to
  // the exemplar itself, not its mirror image, so with the chiral "mix" a few votes differ (4 of 402).
  StencilLayout voted = layout, whole_voted = whole_layout;
  energy.vote_types(voted);
  det_vote_types(det, whole_energy.neighborhoods(), whole_voted);
  int same = 0;
  for (int i = 0; i < S; ++i) same += voted[size_t(i)].type == whole_voted[size_t(i)].type;
  EXPECT_GE(same, 0.98 * S);
}

TEST(PatternMirror, TheAutomaticScaleAndEpsilonOfAHalfAreTheWholes) {
  // The built-in plate and its half on the plane y = −0.025: the same ℓ and ε, so the half's
  // design has the whole's stencils.
  const Scene whole = parse_scene(builtin_scene_json("plate"), "test:plate");
  nlohmann::json doc = builtin_scene_json("plate");
  doc["mesh"]["params"]["height"] = 0.05;
  doc["supports"].push_back({{"type", "symmetry"},
                             {"axis", "y"},
                             {"select", {{"entity", "vertices"}, {"y", {{"below", -0.0249999}}}}}});
  const Scene half = parse_scene(doc, "test:half plate");
  const SceneMeshes wm = build_scene_meshes(whole), hm = build_scene_meshes(half);
  const PatternContext wc(whole, wm), hc(half, hm);
  EXPECT_NEAR(hc.unit(), wc.unit(), 1e-12 * wc.unit());
  EXPECT_NEAR(hc.epsilon(), wc.epsilon(), 1e-12 * wc.epsilon());
  EXPECT_TRUE(hc.surface().mirror().has_plane(1));
  EXPECT_FALSE(wc.surface().mirror().any());
  // The plane is no boundary of the half: no segment lies on y = −0.025.
  for (const auto& seg : hc.surface().boundary().segments())
    EXPECT_FALSE(std::abs(seg.a.y() + 0.025) < 1e-9 && std::abs(seg.b.y() + 0.025) < 1e-9);
}

}  // namespace
}  // namespace cutwork

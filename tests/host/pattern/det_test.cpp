// Discrete element textures: the projection helper, the energy's gradient against central
// differences, matching of an exact copy, the type vote, and the incremental growth.
#include <gtest/gtest.h>

#include "host/core/error.h"
#include "host/pattern/det.h"
#include "host/pattern/overlaps.h"
#include "host/surfaces/generators.h"
#include "pattern_test_util.h"

namespace cutwork {
namespace {

/// Exemplar type t → stencil type t.
std::vector<int> identity_types(const Exemplar& ex) {
  std::vector<int> t(ex.type_names.size());
  for (size_t k = 0; k < t.size(); ++k) t[k] = int(k);
  return t;
}

std::unique_ptr<PatternSurface> make_surface(const SurfaceMesh& mesh, int symmetry) {
  OrientationFieldOptions o;
  o.symmetry = symmetry;
  return std::make_unique<PatternSurface>(mesh, o, SizingField(Eigen::VectorXd::Ones(mesh.num_vertices())),
                                          0.02);
}

TEST(Det, EquidistantOffsetPreservesLengthAndHasExactJacobian) {
  PatternRng rng(1);
  for (int k = 0; k < 50; ++k) {
    const Vec3 n = Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)).normalized();
    const Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    const Vec3 p = equidistant_offset(v, n, nullptr);
    EXPECT_NEAR(p.norm(), v.norm(), 1e-14);
    EXPECT_NEAR(p.dot(n), 0.0, 1e-14);
    for (int c = 0; c < 3; ++c) {
      auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
        Eigen::Matrix3d J;
        const Vec3 r = equidistant_offset(Vec3(x), n, g ? &J : nullptr);
        if (g) *g = J.row(c).transpose();
        return r[c];
      };
      EXPECT_TRUE(test::gradient_matches(f, Eigen::VectorXd(v), 1e-6, 1e-7, "equidistant offset"));
    }
  }
}

TEST(Det, ExemplarNeedsAnInteriorNeighbourhood) {
  Exemplar ex = builtin_exemplar("packing");
  DetSettings st;
  st.r_N = 0.6;  // no element is 0.6 inside a unit square
  try {
    DetExemplar d(ex, {0}, st);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lower pattern.r_N"), std::string::npos) << e.what();
  }
  st.r_N = 0.3;
  const DetExemplar d(ex, {0}, st);
  EXPECT_FALSE(d.centers().empty());
  for (int e : d.centers()) EXPECT_GE(ex.distance_to_boundary(ex.elements[size_t(e)].position), 0.3);
}

/// Lays an exemplar's elements onto the flat plate: x = origin + σ (u, v), field along x.
StencilLayout copy_exemplar(const DetExemplar& ex, const PatternSurface& surface, const Vec3& origin) {
  StencilLayout layout;
  const double sigma = ex.settings().sigma;
  for (int m = 0; m < ex.num_elements(); ++m) {
    const auto& el = ex.exemplar().elements[size_t(m)];
    const Vec3 x = origin + sigma * Vec3(el.position.x(), el.position.y(), 0);
    const ClosestPoint cp = surface.project(x);
    layout.push_back({cp.point, cp.where, sigma * el.scale, el.angle, ex.stencil_type(m)});
  }
  return layout;
}

TEST(Det, AnExactCopyMatchesItselfAtZeroEnergy) {
  const SurfaceMesh mesh = test::flat_plate(0.3, 0.3, 0.01);
  for (const char* name : {"stripes", "circles"}) {
    const auto surface = make_surface(mesh, 2);
    DetSettings st;
    st.sigma = 0.2;
    st.unit = 0.2 * 0.04;
    st.symmetry = 2;
    const DetExemplar ex(builtin_exemplar(name), identity_types(builtin_exemplar(name)), st);
    const StencilLayout layout = copy_exemplar(ex, *surface, Vec3(0.05, 0.05, 0));
    const auto hoods = det_match(ex, *surface, layout);
    for (int e : ex.centers()) {
      // An interior element sees its exemplar neighbourhood exactly: zero cost, all matched.
      EXPECT_NEAR(hoods[size_t(e)].cost, 0.0, 1e-9) << name << " element " << e;
      for (int m : hoods[size_t(e)].matches) EXPECT_GE(m, 0);
    }
    // The energy of an exact copy is zero except where boundary stencils' partial
    // neighbourhoods matched other patches (they still fit exactly: translation invariance).
    const double E = det_objective(ex, hoods, layout_positions(layout), layout_scales(layout),
                                   layout_types(layout), nullptr, nullptr);
    EXPECT_LT(E, 1e-12) << name;
  }
}

TEST(Det, EnergyGradientOnPlateAndBowl) {
  for (const char* shape : {"plate", "bowl"}) {
    const SurfaceMesh mesh = generate_shape(shape, {}, find_shape(shape)->base_edge_length);
    const auto surface = make_surface(mesh, 1);
    DetSettings st;
    st.sigma = 0.5 * (mesh.bbox_max() - mesh.bbox_min()).maxCoeff();
    st.unit = st.sigma * 0.05;
    st.symmetry = 1;
    st.xi = 0.7;
    const DetExemplar ex(builtin_exemplar("mix"), {0, 1, 0}, st);
    PatternRng rng(4);
    StencilLayout layout;
    det_grow(ex, *surface, layout, rng, DetGrowthOptions{});
    ASSERT_GT(layout.size(), 30u) << shape;
    // Perturb so that the energy is far from zero, then freeze the matching.
    for (auto& s : layout) {
      const Vec3 x = s.position + 0.3 * st.unit * Vec3(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
      const ClosestPoint cp = surface->project(x);
      s.position = cp.point;
      s.where = cp.where;
      s.scale *= rng.uniform(0.8, 1.2);
    }
    const auto hoods = det_match(ex, *surface, layout);
    const int S = int(layout.size());
    const Eigen::VectorXi types = layout_types(layout);
    auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd* g) {
      const RowMatX3d q = Eigen::Map<const RowMatX3d>(x.data(), S, 3);
      RowMatX3d gq = RowMatX3d::Zero(S, 3);
      Eigen::VectorXd gs = Eigen::VectorXd::Zero(S);
      const double v = det_objective(ex, hoods, q, x.tail(S), types, g ? &gq : nullptr, g ? &gs : nullptr);
      if (g) {
        g->resize(4 * S);
        g->head(3 * S) = Eigen::Map<const Eigen::VectorXd>(gq.data(), 3 * S);
        g->tail(S) = gs;
      }
      return v;
    };
    Eigen::VectorXd x(4 * S);
    const RowMatX3d q = layout_positions(layout);
    x.head(3 * S) = Eigen::Map<const Eigen::VectorXd>(q.data(), 3 * S);
    x.tail(S) = layout_scales(layout);
    EXPECT_GT(f(x, nullptr), 1.0);
    EXPECT_TRUE(test::gradient_matches(f, x, 1e-6 * st.unit, 1e-6, std::string("DET (6) on ") + shape));
  }
}

TEST(Det, MajorityVote) {
  // Hand-made neighbourhoods: stencil 0 gets votes {type 1: 2, type 0: 1} → 1; stencil 1 a tie
  // {0: 1, 1: 1} while being type 1 → stays 1; stencil 2 a tie while being type 2 → lowest, 0.
  const SurfaceMesh mesh = test::flat_plate(0.1, 0.1, 0.02);
  DetSettings st;
  st.r_N = 0.3;
  Exemplar exm = builtin_exemplar("circles");  // types: element (i + j) even → 0, odd → 1
  const DetExemplar ex(exm, {0, 1}, st);
  int e0 = -1, e1 = -1;  // one element of each type
  for (int m = 0; m < ex.num_elements(); ++m) (ex.stencil_type(m) == 0 ? e0 : e1) = m;
  StencilLayout layout(3);
  layout[0].type = 0;
  layout[1].type = 1;
  layout[2].type = 2;
  std::vector<DetNeighborhood> hoods(2);
  hoods[0].stencil = 0;
  hoods[0].center = e1;
  hoods[0].outputs = {1, 2};
  hoods[0].matches = {e0, e1};
  hoods[1].stencil = 1;
  hoods[1].center = e1;
  hoods[1].outputs = {0, 2};
  hoods[1].matches = {e1, e0};
  // Votes: 0 ← e1 (centre of hood 0), e1 (in hood 1) ; 1 ← e0 (hood 0), e1 (centre of hood 1);
  //        2 ← e1 (hood 0), e0 (hood 1).
  hoods.push_back(hoods[0]);
  hoods[2].stencil = 0;
  hoods[2].center = e0;
  hoods[2].outputs = {};
  hoods[2].matches = {};
  const int changed = det_vote_types(ex, hoods, layout);
  EXPECT_EQ(layout[0].type, 1);
  EXPECT_EQ(layout[1].type, 1);
  EXPECT_EQ(layout[2].type, 0);
  EXPECT_EQ(changed, 2);
}

TEST(Det, GrowthCoversThePlateWithoutCollisionsAndFillsHoles) {
  const SurfaceMesh mesh = test::flat_plate(0.3, 0.2, 0.005);
  const auto surface = make_surface(mesh, 1);
  for (const char* name : {"flowers", "stripes", "circles", "mix"}) {
    DetSettings st;
    st.sigma = 0.08;
    st.unit = st.sigma * 0.04;
    st.symmetry = 1;
    st.safety = 0.2;
    const DetExemplar ex(builtin_exemplar(name), identity_types(builtin_exemplar(name)), st);
    PatternRng rng(8);
    StencilLayout layout;
    const DetGrowthReport rep = det_grow(ex, *surface, layout, rng, DetGrowthOptions{});
    EXPECT_FALSE(rep.capped);
    const double expected = ex.density() * surface->area() / (st.sigma * st.sigma);
    EXPECT_GT(double(layout.size()), 0.75 * expected) << name;
    EXPECT_LT(double(layout.size()), 1.3 * expected) << name;
    const OverlapReport ov = find_overlaps_brute_force(*surface, layout, st.safety);
    EXPECT_FALSE(ov.any()) << name << ": growth inserts only where (1+s) clearances hold";
    // Every point farther than the hole size from the boundary has a stencil nearby.
    const double hole = 1.5 * st.sigma * ex.covering_radius();
    for (int f = 0; f < mesh.num_faces(); f += 7) {
      const Vec3 c = mesh.point(SurfacePoint{f, Vec3::Constant(1.0 / 3)});
      if (surface->boundary_distance(c, hole) < hole) continue;
      double best = INFINITY;
      for (const auto& s : layout) best = std::min(best, (s.position - c).norm());
      EXPECT_LE(best, hole) << name << " face " << f;
    }
    // Hole filling: cut a hole and grow again; the count comes back within 10%.
    const size_t full = layout.size();
    StencilLayout holed;
    for (const auto& s : layout)
      if ((s.position - Vec3(0.15, 0.1, 0)).norm() > 0.05) holed.push_back(s);
    ASSERT_LT(holed.size(), full);
    const DetGrowthReport refill = det_grow(ex, *surface, holed, rng, DetGrowthOptions{});
    EXPECT_GT(refill.added, 0) << name;
    EXPECT_NEAR(double(holed.size()), double(full), 0.1 * full) << name;
    EXPECT_FALSE(find_overlaps_brute_force(*surface, holed, st.safety).any()) << name;
  }
}

}  // namespace
}  // namespace cutwork

// Rim recovery (solvers/conforming/rim_recovery.h) against closed forms: the rim of a hole of
// radius a at the centre of a 20a × 20a plate, in tension (Kirsch) and in bending (Goodier), on
// graded conforming meshes built the way `cutwork verify` builds its levels: level k remeshed at
// L = a/2^k, graded twice along the outline (rim edges L/4, bounded by the 128-gon's sides).
//
// Tension: Kirsch's setup of kirsch_test.cpp (edge loads on both x-edges, a short clamp); the peak
// against Howland's finite-width factor Kt_g = 3.032 at d/W = 0.1.
//
// Bending: pinned along both x-edges under a uniform area load — at the centre M_x = p W²/8 and no
// shear force, so around the hole the far field is two bending moments M1 (x), M2 (y). The plate is
// not infinite (M2/M1 ≈ 0.26 here, and the net section moves the moments by a few per cent), so M1
// and M2 are the least-squares amplitudes of Goodier's field over the faces 2a–3a from the centre,
// where the hole's disturbance is down to a²/r² and the faces' own curvatures are good to 3% RMS.
// Goodier's rim field of a Kirchhoff plate (free edge: M_r = 0, V_r = Q_r + ∂M_rθ/(r∂θ) = 0), for M1
// alone (M2 is the same turned by 90°), c = 2(1 + ν)/(3 + ν):
//     M_θθ(a, θ) = M1 (1 − c cos 2θ),   M_rθ(a, θ) = −2 M1 sin 2θ / (3 + ν),
// and the whole field (derived with sympy from w = w₀ + A ln r + (C/r² + E) cos 2θ) in goodier_unit.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "host/core/error.h"
#include "host/cut/cut_surface.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/conforming/rim_recovery.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/energy_density.h"
#include "solvers/shell/shell_energy.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRadius = 0.01;  // a (m)

enum class Loading { Tension, Bending };

/// One level's run.
struct HoleRun {
  int faces = 0;
  Material material;
  double traction = 0;             ///< N/m (tension)
  std::vector<RimPoint> rim;       ///< the hole's rim points (within 2a of the centre)
  std::vector<RimPoint> all_rim;   ///< every free rim point (the plate's border too)
  std::vector<double> theta;       ///< their angles from +x
  double face_peak = 0;            ///< largest face W touching the hole's rim (J/m²)
  /// Bending: faces 2a–3a from the centre: r, θ, M_θθ, M_rθ (N), from the faces' curvatures.
  std::vector<std::array<double, 4>> ring;
};

double bending_rigidity(const Material& m) {
  return m.youngs_modulus * std::pow(m.thickness, 3) / (12 * (1 - m.poisson_ratio * m.poisson_ratio));
}

HoleRun run_hole(int level, Loading loading, const nlohmann::json& stencil, const RimRecoveryOptions& options = {}) {
  const double a = kRadius, W = 20 * a, L = a / std::pow(2.0, level);
  nlohmann::json doc = builtin_scene_json("plate");
  doc["name"] = "holed-plate";
  doc["mesh"]["params"] = {{"width", W}, {"height", W}};
  doc["mesh"]["edge_length"] = a / 2;
  doc["mesh"]["sim_edge_length"] = W / 4;
  doc["stencils"] = nlohmann::json::array({stencil});
  const double E = doc["material"]["youngs_modulus"].get<double>();
  const double h = doc["material"]["thickness"].get<double>();
  const double nu = doc["material"]["poisson_ratio"].get<double>();
  nlohmann::json left = {{"entity", "vertices"}}, right = left;
  left["x"] = {{"below", -W / 2 + 1e-9}};
  right["x"] = {{"above", W / 2 - 1e-9}};
  HoleRun out;
  if (loading == Loading::Tension) {
    out.traction = E * 1e-5 * h;  // σ∞ = 1e-5 E: linear
    nlohmann::json clamp = left;
    clamp["y"] = {{"above", -0.3 * a}, {"below", 0.3 * a}};
    left["entity"] = right["entity"] = "boundary_edges";
    doc["supports"] = nlohmann::json::array({{{"type", "clamped"}, {"select", clamp}}});
    doc["loads"] = nlohmann::json::array({{{"type", "edge"}, {"force", {-out.traction, 0.0, 0.0}}, {"select", left}},
                                          {{"type", "edge"}, {"force", {out.traction, 0.0, 0.0}}, {"select", right}}});
  } else {
    // p W²/8 = D κ with κ h = 1e-6 at the centre: deflection 1e-3 h, linear.
    const double D = E * h * h * h / (12 * (1 - nu * nu));
    const double p = 8 * D * (1e-6 / h) / (W * W);
    doc["supports"] = nlohmann::json::array({{{"type", "pinned"}, {"select", left}}, {{"type", "pinned"}, {"select", right}}});
    doc["loads"] = nlohmann::json::array({{{"type", "area"}, {"force", {0.0, 0.0, -p}}, {"select", {{"entity", "faces"}}}}});
  }
  const Scene scene = parse_scene(doc, "test:holed-plate");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  StencilParams hole;
  hole.scale = a;
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), std::vector{hole});
  RemeshOptions ro{L, 5, 30.0};
  ro.grading.depth = 2;
  ro.grading.elements_across = 3;
  ro.grading.feature_scale = std::pow(2.0, level);
  ro.grading.rings = 2;
  const RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, ro);
  const SurfaceMesh mesh(r.vertices, r.faces, "holed-plate");
  const ShellModel model(mesh, scene.material, resolve_load_case(scene, mesh), MechanicsSettings{});
  EquilibriumSolver solver(model);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_faces());
  solver.solve(ones);

  out.faces = mesh.num_faces();
  out.material = scene.material;
  const RowMatX3d& X = mesh.vertices();
  auto on_hole = [&](int v) { return mesh.is_boundary_vertex()[std::size_t(v)] && X.row(v).norm() < 2 * a; };
  out.all_rim = recover_rim(model, solver.positions(), options);
  for (const RimPoint& p : out.all_rim) {
    if (!on_hole(p.vertex)) continue;
    out.rim.push_back(p);
    out.theta.push_back(std::atan2(p.position.y(), p.position.x()));
  }
  const Eigen::VectorXd W_face = energy_density(model, solver.positions(), ones);
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (on_hole(mesh.faces()(f, k))) out.face_peak = std::max(out.face_peak, W_face(f));
  if (loading == Loading::Bending) {
    const double D = bending_rigidity(scene.material);
    for (const ShellBend& bend : model.bends()) {
      const int f = bend.face;
      const Vec3 X0 = X.row(mesh.faces()(f, 0)), X1 = X.row(mesh.faces()(f, 1)), X2 = X.row(mesh.faces()(f, 2));
      const Vec3 c = (X0 + X1 + X2) / 3;
      if (c.norm() < 2 * a || c.norm() > 3 * a) continue;
      // k in the face's rest frame (b1 along X1 − X0, b2 = n × b1), read along e_r and e_θ.
      const Vec3 b1 = (X1 - X0).normalized(), b2 = (X1 - X0).cross(X2 - X0).normalized().cross(b1);
      const Vec3 k = shape_operator_strain(bend_positions(bend, solver.positions()), bend.rest);
      Eigen::Matrix2d K;
      K << k(0), k(2), k(2), k(1);
      const double th = std::atan2(c.y(), c.x());
      const Eigen::Vector2d er(std::cos(th) * b1.x() + std::sin(th) * b1.y(), std::cos(th) * b2.x() + std::sin(th) * b2.y());
      const Eigen::Vector2d et(-std::sin(th) * b1.x() + std::cos(th) * b1.y(),
                               -std::sin(th) * b2.x() + std::cos(th) * b2.y());
      out.ring.push_back({c.norm(), th, D * (et.dot(K * et) + nu * er.dot(K * er)), D * (1 - nu) * er.dot(K * et)});
    }
  }
  return out;
}

const nlohmann::json kCircle = {{"name", "circle"}, {"kind", "circle"}, {"params", {{"segments", 128}}}};

/// Goodier's field for far-field M = 1 along x: {M_θθ, M_rθ} at (r, θ), hole radius a.
std::array<double, 2> goodier_unit(double r, double th, double a, double nu) {
  const double c = std::cos(2 * th), s2 = std::sin(2 * th), a2 = a * a, a4 = a2 * a2, r2 = r * r, r4 = r2 * r2;
  const double Mt = (3 * a4 * (1 - nu) * c + a2 * r2 * (3 + nu - 4 * c) + r4 * (3 + nu - (3 + nu) * c)) / (2 * r4 * (3 + nu));
  const double Mrt = (-3 * a4 * (1 - nu) + 2 * a2 * r2 * (1 - nu) - r4 * (3 + nu)) * s2 / (2 * r4 * (3 + nu));
  return {Mt, Mrt};
}

/// Goodier's field for far-field moments (M1 along x, M2 along y).
struct Goodier {
  double M1 = 0, M2 = 0, nu = 0;
  std::array<double, 2> at(double r, double th) const {
    const auto x = goodier_unit(r, th, kRadius, nu), y = goodier_unit(r, th - kPi / 2, kRadius, nu);
    return {M1 * x[0] + M2 * y[0], M1 * x[1] + M2 * y[1]};
  }
};

/// M1, M2 by least squares over the ring faces' M_θθ and M_rθ.
Goodier fit_far_field(const HoleRun& run) {
  const double nu = run.material.poisson_ratio;
  Eigen::MatrixXd A(2 * run.ring.size(), 2);
  Eigen::VectorXd b(2 * run.ring.size());
  for (std::size_t i = 0; i < run.ring.size(); ++i) {
    const auto& f = run.ring[i];
    const auto x = goodier_unit(f[0], f[1], kRadius, nu), y = goodier_unit(f[0], f[1] - kPi / 2, kRadius, nu);
    A.row(Eigen::Index(2 * i)) << x[0], y[0];
    A.row(Eigen::Index(2 * i + 1)) << x[1], y[1];
    b(Eigen::Index(2 * i)) = f[2];
    b(Eigen::Index(2 * i + 1)) = f[3];
  }
  const Eigen::Vector2d m = A.colPivHouseholderQr().solve(b);
  return {m(0), m(1), nu};
}

TEST(RimRecovery, GoodiersFieldMeetsTheFreeEdgeConditionsAndTheKnownFactor) {
  // The closed form itself: (5 + 3ν)/(3 + ν) at θ = 90°, (1 − ν)/(3 + ν) at 0°, and far away the
  // uniform field (M_θθ = sin²θ, M_rθ = −sin θ cos θ for M_x = 1).
  for (double nu : {0.0, 0.3, 0.4}) {
    EXPECT_NEAR(goodier_unit(kRadius, kPi / 2, kRadius, nu)[0], (5 + 3 * nu) / (3 + nu), 1e-12);
    EXPECT_NEAR(goodier_unit(kRadius, 0, kRadius, nu)[0], (1 - nu) / (3 + nu), 1e-12);
    EXPECT_NEAR(goodier_unit(kRadius, kPi / 4, kRadius, nu)[1], -2 / (3 + nu), 1e-12);
    const double far = 1e4 * kRadius, th = 0.3;
    EXPECT_NEAR(goodier_unit(far, th, kRadius, nu)[0], std::pow(std::sin(th), 2), 1e-6);
    EXPECT_NEAR(goodier_unit(far, th, kRadius, nu)[1], -std::sin(th) * std::cos(th), 1e-6);
  }
}

TEST(RimRecovery, KirschRimStressConvergesToHowlandsFactorAndBeatsTheFacePeak) {
  const double kt = (2 + std::pow(0.9, 3)) / 0.9;  // Howland / Heywood at d/W = 0.1: 3.032
  std::vector<double> peak_error, rms;
  for (int level = 0; level < 3; ++level) {
    const HoleRun run = run_hole(level, Loading::Tension, kCircle);
    ASSERT_GE(run.rim.size(), 32u);
    const double E = run.material.youngs_modulus, h = run.material.thickness, sigma = run.traction / h;
    double peak = 0, sq = 0;
    for (std::size_t i = 0; i < run.rim.size(); ++i) {
      const double s = E * run.rim[i].strain / sigma;
      peak = std::max(peak, s);
      sq += std::pow(s - (1 - 2 * std::cos(2 * run.theta[i])), 2);
      EXPECT_EQ(run.rim[i].fit_degree, 3);
      EXPECT_FALSE(run.rim[i].singular);
    }
    peak_error.push_back(peak / kt - 1);
    rms.push_back(std::sqrt(sq / double(run.rim.size())) / 3);
    const double W_ref = 0.5 * std::pow(kt * sigma, 2) * h / E;
    const RimPeak rp = rim_peak(run.rim);
    std::cout << "level " << level << ": " << run.faces << " faces, " << run.rim.size()
              << " rim points: peak sigma / Kt_g " << peak / kt << ", RMS / 3 " << rms.back() << "; W peak / ref "
              << rp.energy_density / W_ref << ", largest face W / ref " << run.face_peak / W_ref << "\n";
    if (level == 2) {
      // The recovered W is the peak's: within 3% in stress (6% in W), and closer than the faces.
      EXPECT_NEAR(rp.energy_density / W_ref, 1, 0.06);
      EXPECT_LT(std::abs(rp.energy_density / W_ref - 1), std::abs(run.face_peak / W_ref - 1));
    }
  }
  EXPECT_LT(std::abs(peak_error[2]), 0.03);
  EXPECT_LT(rms[2], 0.03);
  EXPECT_LT(rms[2], rms[1]);
  EXPECT_LT(rms[1], rms[0]);
}

// A smooth outline comes as a polygon: a 16-gon hole (22.5° turns, segments 0.39a) in tension.
// Once the rims are finer than the segments the polygon's vertices show, each a re-entrant corner
// of 22.5° with a (weakly) singular stress: read over the mesh alone, the peak grows with every
// level. Read over at least one segment (outline_radius, the default) it settles on the smooth
// field the polygon stands for.
TEST(RimRecovery, APolygonalOutlineIsReadOverItsSegmentsNotItsCorners) {
  const nlohmann::json polygon = {{"name", "circle"}, {"kind", "circle"}, {"params", {{"segments", 16}}}};
  RimRecoveryOptions mesh_only;
  mesh_only.outline_radius = 0;
  std::vector<double> smooth, raw, smooth_rms;
  for (int level = 1; level <= 3; ++level) {
    const HoleRun run = run_hole(level, Loading::Tension, polygon);
    const HoleRun local = run_hole(level, Loading::Tension, polygon, mesh_only);
    const double E = run.material.youngs_modulus, sigma = run.traction / run.material.thickness;
    auto peak = [&](const HoleRun& r) {
      double p = 0;
      for (const RimPoint& q : r.rim) p = std::max(p, E * q.strain / sigma);
      return p;
    };
    double sq = 0;
    for (std::size_t i = 0; i < run.rim.size(); ++i)
      sq += std::pow(E * run.rim[i].strain / sigma - (1 - 2 * std::cos(2 * run.theta[i])), 2);
    smooth.push_back(peak(run));
    raw.push_back(peak(local));
    smooth_rms.push_back(std::sqrt(sq / double(run.rim.size())) / 3);
    std::cout << "level " << level << ": " << run.faces << " faces, " << run.rim.size() << " rim points: peak sigma / "
              << "sigma_inf over segments " << smooth.back() << " (RMS against Kirsch / 3: " << smooth_rms.back()
              << "), over the mesh alone " << raw.back() << "\n";
  }
  // Measured (levels 1, 2, 3: rims at a/8, a/16, a/32): over the segments 2.907, 2.935, 2.950 σ∞
  // (RMS against Kirsch's circle 3.0%, 1.6%, 1.2%: the 16-gon is nearly the circle), over the mesh
  // alone 2.795, 3.031, 3.544 (+8%, then +17%).
  EXPECT_LT(std::abs(smooth[2] / smooth[1] - 1), 0.02);
  EXPECT_GT(raw[2] / raw[1] - 1, 0.05);
  EXPECT_GT(raw[2], smooth[2]);
}

TEST(RimRecovery, GoodierRimMomentConvergesInBendingWhereTheFacesDoNot) {
  std::vector<double> bias, rms, twist_rms;
  for (int level = 0; level < 3; ++level) {
    const HoleRun run = run_hole(level, Loading::Bending, kCircle);
    const Goodier g = fit_far_field(run);
    const double D = bending_rigidity(run.material), nu = run.material.poisson_ratio;
    const double scale = g.at(kRadius, kPi / 2)[0];  // the peak M_θθ
    auto W_of = [&](double Mt, double Mrt) { return 0.5 * Mt * Mt / (D * (1 - nu * nu)) + Mrt * Mrt / (D * (1 - nu)); };
    double W_ref = 0;
    for (int i = 0; i < 3600; ++i) {
      const auto m = g.at(kRadius, 2 * kPi * i / 3600);
      W_ref = std::max(W_ref, W_of(m[0], m[1]));
    }
    double b = 0, sq = 0, tq = 0;
    for (std::size_t i = 0; i < run.rim.size(); ++i) {
      const auto m = g.at(kRadius, run.theta[i]);
      const double Mt = D * (1 - nu * nu) * run.rim[i].curvature, Mrt = D * (1 - nu) * run.rim[i].twist;
      b += (std::abs(Mt) - std::abs(m[0])) / scale;
      sq += std::pow((std::abs(Mt) - std::abs(m[0])) / scale, 2);
      tq += std::pow((std::abs(Mrt) - std::abs(m[1])) / scale, 2);
    }
    const double n = double(run.rim.size());
    bias.push_back(b / n);
    rms.push_back(std::sqrt(sq / n));
    twist_rms.push_back(std::sqrt(tq / n));
    const RimPeak rp = rim_peak(run.rim);
    std::cout << "level " << level << ": " << run.faces << " faces, far field M1 " << g.M1 << ", M2 " << g.M2
              << "; rim M_tt bias " << bias.back() << ", RMS " << rms.back() << ", M_rt RMS " << twist_rms.back()
              << "; W peak / ref " << rp.energy_density / W_ref << ", largest face W / ref " << run.face_peak / W_ref
              << "\n";
    if (level > 0) {
      EXPECT_LT(std::abs(rp.energy_density / W_ref - 1), std::abs(run.face_peak / W_ref - 1)) << "level " << level;
      EXPECT_LT(std::abs(bias[std::size_t(level)]), std::abs(bias[std::size_t(level) - 1])) << "level " << level;
      EXPECT_LT(rms[std::size_t(level)], rms[std::size_t(level) - 1]) << "level " << level;
    }
    if (level == 2) {
      EXPECT_NEAR(rp.energy_density / W_ref, 1, 0.1);
    }
  }
  // Measured (smoothed along the rim): bias −0.189, −0.098, −0.031 (first order and better), RMS
  // 0.198, 0.100, 0.034; the twist's RMS 0.047, 0.016, 0.009; W peak / closed form 0.66, 0.83,
  // 0.97 where the largest face W reads 1.63, 1.77, 1.48.
  EXPECT_LT(std::abs(bias[2]), 0.05);
  EXPECT_LT(rms[2], 0.06);
  EXPECT_LT(twist_rms[2], 0.03);
}

TEST(RimRecovery, StarTipsAreSingularAndLeftOutOfThePeak) {
  const nlohmann::json star = {{"name", "star"}, {"kind", "star"}, {"params", {{"points", 5}, {"inner_ratio", 0.5}}}};
  RimRecoveryOptions options;
  options.corner_radius = 0.25 * kRadius;
  const HoleRun run = run_hole(0, Loading::Tension, star, options);
  int tips = 0, singular = 0;
  for (const RimPoint& p : run.rim) {
    singular += p.singular;
    if (p.material_angle > 180 + options.corner_angle) {
      ++tips;
      EXPECT_TRUE(p.singular);
      EXPECT_NEAR(p.position.norm(), kRadius, 1e-9);  // a tip: on the star's outer radius
    }
  }
  EXPECT_EQ(tips, 5);
  EXPECT_GT(singular, tips);  // their neighbours within the radius too
  const RimPeak rp = rim_peak(run.rim);
  ASSERT_GE(rp.index, 0);
  EXPECT_FALSE(run.rim[std::size_t(rp.index)].singular);
  double tip_max = 0;
  for (const RimPoint& p : run.rim)
    if (p.singular) tip_max = std::max(tip_max, p.energy_density);
  EXPECT_GT(tip_max, rp.energy_density);  // what was left out is the larger: the tips' spikes
  // Left out for the corners, not for a support (the plate's supports are far from the hole):
  // `at_corner` says so, and verify reports their largest W as the level's corner_peak.
  for (const RimPoint& p : run.rim) {
    if (p.position.norm() < 2 * kRadius) {
      EXPECT_EQ(p.at_corner, p.singular) << p.position.transpose();
    }
  }
}

/// The built-in plate on its simulation mesh: free rims on three sides, a clamp on the fourth.
struct BuiltInPlate {
  Scene scene = parse_scene(builtin_scene_json("plate"), "test:plate");
  SceneMeshes meshes = build_scene_meshes(scene);
  ShellModel model{meshes.sim, scene.material, resolve_load_case(scene, meshes.sim), MechanicsSettings{}};
};

TEST(RimRecovery, WhereASupportEndsTheRimIsSingular) {
  // Kirsch's plate is held by a clamp over 0.6a of its left edge (x = −10a): the left edge's free
  // points within the radius of the clamp's two ends are singular, the rest of the border is not.
  RimRecoveryOptions options;
  options.support_radius = kRadius;
  const HoleRun run = run_hole(0, Loading::Tension, kCircle, options);
  int near = 0, far = 0;
  for (const RimPoint& p : run.all_rim) {
    const double to_end = std::min((p.position - Vec3(-10 * kRadius, 0.3 * kRadius, 0)).norm(),
                                   (p.position - Vec3(-10 * kRadius, -0.3 * kRadius, 0)).norm());
    if (to_end < 0.9 * kRadius) {
      EXPECT_TRUE(p.singular) << p.position.transpose();
      ++near;
    } else if (to_end > 1.1 * kRadius + 1e-3) {  // the clamp's ends sit within a mesh edge of ±0.3a
      EXPECT_FALSE(p.singular) << p.position.transpose();
      ++far;
    }
  }
  EXPECT_GE(near, 2);
  EXPECT_GT(far, 100);
}

// A corner cut as several small turns: a 24-gon hole of radius 10 mm turns into the material by
// 15° at each vertex, 2.6 mm apart. Vertex by vertex no corner passes 30°; summed over a window
// of 2.2 segments, three vertices turn 45° and every polygon vertex is a corner (an outline of
// radius 10 mm read at a 5.8 mm scale). The plate's own corners turn out of the material.
TEST(RimRecovery, TurnsCloseTogetherAreOneCorner) {
  nlohmann::json doc = builtin_scene_json("plate");
  doc["stencils"] = nlohmann::json::array({{{"name", "p"}, {"kind", "circle"}, {"params", {{"segments", 24}}}}});
  const Scene scene = parse_scene(doc, "test:24-gon");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  StencilParams hole;
  hole.scale = 0.01;
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), std::vector{hole});
  const double segment = 2 * kPi * 0.01 / 24;
  auto on_hole = [](const std::vector<Vec3>& corners) {
    return std::count_if(corners.begin(), corners.end(), [](const Vec3& c) { return c.norm() < 0.02; });
  };
  EXPECT_EQ(singular_corners(cut.vertices, cut.faces, 30).size(), 0u);
  EXPECT_EQ(on_hole(singular_corners(cut.vertices, cut.faces, 30, 0.5 * segment)), 0);
  const std::vector<Vec3> wide = singular_corners(cut.vertices, cut.faces, 30, 2.2 * segment);
  EXPECT_GE(on_hole(wide), 24);
  EXPECT_EQ(on_hole(wide), std::ptrdiff_t(wide.size()));  // none on the plate's border
  // Every polygon vertex (at the radius; the points where the outline crosses the base mesh's edges
  // lie inside it) is among them.
  EXPECT_GE(std::count_if(wide.begin(), wide.end(), [](const Vec3& c) { return std::abs(c.norm() - 0.01) < 1e-6; }), 24);
}

// The table's free border runs straight along its top and around the fillets into the legs. The
// fillets' polygonal faces turn the border by a fraction of a degree at each vertex: not outline
// vertices, or the whole top edge between them would count as one segment and its patches would
// span the top, the fillets and the legs (read: 1000 J/m² where the faces read 4). Uncut, under its
// load: the rim along the top edge reads within a small factor of the faces touching it.
TEST(RimRecovery, ACurvedShellsBorderIsNoPolygonalOutline) {
  // Remeshed at 12 mm as a conforming level is: the fillets' border vertices then turn by 0.2°.
  const Scene scene = parse_scene(builtin_scene_json("table"), "test:table");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const RemeshedMesh r = remesh_isotropic(meshes.base.vertices(), meshes.base.faces(), {0.012, 5, 30.0});
  const SurfaceMesh mesh(r.vertices, r.faces, "table at 12 mm");
  const ShellModel model(mesh, scene.material, resolve_load_case(scene, mesh), MechanicsSettings{});
  EquilibriumSolver solver(model);
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(mesh.num_faces());
  solver.solve(ones);
  const std::vector<RimPoint> rim = recover_rim(model, solver.positions());
  const Eigen::VectorXd W = energy_density(model, solver.positions(), ones);
  double rim_top = 0, face_top = 0, widest = 0;
  for (const RimPoint& p : rim) {
    if (p.position.z() < 0.69) continue;  // the top edge
    rim_top = std::max(rim_top, p.energy_density);
    widest = std::max(widest, p.patch_radius);
  }
  for (int f = 0; f < mesh.num_faces(); ++f) {
    bool top_rim = false;
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.faces()(f, k);
      top_rim = top_rim || (mesh.is_boundary_vertex()[std::size_t(v)] && mesh.vertices()(v, 2) > 0.69);
    }
    if (top_rim) face_top = std::max(face_top, W(f));
  }
  ASSERT_GT(face_top, 0);
  std::cout << "table top edge: rim peak " << rim_top << " J/m², faces " << face_top << " J/m², widest patch "
            << widest << " m\n";
  EXPECT_LT(widest, 0.1);
  EXPECT_LT(rim_top, 3 * face_top);
}

TEST(RimRecovery, RejectsBadOptions) {
  const BuiltInPlate plate;
  const ShellModel& model = plate.model;
  const RowMatX3d& X = plate.meshes.sim.vertices();
  EXPECT_NO_THROW(recover_rim(model, X));
  for (auto bad : {+[](RimRecoveryOptions& o) { o.degree = 1; }, +[](RimRecoveryOptions& o) { o.degree = 5; },
                   +[](RimRecoveryOptions& o) { o.patch_radius = 0; },
                   +[](RimRecoveryOptions& o) { o.patch_radius = NAN; },
                   +[](RimRecoveryOptions& o) { o.corner_angle = 0; },
                   +[](RimRecoveryOptions& o) { o.corner_angle = 180; },
                   +[](RimRecoveryOptions& o) { o.corner_radius = -1; },
                   +[](RimRecoveryOptions& o) { o.support_radius = NAN; },
                   +[](RimRecoveryOptions& o) { o.nodes_per_coefficient = 1.4; },
                   +[](RimRecoveryOptions& o) { o.nodes_per_coefficient = 11; },
                   +[](RimRecoveryOptions& o) { o.outline_radius = -0.1; },
                   +[](RimRecoveryOptions& o) { o.outline_radius = NAN; },
                   +[](RimRecoveryOptions& o) { o.outline_radius = 5; }}) {
    RimRecoveryOptions o;
    bad(o);
    EXPECT_THROW(recover_rim(model, X, o), InputError);
  }
  EXPECT_THROW(recover_rim(model, X.topRows(3)), InputError);
  // At rest every rim point reads zero.
  for (const RimPoint& p : recover_rim(model, X)) EXPECT_NEAR(p.energy_density, 0, 1e-18);
}

TEST(RimRecovery, RigidMotionsReadNothingAndAStretchReadsItsGreenStrain) {
  const BuiltInPlate plate;
  const ShellModel& model = plate.model;
  const RowMatX3d& X = plate.meshes.sim.vertices();
  // A finite rotation (0.4 rad) and a translation: no strain, no curvature (a linear strain would
  // read −(1 − cos 0.4) = −0.079 along every rim).
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  RowMatX3d moved = X * R.transpose();
  moved.rowwise() += Eigen::RowVector3d(0.1, -0.2, 0.3);
  const std::vector<RimPoint> rim = recover_rim(model, moved);
  ASSERT_FALSE(rim.empty());
  for (const RimPoint& p : rim) {
    EXPECT_NEAR(p.strain, 0, 1e-12);
    EXPECT_NEAR(p.curvature, 0, 1e-9);
    EXPECT_NEAR(p.twist, 0, 1e-9);
  }
  // Stretched by 1% along x, then rotated: ε_tt = ½((1.01 t_x)² + t_y² − 1), t the rim's tangent;
  // bent into a cylinder of radius ρ about the y axis: κ_tt = t_x²/ρ.
  RowMatX3d stretched = X;
  stretched.col(0) *= 1.01;
  const double rho = 2.0;
  RowMatX3d bent = X;
  for (Eigen::Index i = 0; i < X.rows(); ++i) {
    const double phi = X(i, 0) / rho;
    bent(i, 0) = rho * std::sin(phi);
    bent(i, 2) = rho * (1 - std::cos(phi));
  }
  const std::vector<RimPoint> s_rim = recover_rim(model, stretched * R.transpose());
  const std::vector<RimPoint> b_rim = recover_rim(model, bent);
  for (std::size_t i = 0; i < rim.size(); ++i) {
    const Vec3 t = s_rim[i].tangent;
    EXPECT_NEAR(s_rim[i].strain, 0.5 * (std::pow(1.01 * t.x(), 2) + t.y() * t.y() - 1), 1e-9);
    EXPECT_NEAR(b_rim[i].strain, 0, 1e-6);  // the cylinder is developable: only a cubic fit's remainder
    EXPECT_NEAR(std::abs(b_rim[i].curvature), t.x() * t.x() / rho, 2e-3 / rho);
  }
}

}  // namespace
}  // namespace cutwork::solvers

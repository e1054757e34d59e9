// The narrow ligament between two holes (issue 21 item 5), on conforming meshes built as the
// conforming verification builds them: the holes cut into a flat membrane (host/cut), the surface
// remeshed with grading along the outlines and a focus on the neck (host/mesh/isotropic_remesh),
// supports and loads resolved from a scene, solved as a shell at α = 1, the rim's energy density
// recovered as verify recovers it (solvers/conforming/rim_recovery.h) and, as a second measure, the
// free rim edges' tangential strains (solvers/homogenise/free_edge_strain.h).
//
// Setting. Holes of radius R and ρ_b (240-gons) with a ligament w between them on the x axis, in a
// 24R square plate pulled along y (perpendicular to the line of centres: the neck is pulled along
// its length) by σ∞ on both edges, held by a short clamp at the middle of one. Level-0 edge R/4,
// two grading passes, then focus passes about the neck down to w/10 and finer.
//
// What is checked:
//  - the equal pairs' neck stress over σ∞ is the two-hole table of solvers/objective/ligament_peak.h
//    (the table is this measurement: 1024-gons and finer meshes there; 5.70, 11.58 here against
//    5.71 and 11.59), and the two measures agree; bent, the neck's moment over M∞ is the bending
//    table's (4.08 at x = 4);
//  - an unequal pair (ρ_b = 2R at w = R/8): K_σ = 13.13, which the rule reads as 11.8 at
//    x = S²/(R_h w) (−10%); read at x = R_h/w, as the neck's curvature alone would say, it is 9.4:
//    the pair's size matters, not only the neck's shape. Bent, the same pair's neck moment is
//    6.52, which the bending table reads at x_b = R_h/w as 6.30 (−3.4%) and at x as 7.77: there the
//    neck's shape alone sets it;
//  - a 1024-gon pair reads as the 240-gons: the rim recovery's outline segments end where a curve
//    sampled finer than 1° per vertex has turned by 1° (rim_recovery.h).
// Each run takes 3–5 s (30k–45k triangles). It fails where it should: without the focus passes
// (the grading alone: the neck's rim at w/9.5 at x = 4) the recovered neck reads 5.51 (−3.5%) and
// the edges 5.78; both checks fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "host/cut/cut_surface.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/conforming/rim_recovery.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/homogenise/free_edge_strain.h"
#include "solvers/objective/ligament_peak.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {
namespace {

struct NeckRun {
  int faces = 0;
  double recovered = 0;  ///< √(W/W∞) of the recovered rim peak within the neck's window
  double edges = 0;      ///< the largest rim edge stress over σ∞ in the same window
};

/// Holes of radius R and Rb with a ligament w between them, pulled across the line of centres or
/// (`bending`) bent about it: a cantilever clamped along the edge y = −12R with a transverse edge
/// load on y = +12R, whose moment at the holes is M∞ (surface strain 1e-5).
NeckRun run_neck(double R, double Rb, double w, int focus_depth, bool bending = false, int segments = 240) {
  const double W = 24 * R;
  nlohmann::json doc = builtin_scene_json("plate");
  doc["name"] = "two-holes";
  doc["mesh"]["params"] = {{"width", W}, {"height", W}};
  doc["mesh"]["edge_length"] = R / 4;
  doc["mesh"]["sim_edge_length"] = W / 4;  // unused
  doc["stencils"] =
      nlohmann::json::array({{{"name", "circle"}, {"kind", "circle"}, {"params", {{"segments", segments}}}}});
  const double E = doc["material"]["youngs_modulus"].get<double>();
  const double t = doc["material"]["thickness"].get<double>();
  const double traction = E * 1e-5 * t;  // σ∞ = E · 1e-5: linear
  const double M = E * 1e-5 * t * t / 6;  // N m/m: M∞ at y = 0 from the edge load q at y = W/2
  const double q = 2 * M / W;
  nlohmann::json clamp = {{"entity", "vertices"}};
  clamp["y"] = {{"below", -W / 2 + 1e-9}};
  if (!bending) clamp["x"] = {{"above", -0.6 * R}, {"below", 0.6 * R}};
  doc["supports"] = nlohmann::json::array({{{"type", "clamped"}, {"select", clamp}}});
  nlohmann::json low = {{"entity", "boundary_edges"}}, high = low;
  low["y"] = {{"below", -W / 2 + 1e-9}};
  high["y"] = {{"above", W / 2 - 1e-9}};
  doc["loads"] = nlohmann::json::array({{{"type", "edge"}, {"force", {0.0, -traction, 0.0}}, {"select", low}},
                                        {{"type", "edge"}, {"force", {0.0, traction, 0.0}}, {"select", high}}});
  if (bending) doc["loads"] = nlohmann::json::array({{{"type", "edge"}, {"force", {0.0, 0.0, q}}, {"select", high}}});
  const Scene scene = parse_scene(doc, "test:two-holes");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  StencilParams a, b;
  a.scale = R;
  a.position = Vec3(-(R + w / 2), 0, 0);
  b.scale = Rb;
  b.position = Vec3(Rb + w / 2, 0, 0);
  const std::vector<StencilParams> stencils{a, b};
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), stencils);
  RemeshOptions o{R / 4, 5, 30.0};
  o.grading.depth = 2;
  o.grading.focus = {Vec3::Zero()};
  o.grading.focus_radius = 1.5 * std::sqrt(R * w) + w;
  o.grading.focus_depth = focus_depth;
  const RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, o);
  const SurfaceMesh mesh(r.vertices, r.faces, "two-holes");
  const LoadCase lc = resolve_load_case(scene, mesh);
  const ShellModel model(mesh, scene.material, lc, MechanicsSettings{});
  EquilibriumSolver solver(model);
  solver.solve(Eigen::VectorXd::Ones(mesh.num_faces()));

  NeckRun out;
  out.faces = mesh.num_faces();
  // The far field's energy density: uniaxial tension, or uniaxial bending (M_tt²/(2 D (1 − ν²))).
  const double sigma_inf = traction / t;
  const double W_inf = bending ? 6 * M * M / (E * t * t * t) : traction * traction / (2 * E * t);
  const double window = 4 * w + std::sqrt(R * w);
  const RowMatX3d& X = mesh.vertices();
  const std::vector<RimPoint> rim = recover_rim(model, X + solver.displacements());
  const RimPeak peak = rim_peak_near(rim, {Vec3::Zero()}, window);
  out.recovered = std::sqrt(peak.energy_density / W_inf);
  if (std::getenv("NECK_DEBUG"))
    for (const RimPoint& p : rim)
      if (p.position.norm() < window)
        std::cout << "rim " << p.position.transpose() << " r " << p.patch_radius << " nodes " << p.patch_nodes
                  << " angle " << p.material_angle << " K " << std::sqrt(p.energy_density / W_inf) << "\n";
  if (bending) return out;
  for (const FreeEdgeStrain& e : free_edge_strains(X, mesh.faces(), solver.displacements())) {
    const Vec3 mid = 0.5 * (X.row(e.a) + X.row(e.b)).transpose();
    if (mid.norm() < window) out.edges = std::max(out.edges, E * e.strain / sigma_inf);
  }
  return out;
}

TEST(Ligament, AnEqualPairsNeckStressIsTheTwoHoleTable) {
  const double R = 0.01;
  for (const auto& [x, focus] : {std::pair{4.0, 2}, std::pair{16.0, 3}}) {
    const NeckRun run = run_neck(R, R, R / x, focus);
    const double table = two_hole_concentration(x);
    std::cout << "x = R/w = " << x << ": " << run.faces << " faces, neck K recovered " << run.recovered
              << ", from the rim edges " << run.edges << ", table " << table << "\n";
    EXPECT_NEAR(run.recovered, table, 0.02 * table) << x;
    EXPECT_NEAR(run.edges, run.recovered, 0.02 * run.recovered) << x;
  }
}

TEST(Ligament, AFinelySegmentedCircleReadsAsTheCircle) {
  const double R = 0.01, x = 4;
  const NeckRun run = run_neck(R, R, R / x, 2, false, 1024);
  const double table = two_hole_concentration(x);
  std::cout << "1024-gons, x = R/w = " << x << ": " << run.faces << " faces, neck K recovered " << run.recovered
            << ", from the rim edges " << run.edges << ", table " << table << "\n";
  EXPECT_NEAR(run.recovered, table, 0.02 * table);
  EXPECT_NEAR(run.edges, run.recovered, 0.02 * run.recovered);
}

TEST(Ligament, ABentNeckIsTheBendingTable) {
  const double R = 0.01, x = 4;
  const NeckRun run = run_neck(R, R, R / x, 3, true);
  const double table = two_hole_bending_concentration(x);
  std::cout << "bending, x = R/w = " << x << ": " << run.faces << " faces, neck M_tt/M_inf " << run.recovered
            << ", table " << table << "\n";
  EXPECT_NEAR(run.recovered, table, 0.02 * table);
  // Above the single hole's (Goodier) by more than the membrane's neck is above Kirsch's.
  EXPECT_GT(run.recovered / two_hole_bending_concentration(0), two_hole_concentration(x) / 3);
}

TEST(Ligament, AnUnequalPairIsReadAtItsPairParameter) {
  const double R = 0.01, w = R / 8;
  const NeckRun run = run_neck(R, 2 * R, w, 3);
  Ligament l;
  l.width = w;
  l.radius_a = l.size_a = R;
  l.radius_b = l.size_b = 2 * R;
  const double rule = two_hole_concentration(pair_parameter(l));
  const double neck_only = two_hole_concentration(l.neck_radius() / w);
  std::cout << "2:1 pair at w = R/8: " << run.faces << " faces, neck K recovered " << run.recovered << ", edges "
            << run.edges << "; the rule reads " << rule << ", the neck's curvature alone " << neck_only << "\n";
  EXPECT_NEAR(run.edges, run.recovered, 0.02 * run.recovered);
  EXPECT_NEAR(rule, run.recovered, 0.11 * run.recovered);
  EXPECT_LT(neck_only, 0.75 * run.recovered);
}

TEST(Ligament, AnUnequalPairBentIsReadAtItsNecksShape) {
  const double R = 0.01, w = R / 8;
  const NeckRun run = run_neck(R, 2 * R, w, 3, true);
  Ligament l;
  l.width = w;
  l.radius_a = l.size_a = R;
  l.radius_b = l.size_b = 2 * R;
  const double rule = two_hole_bending_concentration(bending_pair_parameter(l));
  const double membrane_x = two_hole_bending_concentration(pair_parameter(l));
  std::cout << "2:1 pair bent, w = R/8: " << run.faces << " faces, neck M_tt/M_inf " << run.recovered
            << "; the rule reads " << rule << " (x_b = R_h/w), the membrane's x would read " << membrane_x << "\n";
  // Measured 6.522 (6.521 with a fourth focus pass); read 6.30 at x_b, 7.77 at x.
  EXPECT_NEAR(rule, run.recovered, 0.05 * run.recovered);
  EXPECT_GT(membrane_x, 1.15 * run.recovered);
}

}  // namespace
}  // namespace cutwork::solvers

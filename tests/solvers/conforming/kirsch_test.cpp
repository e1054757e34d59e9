// Kirsch (issue 21, "Tests that can fail"): a small circular hole in a large flat membrane under
// uniaxial tension, built the way the conforming verification builds its reference — the hole cut
// into the plate's surface (host/cut), the surface remeshed uniformly (host/mesh/isotropic_remesh),
// supports and loads resolved from a scene, solved as a shell with α = 1 — and the hoop stress
// along the rim recovered from the rim's edges (solvers/homogenise/free_edge_strain.h).
//
// Reference. Kirsch's infinite sheet: σ_θθ(a, θ) = σ∞ (1 − 2 cos 2θ), θ from the load axis: 3σ∞ at
// θ = ±90°, −σ∞ at θ = 0°, 180°. The plate is a W × W square with W = 20a (d/W = 0.1), so the
// peak is compared with the finite-width (Howland, Heywood's fit) gross-stress factor
// Kt_g = (2 + (1 − d/W)³)/(1 − d/W) = 3.032, not with 3 (1.1% apart).
//
// Loading. Both opposite edges carry the edge load, −x on the left and +x on the right
// (σ∞ = traction / thickness, strain 1e-5: linear), and the plate is held by a clamp over only the
// middle 0.6a of the left edge: the loads balance, and the clamp only removes the rigid motions.
// A clamp along the whole left edge (the plate pulled against it) stops the Poisson contraction
// there, 10a from the hole: measured at a/8 (64-gon), that raised the peak to 3.07 (+1.2% over
// Kt_g) and left the θ = 180° side at −0.94 — a disturbance of the test's own making, gone here.
//
// Rim stress. A free edge is uniaxial, σ_tt = E ε_tt, and ε_tt along each rim edge (a chord of the
// 128-gon) is exact for its face's linear displacement. Edge by edge it scatters by about ±0.1σ∞
// with the shapes of the faces at the rim, so the single largest edge is no measure (measured at
// a/6: 3.04 on the 128-gon, 3.30 on a 96-gon, whose fits agree within 0.6%); the rim's values are
// fitted (least squares, weighted by edge length) by a Fourier series up to 4θ — Kirsch's
// 1 − 2 cos 2θ, the finite width's cos 4θ, and the odd and sine terms of a mesh and supports that
// are not exactly symmetric — and the fit is read at ±90° and at 0°, 180°.
//
// Measured (a/6, 128-gon: 43k faces, 140 rim edges; 3.5–4.6 s on the loaded 2-core machine, of
// which the remesh ≈ 1 s and the solve ≈ 2 s): fit 3.001 (+90°), 3.007 (−90°), −1.026 (0°),
// −1.029 (180°); raw per-edge RMS against 1 − 2 cos 2θ 0.077. The rim's polygon does not matter at
// this size: 48-, 96-gons 3.001/3.035, 3.019/3.027. Finer, a/8 (64-gon): 3.045, 3.049 (+0.5%),
// 60k faces and 5.5 s (too slow for this suite). It fails where it should:
//  - coarse: a/4 with a 32-gon rim (rim edges ≈ the triangles): 2.919, 2.882 (−3.7%, −5.0%), 0° at
//    −0.96 (within its 0.05) and RMS 0.13 — the peak and RMS checks fail. (a/4 with the 128-gon
//    still passes, 2.99/2.98: the rim's short sides keep the faces at the rim small, and the faces
//    at the rim decide.)
//  - the strain read with the wrong sign gives −3 (every check fails); no hole, no rim edges.
//  - σ∞ taken per net section (the load over W − d) instead of the gross one: 2.71, −10%.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <vector>

#include <Eigen/Dense>

#include "host/cut/cut_surface.h"
#include "host/mesh/isotropic_remesh.h"
#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/homogenise/free_edge_strain.h"
#include "solvers/shell/shell_model.h"

namespace cutwork::solvers {
namespace {

constexpr double kPi = std::numbers::pi;

struct RimEdge {
  double theta = 0;   ///< of the edge's midpoint, from the load axis (+x)
  double stress = 0;  ///< σ_tt / σ∞
  double length = 0;  ///< m
};

struct KirschRun {
  int faces = 0;
  int clamped = 0;
  std::vector<RimEdge> rim;
};

/// A W × W plate (W = `width_in_radii` a) with a hole of radius a at its centre (a `segments`-gon),
/// remeshed at edge length a / `per_radius`, pulled along x by σ∞ (strain 1e-5) on both sides.
KirschRun run_kirsch(double a, double width_in_radii, int segments, double per_radius) {
  const double W = width_in_radii * a;
  nlohmann::json doc = builtin_scene_json("plate");
  doc["name"] = "kirsch";
  doc["mesh"]["params"] = {{"width", W}, {"height", W}};
  doc["mesh"]["edge_length"] = a / 2;    // the surface the hole is cut into; remeshed below
  doc["mesh"]["sim_edge_length"] = W / 4;  // unused
  doc["stencils"] = nlohmann::json::array(
      {{{"name", "circle"}, {"kind", "circle"}, {"params", {{"segments", segments}}}}});
  const double E = doc["material"]["youngs_modulus"].get<double>();
  const double thickness = doc["material"]["thickness"].get<double>();
  const double traction = E * 1e-5 * thickness;  // N/m: σ∞ = E · 1e-5
  nlohmann::json clamp = {{"entity", "vertices"}};
  clamp["x"] = {{"below", -W / 2 + 1e-9}};
  clamp["y"] = {{"above", -0.3 * a}, {"below", 0.3 * a}};
  doc["supports"] = nlohmann::json::array({{{"type", "clamped"}, {"select", clamp}}});
  nlohmann::json left = {{"entity", "boundary_edges"}}, right = left;
  left["x"] = {{"below", -W / 2 + 1e-9}};
  right["x"] = {{"above", W / 2 - 1e-9}};
  doc["loads"] = nlohmann::json::array({{{"type", "edge"}, {"force", {-traction, 0.0, 0.0}}, {"select", left}},
                                        {{"type", "edge"}, {"force", {traction, 0.0, 0.0}}, {"select", right}}});
  const Scene scene = parse_scene(doc, "test:kirsch");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  StencilParams hole;
  hole.scale = a;
  const std::vector<StencilParams> stencils{hole};
  const CutSurface cut = cut_stencils(ctx.surface().bvh(), ctx.shapes(), ctx.surface().field(), stencils);
  const RemeshedMesh r = remesh_isotropic(cut.vertices, cut.faces, {a / per_radius, 5, 30.0});
  const SurfaceMesh mesh(r.vertices, r.faces, "kirsch");
  const LoadCase lc = resolve_load_case(scene, mesh);
  const ShellModel model(mesh, scene.material, lc, MechanicsSettings{});  // uncut: every fill rule is the solid
  EquilibriumSolver solver(model);
  solver.solve(Eigen::VectorXd::Ones(mesh.num_faces()));

  KirschRun out;
  out.faces = mesh.num_faces();
  for (bool c : lc.clamped) out.clamped += c;
  const double sigma_inf = traction / thickness;
  const RowMatX3d& X = mesh.vertices();
  for (const FreeEdgeStrain& e : free_edge_strains(X, mesh.faces(), solver.displacements())) {
    const Vec3 pa = X.row(e.a), pb = X.row(e.b);
    // The rim: both ends on the circle (its polygon's vertices, or points on its sides, ≥ a cos(π/n)).
    if (std::abs(pa.norm() - a) > 0.01 * a || std::abs(pb.norm() - a) > 0.01 * a) continue;
    const Vec3 mid = 0.5 * (pa + pb);
    out.rim.push_back({std::atan2(mid.y(), mid.x()), E * e.strain / sigma_inf, (pb - pa).norm()});
  }
  return out;
}

/// The least-squares Fourier series c0 + Σ_{k≤4} (c_k cos kθ + s_k sin kθ) through the rim's values,
/// each weighted by its edge's length.
struct RimFit {
  Eigen::VectorXd c;
  double operator()(double theta) const {
    double v = c(0);
    for (int k = 1; 2 * k < c.size(); ++k) v += c(2 * k - 1) * std::cos(k * theta) + c(2 * k) * std::sin(k * theta);
    return v;
  }
};

RimFit fit_rim(const std::vector<RimEdge>& rim, int harmonics = 4) {
  Eigen::MatrixXd A(rim.size(), 2 * harmonics + 1);
  Eigen::VectorXd b(rim.size());
  for (size_t i = 0; i < rim.size(); ++i) {
    const double w = std::sqrt(rim[i].length);
    A(Eigen::Index(i), 0) = w;
    for (int k = 1; k <= harmonics; ++k) {
      A(Eigen::Index(i), 2 * k - 1) = w * std::cos(k * rim[i].theta);
      A(Eigen::Index(i), 2 * k) = w * std::sin(k * rim[i].theta);
    }
    b(Eigen::Index(i)) = w * rim[i].stress;
  }
  return {A.colPivHouseholderQr().solve(b)};
}

TEST(Kirsch, RimStressOfASmallHoleInATensionedSheetIsThreeTimesTheFarField) {
  const double a = 0.01, width_in_radii = 20;
  const KirschRun run = run_kirsch(a, width_in_radii, 128, 6);
  EXPECT_GE(run.clamped, 2);  // the short clamp holds a few vertices of the left edge
  // Every side of the 128-gon is a rim edge (split, not collapsed, at L = a/6).
  ASSERT_GE(run.rim.size(), 128u) << run.faces << " faces";

  const double d_over_w = 2 / width_in_radii;
  const double kt = (2 + std::pow(1 - d_over_w, 3)) / (1 - d_over_w);  // 3.032
  const RimFit fit = fit_rim(run.rim);
  double sq = 0, peak = -INFINITY;
  for (const RimEdge& e : run.rim) {
    const double kirsch = 1 - 2 * std::cos(2 * e.theta);
    sq += (e.stress - kirsch) * (e.stress - kirsch);
    peak = std::max(peak, e.stress);
  }
  const double rms = std::sqrt(sq / double(run.rim.size()));
  RecordProperty("faces", run.faces);
  std::cout << run.faces << " faces, " << run.rim.size() << " rim edges: sigma/sigma_inf at +90 " << fit(kPi / 2)
            << ", -90 " << fit(-kPi / 2) << " (Kt_g " << kt << "), 0 " << fit(0) << ", 180 " << fit(kPi)
            << "; largest edge " << peak << ", RMS against 1 - 2 cos 2theta " << rms << "\n";

  // The peak, across the load: within 3% of Howland's Kt_g, on each side of the hole.
  EXPECT_NEAR(fit(kPi / 2), kt, 0.03 * kt);
  EXPECT_NEAR(fit(-kPi / 2), kt, 0.03 * kt);
  // On the load axis: −σ∞. Tolerance 0.05σ∞: the peak's 3% (0.09σ∞) scaled by the rim's radial
  // stress gradient, 5σ∞/a at θ = 0 against 7σ∞/a at ±90° (Kirsch; the edge recovery's error goes
  // with it), 0.064σ∞, rounded down; measured −1.026, −1.029.
  EXPECT_NEAR(fit(0), -1.0, 0.05);
  EXPECT_NEAR(fit(kPi), -1.0, 0.05);
  // The whole distribution, edge by edge (the per-edge scatter included): measured 0.077, 0.13 on
  // the coarse mesh.
  EXPECT_LT(rms, 0.1);
}

}  // namespace
}  // namespace cutwork::solvers

// The perforated-lattice suite of issue 21: a plate perforated by a regular lattice of stencils,
// simulated on coarse meshes with fill ratios (triangles ½, 1 and 2 hole diameters across) and
// compared with the converged conforming reference (the plate cut along every outline, refined
// until the compliance changes by less than 1%, Richardson-extrapolated). The coarse compliance
// under each fill rule — the paper's linear g(α) = α per face, the homogenised g(α) per face, and
// the homogenised g at the cell-filtered α (solvers/shell/cell_filter.h) — is the number a design
// iteration sees; the conforming one is what the built plate does.
//
// Scenes: a 0.2 m × 0.1 m PA12 plate, 3 mm, either a cantilever (clamped at x = −0.1, 0.1 N spread
// along the free short side) or clamped round its whole boundary under 100 Pa. The lattice
// (hexagonal or square, spacing a = 10 mm) covers the plate with its stencils at least a/2 from the
// border; the stencil scale follows from the fill ratio asked for. A square case's scene says
// `"lattice": "square"` (its axis along x, the plate's length), so the coarse rule is calibrated on
// the square lattice. The pattern's safety factor
// s = a/(2 r) − 1 makes the scene's nominal spacing 2 (1 + s) ℓ equal to the lattice's, as a
// packing of that density has it (s = 0 where the bounding circles overlap: stars on the square
// lattice).
//
// A third structure, the cantilever pulled along x in its plane (1 N along the free side), loads
// the membrane alone: the square lattice's anisotropy is largest there.
//
// CUTWORK_LATTICE_TABLE=1 prints the whole table (every shape, lattice, α, structure and size)
// instead of the assertions' subset; CUTWORK_LATTICE_SHAPE (circle, star), _LATTICE (hex, square),
// _ALPHA, _STRUCTURE (cantilever, clamped, tension) pick rows, _SIZES the triangle sizes,
// _PLATE_SCALE a larger plate on the same lattice, _PLATE="w,h" its width and height (m) instead,
// _ANGLE (degrees) the lattice turned, _LEVELS the conforming reference's levels (3) and
// _CALIBRATION=hexagonal the square cases under the hexagonal calibration.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "host/pattern/pattern_context.h"
#include "host/scene/scene.h"
#include "solvers/conforming/conforming_verification.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {
namespace {

constexpr double kSpacing = 0.01;

struct LatticeCase {
  std::string shape = "circle";  ///< a built-in stencil kind
  bool hexagonal = true;
  double alpha = 0.67;           ///< fill ratio of the lattice cell
  bool cantilever = true;        ///< else clamped round the boundary under pressure
  double width = 0.2, height = 0.1;  ///< of the plate (m)
  const char* calibration = "square";  ///< mechanics.lattice of a square case
  bool tension = false;  ///< the cantilever pulled along x in its plane (its membrane alone)
  double angle = 0;      ///< the lattice's first axis from x (radians; the scene's lattice_axis)
};

nlohmann::json scene_doc(const LatticeCase& c, double bounding_radius, double sim_edge_length, const char* stiffness,
                         const char* filter) {
  const double width = c.width, height = c.height;
  nlohmann::json doc = builtin_scene_json("plate");
  doc["name"] = "lattice";
  doc["mesh"]["params"] = {{"width", width}, {"height", height}};
  doc["mesh"]["edge_length"] = std::min(0.005, sim_edge_length);
  doc["mesh"]["sim_edge_length"] = sim_edge_length;
  doc["mechanics"] = {{"stiffness", stiffness}, {"filter", filter}};
  // The square lattice runs along x (the default lattice_axis); `lattice` "hexagonal" gives it the
  // hexagonal lattice's calibration instead, as before the rule knew the square one.
  if (!c.hexagonal) doc["mechanics"]["lattice"] = c.calibration;
  // (The hexagonal calibration has no axis: a scene that gave it one would be refused.)
  if (!c.hexagonal && c.angle != 0 && std::string(c.calibration) == "square")
    doc["mechanics"]["lattice_axis"] = {std::cos(c.angle), std::sin(c.angle), 0.0};
  doc["stencils"] = nlohmann::json::array({{{"name", c.shape}, {"kind", c.shape}, {"params", nlohmann::json::object()}}});
  doc["pattern"]["scale"] = bounding_radius;
  // A star's bounding circles overlap on the square lattice at α 0.67 (its tips interleave): the
  // scene's safety factor cannot be negative, and the nominal spacing is then the bounding circles'.
  doc["pattern"]["s"] = std::max(0.0, kSpacing / (2 * bounding_radius) - 1);
  if (c.cantilever) {
    doc["supports"] = nlohmann::json::array(
        {{{"type", "clamped"}, {"select", {{"entity", "vertices"}, {"x", {{"below", -width / 2 + 1e-6}}}}}}});
    doc["loads"] = nlohmann::json::array(
        {{{"type", "edge"},
          {"force", c.tension ? std::vector<double>{1.0 / height, 0.0, 0.0} : std::vector<double>{0.0, 0.0, -0.1 / height}},
          {"select", {{"entity", "boundary_edges"}, {"x", {{"above", width / 2 - 1e-6}}}}}}});
  } else {
    doc["supports"] =
        nlohmann::json::array({{{"type", "clamped"}, {"select", {{"entity", "boundary_vertices"}}}}});
    doc["loads"] = nlohmann::json::array(
        {{{"type", "pressure"}, {"pressure", 100.0}, {"select", {{"entity", "faces"}}}}});
  }
  return doc;
}

/// The stencil scale (bounding radius) that perforates the lattice cell down to c.alpha.
double lattice_scale(const LatticeCase& c, const StencilLibrary& shapes) {
  const double cell = c.hexagonal ? std::sqrt(3.0) / 2 * kSpacing * kSpacing : kSpacing * kSpacing;
  return std::sqrt((1 - c.alpha) * cell / shapes[0].area);
}

std::vector<StencilParams> lattice_stencils(const LatticeCase& c, double scale) {
  const double width = c.width, height = c.height;
  std::vector<StencilParams> out;
  if (c.angle != 0) {
    // The lattice turned about the plate's centre, its points at least half a spacing inside.
    const Eigen::Vector2d a1(std::cos(c.angle), std::sin(c.angle));
    const Eigen::Vector2d a2 = c.hexagonal ? Eigen::Vector2d(std::cos(c.angle + std::numbers::pi / 3),
                                                             std::sin(c.angle + std::numbers::pi / 3))
                                           : Eigen::Vector2d(-a1.y(), a1.x());
    const int n = int(std::ceil(2 * std::hypot(width, height) / kSpacing));
    const double margin = kSpacing / 2;
    for (int j = -n; j <= n; ++j)
      for (int i = -n; i <= n; ++i) {
        const Eigen::Vector2d p = kSpacing * (i * a1 + j * a2);
        if (std::abs(p.x()) > width / 2 - margin + 1e-12 || std::abs(p.y()) > height / 2 - margin + 1e-12)
          continue;
        StencilParams s;
        s.position = Vec3(p.x(), p.y(), 0);
        s.scale = scale;
        out.push_back(s);
      }
    return out;
  }
  const double dy = c.hexagonal ? kSpacing * std::sqrt(3.0) / 2 : kSpacing;
  const double x0 = -width / 2 + kSpacing / 2, y0 = -height / 2 + kSpacing / 2;
  for (int j = 0;; ++j) {
    const double y = y0 + j * dy;
    if (y > height / 2 - kSpacing / 2 + 1e-12) break;
    const double shift = c.hexagonal && (j % 2) ? kSpacing / 2 : 0.0;
    for (int i = 0;; ++i) {
      const double x = x0 + shift + i * kSpacing;
      if (x > width / 2 - kSpacing / 2 + 1e-12) break;
      StencilParams s;
      s.position = Vec3(x, y, 0);
      s.scale = scale;
      out.push_back(s);
    }
  }
  return out;
}

struct CoarseRun {
  double compliance = 0;
  int faces = 0;
};

/// `loads_on_material` false: the loads spread over the surface stay spread by area whatever α
/// (the rule before the loads went onto the material, LoadCase::surface_loads).
CoarseRun coarse_compliance(const nlohmann::json& doc, std::span<const StencilParams> stencils,
                            bool loads_on_material = true) {
  const Scene scene = parse_scene(doc, "test:lattice");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  LoadCase lc = resolve_load_case(scene, meshes.sim);
  if (!loads_on_material) lc.surface_loads.clear();
  const Eigen::VectorXd alpha = design_fill_ratios(scene, ctx, meshes.sim, stencils);
  const ShellModel model(meshes.sim, scene.material, lc, resolve_fill_stiffness(scene.mechanics, ctx.shapes(), scene.material));
  EquilibriumSolver solver(model);
  solver.solve(alpha);
  return {summarize_equilibrium(model, solver.positions(), alpha).compliance, meshes.sim.num_faces()};
}

struct Reference {
  double compliance = 0, error_bar = 0;
  bool converged = false;
  int levels = 0, faces = 0;
};

/// The conforming reference: from L = d/4 (d the stencil's diameter), refined until 1%.
Reference conforming_reference(const LatticeCase& c, double scale, std::span<const StencilParams> stencils,
                               int max_faces = 700'000) {
  const nlohmann::json doc = scene_doc(c, scale, 0.01, "linear", "none");
  const Scene scene = parse_scene(doc, "test:lattice");
  const SceneMeshes meshes = build_scene_meshes(scene);
  const PatternContext ctx(scene, meshes);
  const LoadCase lc = resolve_load_case(scene, meshes.sim);
  ConformingOptions o;
  o.edge_length = scale / 2;
  // CUTWORK_LATTICE_LEVELS: more conforming levels (a tighter error bar, within max_faces).
  o.levels = std::getenv("CUTWORK_LATTICE_LEVELS") ? std::stoi(std::getenv("CUTWORK_LATTICE_LEVELS")) : 3;
  o.tolerance = 0.01;
  o.max_faces = max_faces;
  const ConformingVerification v = verify_conforming(scene, meshes, lc, ctx, stencils, o);
  return {v.extrapolated_compliance, v.compliance_error_bar, v.converged, int(v.levels.size()), v.levels.back().faces};
}

struct Ratios {
  double linear = 0, homogenised = 0, filtered = 0;  ///< coarse / conforming C∞
  double solid = 0;  ///< the uncut plate on the same coarse mesh / the uncut plate's converged compliance
  int faces = 0;
};

struct CaseResult {
  double scale = 0;
  Reference reference;
  Reference solid;  ///< the uncut plate
  std::vector<Ratios> by_size;  ///< triangles ½, 1, 2 stencil diameters across
};

/// Triangle sizes in stencil diameters; CUTWORK_LATTICE_SIZES="0.125,0.25" replaces them.
std::vector<double> lattice_sizes() {
  std::vector<double> sizes = {0.5, 1.0, 2.0};
  if (const char* env = std::getenv("CUTWORK_LATTICE_SIZES")) {
    sizes.clear();
    for (std::string rest = env; !rest.empty();) {
      const size_t comma = rest.find(',');
      sizes.push_back(std::stod(rest.substr(0, comma)));
      rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
    }
  }
  return sizes;
}
const std::vector<double> kSizes = lattice_sizes();

CaseResult run_case(const LatticeCase& c) {
  CaseResult r;
  const Scene probe = parse_scene(scene_doc(c, 0.003, 0.01, "linear", "none"), "test:lattice");
  r.scale = lattice_scale(c, scene_stencil_library(probe));
  const std::vector<StencilParams> stencils = lattice_stencils(c, r.scale);
  r.reference = conforming_reference(c, r.scale, stencils);
  r.solid = conforming_reference(c, r.scale, {});
  for (double size : kSizes) {
    const double h = size * 2 * r.scale;
    Ratios q;
    const CoarseRun lin = coarse_compliance(scene_doc(c, r.scale, h, "linear", "none"), stencils);
    q.linear = lin.compliance / r.reference.compliance;
    q.faces = lin.faces;
    q.solid = coarse_compliance(scene_doc(c, r.scale, h, "linear", "none"), {}).compliance / r.solid.compliance;
    q.homogenised = coarse_compliance(scene_doc(c, r.scale, h, "homogenised", "none"), stencils).compliance /
                    r.reference.compliance;
    q.filtered = coarse_compliance(scene_doc(c, r.scale, h, "homogenised", "cell"), stencils).compliance /
                 r.reference.compliance;
    r.by_size.push_back(q);
  }
  return r;
}

std::string describe(const LatticeCase& c) {
  return fmt::format("{} {}{} α {:.2f} {}", c.shape, c.hexagonal ? "hex" : "square",
                     c.angle != 0 ? fmt::format(" at {:.0f}°", c.angle * 180 / std::numbers::pi) : "", c.alpha,
                     c.tension ? "in tension" : c.cantilever ? "cantilever" : "clamped plate");
}

void print(const LatticeCase& c, const CaseResult& r) {
  std::string line = fmt::format("{:<38} C∞ {:.4e} ± {:.1f}% ({} levels{}, {} faces)", describe(c),
                                 r.reference.compliance, 100 * r.reference.error_bar / r.reference.compliance,
                                 r.reference.levels, r.reference.converged ? ", converged" : "", r.reference.faces);
  for (size_t k = 0; k < kSizes.size(); ++k)
    line += fmt::format(
        "\n    h = {:.1f} d ({:5d} faces): linear {:.3f}  homogenised {:.3f}  cell-filtered {:.3f}  (uncut {:.3f})",
        kSizes[k], r.by_size[k].faces, r.by_size[k].linear, r.by_size[k].homogenised, r.by_size[k].filtered,
        r.by_size[k].solid);
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

double compliance(const LatticeCase& c, double scale, double size, const char* stiffness, const char* filter,
                  std::span<const StencilParams> stencils) {
  return coarse_compliance(scene_doc(c, scale, size * 2 * scale, stiffness, filter), stencils).compliance;
}

// What the filter is for: on triangles as large as the stencils or larger, the answer should not
// depend on how the mesh happens to cut the lattice. Normalised by the uncut plate on the same mesh
// (the coarse mesh's own discretisation error, 0.5% here), the perforated compliance at 1 and 2
// stencil diameters: measured 0.3% apart with the filter, 5.6% per face (homogenised g) and 0.3%
// per face with the linear rule — which is as consistently wrong, by 24%, see the next test.
TEST(PerforatedLattice, CellFilteredComplianceDoesNotDependOnTheTriangleSize) {
  const LatticeCase c;  // circles, hexagonal, α = 0.67, cantilever 0.2 m × 0.1 m
  const Scene probe = parse_scene(scene_doc(c, 0.003, 0.01, "linear", "none"), "test:lattice");
  const double scale = lattice_scale(c, scene_stencil_library(probe));
  const std::vector<StencilParams> stencils = lattice_stencils(c, scale);
  auto normalised = [&](double size, const char* filter) {
    return compliance(c, scale, size, "homogenised", filter, stencils) /
           compliance(c, scale, size, "linear", "none", {});
  };
  const double filtered_1 = normalised(1, "cell"), filtered_2 = normalised(2, "cell");
  const double per_face_1 = normalised(1, "none"), per_face_2 = normalised(2, "none");
  std::printf("perforated / uncut compliance at 1 d and 2 d: cell-filtered %.4f %.4f, per face %.4f %.4f\n",
              filtered_1, filtered_2, per_face_1, per_face_2);
  EXPECT_LT(std::abs(filtered_1 / filtered_2 - 1), 0.015);
  EXPECT_GT(std::abs(per_face_1 / per_face_2 - 1), 0.03);
}

// Against the conforming reference (refined to 1% or to two levels within 150k triangles), on a
// 0.12 m × 0.06 m cantilever at triangles one stencil diameter across: the filtered homogenised rule
// is closer than the per-face homogenised rule, which is closer than the paper's linear rule, and
// within the 3%. The full table (CUTWORK_LATTICE_TABLE=1, in docs/DESIGN.md) has the rest:
// every hexagonal cantilever within 1.3% at 1 d and 2 d, the square ones (with the square
// lattice's calibration) within 2.7%; plates clamped all round (the pressure on the material, the
// filter stopped at the clamps both ways) 0.981–0.994 raw at 1 d on the hexagonal lattice, 2–5%
// too stiff over the coarse mesh's own error.
/// Case c on the 0.12 m × 0.06 m plate of the assertions below: its stencil scale and stencils.
struct SmallPlate {
  LatticeCase c;
  double scale = 0;
  std::vector<StencilParams> stencils;
  explicit SmallPlate(LatticeCase lattice_case) : c(std::move(lattice_case)) {
    c.width = 0.12;
    c.height = 0.06;
    const Scene probe = parse_scene(scene_doc(c, 0.003, 0.01, "linear", "none"), "test:lattice");
    scale = lattice_scale(c, scene_stencil_library(probe));
    stencils = lattice_stencils(c, scale);
  }
};

TEST(PerforatedLattice, CellFilteredHomogenisedRuleIsClosestToTheConformingPlate) {
  const SmallPlate plate{LatticeCase{}};
  const LatticeCase& c = plate.c;
  const double scale = plate.scale;
  const std::vector<StencilParams>& stencils = plate.stencils;
  const Reference ref = conforming_reference(c, scale, stencils, 150'000);
  ASSERT_GE(ref.levels, 2);
  const double linear = compliance(c, scale, 1, "linear", "none", stencils) / ref.compliance;
  const double per_face = compliance(c, scale, 1, "homogenised", "none", stencils) / ref.compliance;
  const double filtered = compliance(c, scale, 1, "homogenised", "cell", stencils) / ref.compliance;
  std::printf("coarse / conforming C∞ (%d levels, error bar %.1f%%): linear %.3f, homogenised %.3f, "
              "cell-filtered %.3f\n",
              ref.levels, 100 * ref.error_bar / ref.compliance, linear, per_face, filtered);
  EXPECT_LT(std::abs(filtered - 1), std::abs(per_face - 1));
  EXPECT_LT(std::abs(per_face - 1), std::abs(linear - 1));
  // The target at 1 d: measured 0.995 (0.987 while the faces inside still counted the
  // clamp's faces in their cells, 1.004 before the filter stopped at the clamp),
  // 0.930 with the scalar g (which gave the perforated plate the solid's Poisson ratio), 0.791 with
  // the linear rule.
  EXPECT_NEAR(filtered, 1.0, 0.03);
}

// A plate clamped all round under 100 Pa (circles, hexagonal lattice, α 0.5, the 0.12 m × 0.06 m
// plate, triangles one stencil diameter across). The hexagonal rows leave solid margins between the
// border and the first holes (up to 11.7 mm here), where the built plate carries more of the
// pressure per area than in its perforated middle. With the load spread by area whatever α (the
// rule before LoadCase::surface_loads) the coarse plate put that share on the middle and read too
// soft; carried by the material, as the conforming plate carries it, it is close. Measured over
// the coarse mesh's own error (the uncut plate's coarse / conforming, 1.108 here): 1.001 on the
// material, 1.306 spread by area (0.965 and 1.288 while the faces next to the clamps counted the
// clamp's solid margin in their cells: cell_filter.h). Asserted: the 3%, and the by-area
// rule at least 5% softer.
TEST(PerforatedLattice, AClampedPlateCarriesItsPressureOnItsMaterial) {
  LatticeCase clamped_case;
  clamped_case.alpha = 0.5;
  clamped_case.cantilever = false;
  const SmallPlate plate{clamped_case};
  const Reference ref = conforming_reference(plate.c, plate.scale, plate.stencils, 150'000);
  const Reference solid = conforming_reference(plate.c, plate.scale, {}, 150'000);
  ASSERT_GE(ref.levels, 2);
  ASSERT_GE(solid.levels, 2);
  const double uncut = compliance(plate.c, plate.scale, 1, "linear", "none", {}) / solid.compliance;
  const nlohmann::json doc = scene_doc(plate.c, plate.scale, 2 * plate.scale, "homogenised", "cell");
  const double on_material = coarse_compliance(doc, plate.stencils).compliance / ref.compliance / uncut;
  const double by_area = coarse_compliance(doc, plate.stencils, false).compliance / ref.compliance / uncut;
  std::printf("clamped plate, hex α 0.5, h = 1 d: coarse / conforming C∞ over the uncut plate's %.3f (%d levels, "
              "error bar %.1f%%): pressure on the material %.3f, spread by area %.3f\n",
              uncut, ref.levels, 100 * ref.error_bar / ref.compliance, on_material, by_area);
  EXPECT_LT(std::abs(on_material - 1), std::abs(by_area - 1));
  EXPECT_GT(by_area, on_material * 1.05) << "the load on the holes' share of the middle makes it softer";
  EXPECT_NEAR(on_material, 1.0, 0.03);
}

// The square lattice (mechanics.lattice "square"): circles at α 0.5 on a 0.12 m × 0.06 m
// cantilever along the lattice's axis, triangles one and two stencil diameters across. With the
// square lattice's calibration (its bulk, mean shear and anisotropic parts) the filtered rule is
// closer to the conforming reference than with the hexagonal lattice's (as before the rule knew the
// square one; it is too stiff, by 4.5% and 7.6% here); the rule's own error, over the coarse mesh's
// (the uncut plate's coarse / conforming on the same mesh, 1.007 at 1 d), is within the 3%
// at 1 d, and the raw ratio within its 5% at 2 d. Measured: 1.015 (over the uncut 1.008) and 0.999
// (1.018 and 1.002 before the curve was sampled at the circle's lowest α on the square lattice, 0.364),
// against 0.942 and 0.925 with the hexagonal calibration (1.035 and 1.000 while the faces next to the
// clamp counted the clamp's faces in their cells); the 0.2 m plate of the table: 1.027 and 1.001
// (before that change). At 1 d the triangles (0.8 spacings across) alias with the lattice, as the
// per-face rule's 0.929 there shows.
TEST(PerforatedLattice, TheSquareLatticesCalibrationIsCloserAlongItsAxes) {
  LatticeCase square_case;
  square_case.hexagonal = false;
  square_case.alpha = 0.5;
  const SmallPlate plate{square_case};
  const LatticeCase& c = plate.c;
  const double scale = plate.scale;
  const std::vector<StencilParams>& stencils = plate.stencils;
  const Reference ref = conforming_reference(c, scale, stencils, 150'000);
  const Reference solid = conforming_reference(c, scale, {}, 150'000);
  ASSERT_GE(ref.levels, 2);
  ASSERT_GE(solid.levels, 2);
  LatticeCase hex_calibrated = c;
  hex_calibrated.calibration = "hexagonal";
  for (const double size : {1.0, 2.0}) {
    const double square = compliance(c, scale, size, "homogenised", "cell", stencils) / ref.compliance;
    const double hexagonal = compliance(hex_calibrated, scale, size, "homogenised", "cell", stencils) / ref.compliance;
    const double uncut = compliance(c, scale, size, "linear", "none", {}) / solid.compliance;
    std::printf("square lattice α 0.5, h = %.0f d: coarse / conforming C∞ (%d levels, error bar %.1f%%): square "
                "calibration %.3f (over the uncut plate's %.3f: %.3f), hexagonal calibration %.3f\n",
                size, ref.levels, 100 * ref.error_bar / ref.compliance, square, uncut, square / uncut, hexagonal);
    EXPECT_LT(std::abs(square - 1), std::abs(hexagonal - 1)) << size;
    if (size == 1.0) EXPECT_NEAR(square / uncut, 1.0, 0.03);
    else EXPECT_NEAR(square, 1.0, 0.05);
  }
}

// The square lattice in its plane (circles, α 0.5, the 0.12 m × 0.06 m cantilever pulled along x),
// where its anisotropy is largest: along its axes the straight ligaments carry the load, at 45°
// they bend. The hexagonal calibration, isotropic, is then too soft along the axes and too stiff at
// 45° (on the 0.2 m plate of the table at 1 d / 2 d: 1.332 / 1.324 and 0.686 / 0.674 — a third
// off, at 45° on the unsafe side); the square lattice's, with its anisotropic part turned with
// lattice_axis, is 0.968 / 0.961 and 1.094 / 1.073 there. On this plate, 12 × 6 cells, the cells
// cut by its free sides weigh more: at 2 d, 0.919 and 1.098 against the hexagonal calibration's
// 1.269 and 0.770 (0.922 and 1.105 before the curve was sampled at the circle's lowest α on the
// square lattice; 0.921, 1.101, 1.267, 0.766 before the clamp's faces left the cells of the faces
// next to them). Asserted: the square calibration at least twice as close as the hexagonal one
// at both angles, and the hexagonal one's error on the side the anisotropy puts it (a wrong sign
// or angle of the anisotropic part fails both).
TEST(PerforatedLattice, TheSquareLatticeInTensionAlongItsAxesAndAt45Degrees) {
  for (const double degrees : {0.0, 45.0}) {
    LatticeCase square_case;
    square_case.hexagonal = false;
    square_case.alpha = 0.5;
    square_case.tension = true;
    square_case.angle = degrees * std::numbers::pi / 180;
    const SmallPlate plate{square_case};
    const Reference ref = conforming_reference(plate.c, plate.scale, plate.stencils, 150'000);
    ASSERT_GE(ref.levels, 2);
    LatticeCase hex_calibrated = plate.c;
    hex_calibrated.calibration = "hexagonal";
    const double square = compliance(plate.c, plate.scale, 2, "homogenised", "cell", plate.stencils) / ref.compliance;
    const double hexagonal =
        compliance(hex_calibrated, plate.scale, 2, "homogenised", "cell", plate.stencils) / ref.compliance;
    std::printf("square lattice at %.0f° in tension, h = 2 d: coarse / conforming C∞ (%d levels, error bar %.1f%%): "
                "square calibration %.3f, hexagonal calibration %.3f\n",
                degrees, ref.levels, 100 * ref.error_bar / ref.compliance, square, hexagonal);
    EXPECT_LT(2 * std::abs(square - 1), std::abs(hexagonal - 1)) << degrees;
    EXPECT_TRUE(degrees == 0 ? hexagonal > 1 : hexagonal < 1) << "too soft along the axes, too stiff at 45°";
  }
}

// Stars (the suite's non-convex shape: hexagonal lattice, α 0.67, the 0.12 m × 0.06 m cantilever)
// on triangles half a bounding diameter d across. The filter's blend hands a face back its own α
// where the triangles resolve the stencils, measured against the shape's hydraulic diameter 4A/P
// (0.44 d for the star): at ½ d the star is not resolved (its tips and inner corners are far
// narrower than d), and a face's own α, even through the homogenised g, makes it too stiff. On the
// 0.2 m plate of the table, cell-filtered at ¼ d / ½ d / 0.8 d: 0.877 / 1.006 / 0.995, against
// 0.776 / 0.841 / 0.947 while the blend measured triangles against d (b = 0.26 at ½ d) and the
// star's curve rose from the grid point below its lowest α (fill_stiffness_calibration.h); per
// face, 0.787 / 0.793 / 0.839. Here: 1.016, per face 0.827 (0.869 and 0.814 with the blend against
// d and the old samples). Asserted: the 3% at ½ d, and the filtered rule closer than the
// per-face one.
TEST(PerforatedLattice, StarsAreFilteredUntilTheTrianglesResolveTheirNarrowFeatures) {
  LatticeCase star_case;
  star_case.shape = "star";
  const SmallPlate plate{star_case};
  const Reference ref = conforming_reference(plate.c, plate.scale, plate.stencils, 150'000);
  ASSERT_GE(ref.levels, 2);
  const double filtered = compliance(plate.c, plate.scale, 0.5, "homogenised", "cell", plate.stencils) / ref.compliance;
  const double per_face = compliance(plate.c, plate.scale, 0.5, "homogenised", "none", plate.stencils) / ref.compliance;
  std::printf("stars, hex α 0.67, h = ½ d: coarse / conforming C∞ (%d levels, error bar %.1f%%): "
              "cell-filtered %.3f, per face %.3f\n",
              ref.levels, 100 * ref.error_bar / ref.compliance, filtered, per_face);
  EXPECT_LT(std::abs(filtered - 1), std::abs(per_face - 1));
  EXPECT_NEAR(filtered, 1.0, 0.03);
}

TEST(PerforatedLattice, Table) {
  if (!std::getenv("CUTWORK_LATTICE_TABLE")) GTEST_SKIP() << "set CUTWORK_LATTICE_TABLE=1 for the whole table";
  const char* only = std::getenv("CUTWORK_LATTICE_SHAPE");
  const char* alphas = std::getenv("CUTWORK_LATTICE_ALPHA");
  const char* structure = std::getenv("CUTWORK_LATTICE_STRUCTURE");  // "cantilever", "clamped" or "tension"
  const char* lattice = std::getenv("CUTWORK_LATTICE_LATTICE");      // "hex" or "square"
  // CUTWORK_LATTICE_PLATE_SCALE = k: a k times larger plate on the same lattice (k² as many cells).
  const double plate = std::getenv("CUTWORK_LATTICE_PLATE_SCALE") ? std::stod(std::getenv("CUTWORK_LATTICE_PLATE_SCALE")) : 1.0;
  // CUTWORK_LATTICE_ANGLE = degrees: the lattice turned by that much (its axis the scene's).
  const double angle = std::getenv("CUTWORK_LATTICE_ANGLE") ? std::stod(std::getenv("CUTWORK_LATTICE_ANGLE")) * std::numbers::pi / 180 : 0.0;
  for (const char* shape : {"circle", "star"})
    for (bool hex : {true, false})
      for (double alpha : {0.5, 0.67, 0.85})
        for (const std::string kind : {"cantilever", "clamped", "tension"}) {
          if (only && std::string(only) != shape) continue;
          if (alphas && std::abs(std::stod(alphas) - alpha) > 1e-9) continue;
          if (structure && std::string(structure) != kind) continue;
          if (lattice && (std::string(lattice) == "hex") != hex) continue;
          LatticeCase c{shape, hex, alpha, kind != "clamped", 0.2 * plate, 0.1 * plate};
          if (const char* wh = std::getenv("CUTWORK_LATTICE_PLATE")) {
            const std::string text = wh;
            c.width = std::stod(text.substr(0, text.find(',')));
            c.height = std::stod(text.substr(text.find(',') + 1));
          }
          c.tension = kind == "tension";
          c.angle = angle;
          // CUTWORK_LATTICE_CALIBRATION=hexagonal: a square case with the hexagonal calibration.
          if (const char* calibration = std::getenv("CUTWORK_LATTICE_CALIBRATION")) c.calibration = calibration;
          print(c, run_case(c));
        }
}

}  // namespace
}  // namespace cutwork::solvers

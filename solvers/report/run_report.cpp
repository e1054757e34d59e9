#include "solvers/homogenise/fill_stiffness_calibration.h"
#include "solvers/report/run_report.h"

#include <algorithm>
#include <numeric>

#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "host/pattern/lattice_order.h"
#include "host/pattern/pattern_context.h"

namespace cutwork::solvers {

namespace {

const char* lattice_name(PerforationLattice lattice) {
  return lattice == PerforationLattice::Square ? "square" : "hexagonal";
}

}  // namespace

nlohmann::json lattice_order_json(const MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field,
                                  std::span<const StencilParams> stencils, std::vector<std::string>& notes) {
  RowMatX3d centres, normals, tangents;
  stencil_frames(bvh, field, stencils, centres, normals, &tangents);
  const bool square = mechanics.lattice == PerforationLattice::Square;
  // What the model used: stated by the scene, or read from the stencils ("auto"; for a design,
  // from its layout when the structural phase started, which these final stencils may have left).
  const std::string used = mechanics.lattice_source == LatticeSource::Scene ? "mechanics.lattice is"
                           : mechanics.lattice_source == LatticeSource::Stencils
                               ? "mechanics.lattice (auto) was read from the stencils as"
                               : "mechanics.lattice (auto, no stencils to read) is";
  // The angles from the axis the model used: the one axis, or the field's at each stencil.
  RowMatX3d axes;
  if (square && mechanics.lattice_follows_field && mechanics.lattice_axis_at) {
    axes.resize(centres.rows(), 3);
    for (Eigen::Index i = 0; i < centres.rows(); ++i)
      axes.row(i) = mechanics.lattice_axis_at(centres.row(i).transpose()).transpose();
  }
  const LatticeOrder o = measure_lattice_order(centres, normals, mechanics.lattice_axis, axes.rows() ? &axes : nullptr);
  if (o.stencils > 0) {
    // Told where the square lattice is one the model could have used (one axis, or the field's):
    // a turning one that neither fits is modelled best by the isotropic calibration (and a design
    // whose stencils formed a square lattice after its lattice was read is told here too).
    if (!square && o.square >= 0.7 && o.hexagonal < 0.5 && measure_lattice(centres, normals, &tangents).square)
      notes.push_back(fmt::format(
          "the stencils lie on a square lattice (median |psi4| {:.2f}, |psi6| {:.2f}) but {} "
          "hexagonal: the homogenised stiffness is then the hexagonal lattice's (bent along the square's axes up to 8% "
          "too stiff, stretched along them up to 29% too soft); say \"lattice\": \"square\" with its lattice_axis, "
          "or \"auto\"",
          o.square, o.hexagonal, used));
    if (square && o.square < 0.5)
      notes.push_back(fmt::format("{} square but the stencils do not form one (median |psi4| {:.2f}, "
                                  "|psi6| {:.2f}): the square lattice's anisotropy is then assumed where it is not",
                                  used, o.square, o.hexagonal));
    if (square && o.axis_misfit > 10)
      notes.push_back(fmt::format("the stencils' square lattice runs a median {:.0f} degrees from the lattice axis "
                                  "the model used (projected): its anisotropy is applied in the wrong direction there",
                                  o.axis_misfit));
  }
  nlohmann::json out = {
      {"stated", mechanics.lattice_source == LatticeSource::Scene ? lattice_name(mechanics.lattice) : "auto"},
      {"used", lattice_name(mechanics.lattice)},
      {"stencils_measured", o.stencils},
      {"square_order", number_or_null(o.square)},
      {"hexagonal_order", number_or_null(o.hexagonal)},
      {"axis_misfit_degrees", number_or_null(o.axis_misfit)},
      {"rule", "per stencil with three or more neighbours within 1.3 times its nearest one's distance: |mean "
               "exp(4 i theta)| (1 on a square lattice) and |mean exp(6 i theta)| (1 on a hexagonal one), theta "
               "the neighbours' angles in the tangent plane from the projected lattice_axis; medians. \"auto\" reads "
               "square where those medians are >= 0.7 and < 0.5 and one axis fits the stencils' own within 10 "
               "degrees (median)"}};
  if (square && mechanics.lattice_follows_field) {
    out["used_axis"] = "field";
    out["used_field_angle_degrees"] = mechanics.lattice_field_angle * 180 / std::numbers::pi;
  } else if (square) {
    out["used_axis"] = {mechanics.lattice_axis.x(), mechanics.lattice_axis.y(), mechanics.lattice_axis.z()};
  }
  return out;
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json timings_json(const Timings& timings) {
  nlohmann::json t = nlohmann::json::object();
  for (const auto& [name, seconds] : timings.entries()) t[name] = seconds;
  return t;
}

nlohmann::json base_report(const Scene& scene, const SceneMeshes& meshes, const Timings& timings,
                           const MechanicsSettings* used) {
  nlohmann::json r;
  r["scene"] = scene.name;
  r["scene_source"] = scene_origin(scene);
  r["mesh"] = {{"vertices", meshes.base.num_vertices()},
               {"triangles", meshes.base.num_faces()},
               {"sim_vertices", meshes.sim.num_vertices()},
               {"sim_triangles", meshes.sim.num_faces()},
               {"sim_is_base", meshes.sim_is_base},
               {"sim_subdivisions", meshes.sim_subdivisions},
               {"sim_union_jack_flips", meshes.sim_flips},
               {"map_max_distance", meshes.map.max_distance}};
  if (!meshes.sim_choice.is_null()) r["mesh"]["sim_choice"] = meshes.sim_choice;
  const MechanicsSettings mechanics = used ? *used : scene_mechanics(scene);
  r["mechanics"] = {{"bending", mechanics.bending == BendingModel::Hinge ? "hinge" : "shape_operator"},
                    {"stiffness", mechanics.stiffness == FillStiffness::Homogenised ? "homogenised" : "linear"},
                    {"filter", mechanics.filter == FillFilter::Cell ? "cell" : "none"},
                    {"loads", mechanics.loads == LoadSpread::Area ? "area" : "material"},
                    {"lattice", lattice_name(mechanics.lattice)},
                    {"lattice_source", mechanics.lattice_source == LatticeSource::Scene      ? "scene"
                                       : mechanics.lattice_source == LatticeSource::Stencils ? "stencils"
                                                                                             : "auto without stencils"}};
  if (mechanics.lattice == PerforationLattice::Square && mechanics.lattice_follows_field) {
    r["mechanics"]["lattice_axis"] = "field";
    r["mechanics"]["lattice_field_angle_degrees"] = mechanics.lattice_field_angle * 180 / std::numbers::pi;
  } else if (mechanics.lattice == PerforationLattice::Square) {
    r["mechanics"]["lattice_axis"] = {mechanics.lattice_axis.x(), mechanics.lattice_axis.y(), mechanics.lattice_axis.z()};
  }
  if (!mechanics.stiffness_curve.empty()) {
    const FillStiffnessCurve& c = mechanics.stiffness_curve;
    r["mechanics"]["stiffness_curve"] = {{"alpha", c.alpha}, {"membrane_ratio", c.membrane}, {"bending_ratio", c.bending}};
    if (c.split()) {
      nlohmann::json& j = r["mechanics"]["stiffness_curve"];
      j["membrane_bulk_ratio"] = c.membrane_bulk;
      j["membrane_shear_ratio"] = c.membrane_shear;
      j["bending_bulk_ratio"] = c.bending_bulk;
      j["bending_shear_ratio"] = c.bending_shear;
    }
    if (c.anisotropic()) {
      // q = (G₁ − G₂)/(G₁ + G₂): the square lattice's deviatoric moduli along its axes and at 45°.
      r["mechanics"]["stiffness_curve"]["membrane_anisotropy"] = c.membrane_anisotropy;
      r["mechanics"]["stiffness_curve"]["bending_anisotropy"] = c.bending_anisotropy;
    }
    // The cell problems' concentration factors K = peak / mean energy density (W_peak's; the
    // sample at α = 1 is the dilute limit).
    if (!c.membrane_concentration.empty()) {
      r["mechanics"]["stiffness_curve"]["membrane_concentration"] = c.membrane_concentration;
      r["mechanics"]["stiffness_curve"]["bending_concentration"] = c.bending_concentration;
    }
    // By the state's biaxiality ρ (rows: the samples; columns: ρ = −1 … 1).
    if (!c.membrane_concentration_by_biaxiality.empty()) {
      nlohmann::json& j = r["mechanics"]["stiffness_curve"];
      std::vector<double> nodes;
      for (int k = 0; k < kBiaxialityNodes; ++k) nodes.push_back(biaxiality_node(k));
      j["biaxiality"] = nodes;
      j["membrane_concentration_by_biaxiality"] = c.membrane_concentration_by_biaxiality;
      j["bending_concentration_by_biaxiality"] = c.bending_concentration_by_biaxiality;
    }
    // Each shape's weight in the curve (its share of the run's stencils by count), by name, and
    // each shape's own concentration factors (W_peak mixes them per face by the shapes' covered
    // fractions, peak_energy_density.h).
    if (!c.shape_weights.empty() || !c.shape_concentration.empty()) {
      const StencilLibrary shapes = scene_stencil_library(scene);
      nlohmann::json weights = nlohmann::json::object(), by_shape = nlohmann::json::object();
      for (const StencilShape& shape : shapes.shapes()) {
        const size_t k = size_t(shape.type);
        if (k < c.shape_weights.size()) weights[shape.name] = c.shape_weights[k];
        if (k < c.shape_concentration.size() && !c.shape_concentration[k].empty()) {
          const FillStiffnessCurve::ShapeConcentration& K = c.shape_concentration[k];
          nlohmann::json& j = by_shape[shape.name];
          j["membrane_concentration"] = K.membrane;
          j["bending_concentration"] = K.bending;
          if (!K.membrane_by_biaxiality.empty()) {
            j["membrane_concentration_by_biaxiality"] = K.membrane_by_biaxiality;
            j["bending_concentration_by_biaxiality"] = K.bending_by_biaxiality;
          }
          // Under the corner rule (or the tool's rounds): per sample, corner node major,
          // kBiaxialityNodes per node.
          if (!K.membrane_by_corner.empty()) {
            j["membrane_concentration_by_corner"] = K.membrane_by_corner;
            j["bending_concentration_by_corner"] = K.bending_by_corner;
          }
        }
      }
      if (!c.shape_weights.empty()) r["mechanics"]["stiffness_curve"]["shape_weights"] = weights;
      if (!by_shape.empty()) {
        r["mechanics"]["stiffness_curve"]["concentration_by_shape"] = by_shape;
        // The radius (m) the factors by corner are read at, its nodes in stencil bounding radii, and
        // what they are: the corner rule's about sharp corners, or the tool's rounds.
        std::vector<double> nodes;
        for (int k = 0; k < (c.tool_cut ? kToolNodes : kCornerNodes); ++k)
          nodes.push_back(c.tool_cut ? tool_node(k) : corner_node(k));
        r["mechanics"]["stiffness_curve"]["corner_nodes"] = nodes;
        r["mechanics"]["stiffness_curve"]["corner_factors"] = c.tool_cut ? "tool" : "corner_rule";
        r["mechanics"]["corner_radius"] = mechanics.corner_radius;
        r["mechanics"]["tool_radius"] = mechanics.tool_radius;
      }
    }
  }
  r["timings"] = timings_json(timings);
  return r;
}

nlohmann::json ligament_peak_json(const LigamentPeakSummary& summary, double thickness, int listed) {
  std::vector<int> order(summary.peaks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return summary.peaks[std::size_t(a)].W > summary.peaks[std::size_t(b)].W; });
  if (int(order.size()) > listed) order.resize(std::size_t(std::max(listed, 0)));
  auto point = [](const Vec3& p) { return nlohmann::json{p.x(), p.y(), p.z()}; };
  nlohmann::json worst = nlohmann::json::array();
  for (int i : order) {
    const Ligament& l = summary.ligaments[std::size_t(i)];
    const LigamentPeak& p = summary.peaks[std::size_t(i)];
    worst.push_back({{"W", p.W},
                     {"width", l.width},
                     {"radius_a", number_or_null(l.radius_a)},
                     {"radius_b", number_or_null(l.radius_b)},
                     {"neck_radius", p.neck_radius},
                     {"pair_radius", p.pair_radius},
                     {"x", number_or_null(p.x)},
                     {"x_bending", number_or_null(p.x_bending)},
                     {"x_lattice", number_or_null(p.x_lattice)},
                     {"factor", p.factor},
                     {"face", p.face},
                     {"W_peak_face", p.W_peak_face},
                     {"alpha_face", p.alpha},
                     {"point", point(l.midpoint())}});
  }
  return {{"rule", kLigamentPeakRule},
          {"searched", summary.ligaments.size()},
          {"search_width", kLigamentSearchWidth},
          {"narrowest", summary.ligaments.empty() ? nlohmann::json(nullptr) : nlohmann::json(summary.ligaments[0].width)},
          {"narrower_than_thickness", summary.narrower_than_thickness},
          {"thickness", thickness},
          {"W_ligament_max", number_or_null(summary.W_max)},
          {"worst", worst},
          {"units", {{"W", "J/m^2"}, {"width", "m"}, {"radius", "m"}}}};
}

void symmetry_plane_notes(const LoadCase& load_case, std::span<const StencilParams> stencils,
                          std::vector<std::string>& notes) {
  for (int a = 0; a < 3; ++a) {
    const double c = load_case.symmetry_planes[a];
    if (!std::isfinite(c)) continue;
    int crossing = 0;
    for (const StencilParams& s : stencils) crossing += std::abs(s.position[a] - c) < s.scale;
    if (crossing > 0)
      notes.push_back(fmt::format(
          "{} stencil{} over the symmetry plane {} = {:.4g}: the built shell, this half and its mirror image, has "
          "each such hole united with its mirror image, which the half's model cuts at the plane instead",
          crossing, crossing == 1 ? " reaches" : "s reach", char('x' + a), c));
  }
}

}  // namespace cutwork::solvers

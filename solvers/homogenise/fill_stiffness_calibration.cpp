#include "solvers/homogenise/fill_stiffness_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <tuple>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "host/core/error.h"
#include "host/pattern/lattice_order.h"
#include "host/pattern/pattern_context.h"

namespace cutwork::solvers {

namespace {

/// Ratios (membrane, bending) of one shape at every grid point.
struct ShapeCurve {
  std::vector<double> membrane, bending;
  std::vector<double> membrane_bulk, membrane_shear, bending_bulk, bending_shear;  ///< the isotropic split
  std::vector<double> membrane_concentration, bending_concentration;  ///< K (cell_homogenisation.h)
  /// K by biaxiality per sample (kBiaxialityNodes each)
  std::vector<std::vector<double>> membrane_concentration_by_biaxiality, bending_concentration_by_biaxiality;
  /// K by corner node and biaxiality per sample (kCornerNodes × kBiaxialityNodes each)
  std::vector<std::vector<double>> membrane_concentration_by_corner, bending_concentration_by_corner;
  std::vector<double> membrane_anisotropy, bending_anisotropy;  ///< q (the square lattice's)
};

/// Polygon, ν, resolution, rim edges, lattice, the fill ratios sampled, and whether by the tool.
using CacheKey = std::tuple<std::vector<double>, double, double, double, int, std::vector<double>, bool>;

/// The ratios of one sample, in ShapeCurve's order: membrane, bending, then the split's four.
using SampleRatios = std::array<double, 6>;

void push_ratios(ShapeCurve& c, const SampleRatios& r) {
  c.membrane.push_back(r[0]);
  c.bending.push_back(r[1]);
  c.membrane_bulk.push_back(r[2]);
  c.membrane_shear.push_back(r[3]);
  c.bending_bulk.push_back(r[4]);
  c.bending_shear.push_back(r[5]);
}

/// The cells of one shape's calibration, side by side: `jobs` cells, job k into cells[k]. Each runs
/// alone in an arena of one thread, so that a cell's CHOLMOD factorisation keeps one BLAS thread
/// (thread_policy.h: the arena's concurrency is its thread budget) and reads the same to the last bit
/// however many run beside it; their analyses' METIS orderings are drawn one at a time
/// (cholmod_solver.cpp). A cell's own work is serial (meshing, a factorisation of one thread): one
/// tool cell took 2.0 s alone in the default arena and in an arena of one, two side by side 2.3 s
/// on the two-core build machine.
void homogenise_side_by_side(size_t jobs, const std::function<CellStiffness(size_t)>& cell,
                             std::vector<CellStiffness>& cells) {
  cells.assign(jobs, CellStiffness{});
  // Isolated: the caller holds the calibration's lock (calibrate_fill_stiffness), and a thread that
  // waited here for the cells must not pick up another task that asks for that lock.
  tbb::this_task_arena::isolate([&] {
    tbb::parallel_for(size_t(0), jobs, [&](size_t k) {
      tbb::task_arena alone(1);
      alone.execute([&] { cells[k] = cell(k); });
    });
  });
}

ShapeCurve calibrate_shape(const StencilShape& shape, const Material& material, const CellOptions& options,
                           const std::vector<double>& grid, bool tool_cut) {
  const double lowest = 1 - max_hole_fraction(shape, 0.1, options.lattice);
  // The cells, one per distinct fill ratio (the grid's points below the lowest one share it), and
  // with a tool one per fill ratio and tool node τ_c at which the tool changes the shape's cell
  // (tool_changes_cell: a smooth shape, one no disc of τ_c fits, or one it changes by less than
  // τ_c/20, is its drawn cell, which is what that cell would be), all side by side.
  std::vector<double> cut;
  for (double alpha : grid)
    if (alpha < 1 && std::find(cut.begin(), cut.end(), std::max(alpha, lowest)) == cut.end())
      cut.push_back(std::max(alpha, lowest));
  std::vector<int> nodes;  // the tool nodes that change the cell
  if (tool_cut)
    for (int c = 0; c < kToolNodes; ++c)
      if (tool_changes_cell(shape, tool_node(c))) nodes.push_back(c);
  // Job k: the drawn cell at cut[k] for k < cut.size(), then the tool's cells fill ratio major.
  std::vector<CellStiffness> solved;
  homogenise_side_by_side(cut.size() * (1 + nodes.size()),
                          [&](size_t k) {
                            if (k < cut.size()) return homogenise_cell(shape, material, cut[k], options);
                            const size_t j = k - cut.size();
                            CellOptions o = options;
                            o.tool_radius = tool_node(nodes[j % nodes.size()]);
                            return homogenise_cell(shape, material, cut[j / nodes.size()], o);
                          },
                          solved);
  std::vector<CellStiffness> cells(solved.begin(), solved.begin() + std::ptrdiff_t(cut.size()));
  if (tool_cut)
    // The factors become the tool's (FillStiffnessCurve::tool_cut): by corner its nodes' K by
    // biaxiality, node major, kToolNodes × kBiaxialityNodes values; the plain ones its smallest
    // round's (node 0, the largest K; what a face of no known shape or radius reads).
    for (size_t k = 0; k < cut.size(); ++k) {
      CellStiffness& cell = cells[k];
      std::vector<double> membrane, bending;
      for (int c = 0; c < kToolNodes; ++c) {
        const auto at = std::find(nodes.begin(), nodes.end(), c);
        const CellStiffness& node =
            at == nodes.end() ? solved[k] : solved[cut.size() + k * nodes.size() + size_t(at - nodes.begin())];
        membrane.insert(membrane.end(), node.membrane_concentration_by_biaxiality.begin(),
                        node.membrane_concentration_by_biaxiality.end());
        bending.insert(bending.end(), node.bending_concentration_by_biaxiality.begin(),
                       node.bending_concentration_by_biaxiality.end());
      }
      cell.membrane_concentration_by_corner = std::move(membrane);
      cell.bending_concentration_by_corner = std::move(bending);
      const auto node0 = [](const std::vector<double>& table) {
        return std::vector<double>(table.begin(), table.begin() + kBiaxialityNodes);
      };
      cell.membrane_concentration_by_biaxiality = node0(cell.membrane_concentration_by_corner);
      cell.bending_concentration_by_biaxiality = node0(cell.bending_concentration_by_corner);
      cell.membrane_concentration = *std::max_element(cell.membrane_concentration_by_biaxiality.begin(),
                                                      cell.membrane_concentration_by_biaxiality.end());
      cell.bending_concentration = *std::max_element(cell.bending_concentration_by_biaxiality.begin(),
                                                     cell.bending_concentration_by_biaxiality.end());
    }
  const int corner_nodes = tool_cut ? kToolNodes : kCornerNodes;
  ShapeCurve c;
  for (double alpha : grid) {
    if (alpha >= 1) {
      push_ratios(c, {1, 1, 1, 1, 1, 1});
      c.membrane_anisotropy.push_back(0);
      c.bending_anisotropy.push_back(0);
      // The dilute limit: held at the last cut sample (a vanishing hole still concentrates stress).
      c.membrane_concentration.push_back(c.membrane_concentration.empty() ? 1 : c.membrane_concentration.back());
      c.bending_concentration.push_back(c.bending_concentration.empty() ? 1 : c.bending_concentration.back());
      for (auto* K : {&c.membrane_concentration_by_biaxiality, &c.bending_concentration_by_biaxiality})
        K->push_back(K->empty() ? std::vector<double>(kBiaxialityNodes, 1.0) : K->back());
      for (auto* K : {&c.membrane_concentration_by_corner, &c.bending_concentration_by_corner})
        K->push_back(K->empty() ? std::vector<double>(size_t(corner_nodes * kBiaxialityNodes), 1.0) : K->back());
      continue;
    }
    // Below the lowest fill ratio the lowest cell (K and q held; the ratios lowered after the loop).
    const CellStiffness& cell = cells[std::size_t(std::find(cut.begin(), cut.end(), std::max(alpha, lowest)) - cut.begin())];
    const double w = cell.window_fill_ratio;
    push_ratios(c, {cell.membrane_factor / w, cell.bending_factor / w, cell.membrane_bulk_factor / w,
                    cell.membrane_shear_factor / w, cell.bending_bulk_factor / w, cell.bending_shear_factor / w});
    c.membrane_concentration.push_back(cell.membrane_concentration);
    c.bending_concentration.push_back(cell.bending_concentration);
    c.membrane_concentration_by_biaxiality.push_back(cell.membrane_concentration_by_biaxiality);
    c.bending_concentration_by_biaxiality.push_back(cell.bending_concentration_by_biaxiality);
    c.membrane_concentration_by_corner.push_back(cell.membrane_concentration_by_corner);
    c.bending_concentration_by_corner.push_back(cell.bending_concentration_by_corner);
    c.membrane_anisotropy.push_back(cell.membrane_anisotropy);
    c.bending_anisotropy.push_back(cell.bending_anisotropy);
  }
  // Below the lowest fill ratio no lattice of the shape exists and no cell says what it does; the
  // stiffness ratios continue the secant of the lowest two samples down to the fixed grid's point
  // below the lowest (an interval of the grid at most), and are held from there (at least half the
  // lowest sample's ratio). Held flat from the lowest itself, the interpolating cubic would start
  // with zero slope there and lag the cells above it: the default star read 5% soft at α 0.67
  // (membrane bulk ratio) where its cells rise steeply.
  const auto at = std::find(grid.begin(), grid.end(), lowest);
  const std::vector<double>& fixed = calibration_grid();
  const auto fixed_below = std::lower_bound(fixed.begin(), fixed.end(), lowest);
  if (at != grid.end() && at != grid.begin() && fixed_below != fixed.begin()) {
    const size_t kl = size_t(at - grid.begin());
    const double floor_alpha = *(fixed_below - 1);
    for (std::vector<double>* r : {&c.membrane, &c.bending, &c.membrane_bulk, &c.membrane_shear, &c.bending_bulk,
                                   &c.bending_shear}) {
      const double slope = std::max(0.0, ((*r)[kl + 1] - (*r)[kl]) / (grid[kl + 1] - grid[kl]));
      for (size_t k = 0; k < kl; ++k)
        (*r)[k] = std::max((*r)[kl] - slope * (lowest - std::max(grid[k], floor_alpha)), (*r)[kl] / 2);
    }
  }
  return c;
}

/// The material every calibration runs with: only ν is the design's. The ratios depend on ν alone
/// in exact arithmetic, but the cell solve's round-off depends on E and h; with the cache keyed by
/// ν, a sweep over thickness would otherwise see the curve of whichever variant calibrated first,
/// and its results would depend on the order the variants ran in.
Material canonical_material(double poisson_ratio) {
  Material m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = poisson_ratio;
  m.thickness = 0.05;  // in lattice spacings: a plate of a twentieth of the spacing
  m.density = 1000;
  return m;
}

}  // namespace

const std::vector<double>& calibration_grid() {
  static const std::vector<double> grid = {0.3, 0.45, 0.6, 0.75, 0.9, 1.0};
  return grid;
}

std::vector<double> calibration_samples(const StencilLibrary& shapes, CellLattice lattice,
                                        const std::vector<double>& weights) {
  std::vector<double> samples = calibration_grid();
  for (const StencilShape& shape : shapes.shapes()) {
    if (!weights.empty() && !(weights.at(size_t(shape.type)) > 0)) continue;
    const double lowest = 1 - max_hole_fraction(shape, 0.1, lattice);
    if (lowest <= samples.front() || lowest >= 1) continue;
    const auto at = std::lower_bound(samples.begin(), samples.end(), lowest);
    if (std::abs(*at - lowest) > 1e-9 && (at == samples.begin() || std::abs(*(at - 1) - lowest) > 1e-9))
      samples.insert(at, lowest);
  }
  return samples;
}

std::vector<double> shape_weights(const StencilLibrary& shapes, std::span<const StencilParams> stencils) {
  const size_t n = size_t(shapes.size());
  if (stencils.empty()) return std::vector<double>(n, 1.0 / double(n));
  std::vector<double> w(n, 0.0);
  for (const StencilParams& s : stencils) {
    if (s.type < 0 || size_t(s.type) >= n)
      throw InputError(fmt::format("homogenised stiffness: a stencil of type {} in a library of {} shapes", s.type, n));
    w[size_t(s.type)] += 1.0 / double(stencils.size());
  }
  return w;
}

FillStiffnessCurve calibrate_fill_stiffness(const StencilLibrary& shapes, const Material& material,
                                            const CellOptions& options, std::vector<double> weights, bool tool_cut) {
  if (shapes.size() < 1) throw InputError("homogenised stiffness: the design has no stencil shape");
  if (weights.empty()) weights.assign(size_t(shapes.size()), 1.0 / shapes.size());
  double total = 0;
  for (const double w : weights) {
    if (!(std::isfinite(w) && w >= 0)) throw InputError(fmt::format("homogenised stiffness: shape weight {}", w));
    total += w;
  }
  if (weights.size() != size_t(shapes.size()) || !(total > 0))
    throw InputError(fmt::format("homogenised stiffness: {} shape weights (sum {}) for {} shapes", weights.size(),
                                 total, shapes.size()));
  for (double& w : weights) w /= total;
  static std::mutex mutex;
  static std::map<CacheKey, ShapeCurve> cache;
  const std::vector<double> grid = calibration_samples(shapes, options.lattice, weights);
  FillStiffnessCurve out;
  out.alpha = grid;
  out.shape_weights = weights;
  out.tool_cut = tool_cut;
  for (std::vector<double>* r : {&out.membrane, &out.bending, &out.membrane_bulk, &out.membrane_shear,
                                  &out.bending_bulk, &out.bending_shear})
    r->assign(grid.size(), 0.0);
  out.membrane_concentration.assign(grid.size(), 1.0);
  out.bending_concentration.assign(grid.size(), 1.0);
  out.membrane_concentration_by_biaxiality.assign(grid.size(), std::vector<double>(kBiaxialityNodes, 1.0));
  out.bending_concentration_by_biaxiality.assign(grid.size(), std::vector<double>(kBiaxialityNodes, 1.0));
  // The hexagonal lattice is isotropic (its cells' q is round-off): no anisotropic part.
  const bool square = options.lattice == CellLattice::Square;
  if (square) {
    out.membrane_anisotropy.assign(grid.size(), 0.0);
    out.bending_anisotropy.assign(grid.size(), 0.0);
  }
  out.shape_concentration.resize(size_t(shapes.size()));
  for (const StencilShape& shape : shapes.shapes()) {
    const double w = weights[size_t(shape.type)];
    if (w == 0) continue;
    std::vector<double> polygon;
    for (const Vec2& p : shape.polygon) polygon.insert(polygon.end(), {p.x(), p.y()});
    const CacheKey key{polygon, material.poisson_ratio, options.resolution, options.rim_edges, int(options.lattice),
                       grid, tool_cut};
    // One calibration at a time in the process, the cache looked up again under the lock: a
    // caller that waited finds the curve another computed (a sweep's concurrent variants calibrate
    // once); the shape's cells run side by side inside it (homogenise_side_by_side). Two cell
    // problems of 25k DOFs factorised at once in two threads (α = 0.9 at 96 edges per spacing)
    // used to differ in the 14th digit now and then, and a sweep's variants with them
    // (SweepCommand.LocalAndMpiRunsAgree), smaller ones (under 20k DOFs: AMD) never: their METIS
    // orderings drew from one random generator at once. Analyses with METIS are now one at a time
    // (CholmodSolver::analyze), and cells side by side read as they do one after the other.
    std::unique_lock lock(mutex);
    auto it = cache.find(key);
    if (it == cache.end())
      it = cache.emplace(key, calibrate_shape(shape, canonical_material(material.poisson_ratio), options, grid, tool_cut)).first;
    const ShapeCurve c = it->second;
    lock.unlock();
    out.shape_concentration[size_t(shape.type)] = {c.membrane_concentration, c.bending_concentration,
                                                   c.membrane_concentration_by_biaxiality,
                                                   c.bending_concentration_by_biaxiality,
                                                   c.membrane_concentration_by_corner,
                                                   c.bending_concentration_by_corner};
    for (size_t k = 0; k < grid.size(); ++k) {
      out.membrane[k] += w * c.membrane[k];
      out.bending[k] += w * c.bending[k];
      out.membrane_bulk[k] += w * c.membrane_bulk[k];
      out.membrane_shear[k] += w * c.membrane_shear[k];
      out.bending_bulk[k] += w * c.bending_bulk[k];
      out.bending_shear[k] += w * c.bending_shear[k];
      if (square) {
        out.membrane_anisotropy[k] += w * c.membrane_anisotropy[k];
        out.bending_anisotropy[k] += w * c.bending_anisotropy[k];
      }
      // Peaks: the worst shape the design uses (a face's α does not say which shape cut it).
      out.membrane_concentration[k] = std::max(out.membrane_concentration[k], c.membrane_concentration[k]);
      out.bending_concentration[k] = std::max(out.bending_concentration[k], c.bending_concentration[k]);
      for (int j = 0; j < kBiaxialityNodes; ++j) {
        double& km = out.membrane_concentration_by_biaxiality[k][size_t(j)];
        double& kb = out.bending_concentration_by_biaxiality[k][size_t(j)];
        km = std::max(km, c.membrane_concentration_by_biaxiality[k][size_t(j)]);
        kb = std::max(kb, c.bending_concentration_by_biaxiality[k][size_t(j)]);
      }
    }
  }
  // Exactly 1 at α = 1, whatever the rounding of the mean.
  out.membrane.back() = out.bending.back() = 1.0;
  out.membrane_bulk.back() = out.membrane_shear.back() = out.bending_bulk.back() = out.bending_shear.back() = 1.0;
  if (square) out.membrane_anisotropy.back() = out.bending_anisotropy.back() = 0.0;
  return out;
}

MechanicsSettings measured_lattice(const MechanicsSettings& mechanics, const FaceBvh& bvh, const TangentField& field,
                                   std::span<const StencilParams> stencils, std::vector<std::string>& notes) {
  MechanicsSettings m = mechanics;
  if (m.lattice_source != LatticeSource::Scene && !stencils.empty()) {
    RowMatX3d centres, normals, tangents;
    stencil_frames(bvh, field, stencils, centres, normals, &tangents);
    const MeasuredLattice measured = measure_lattice(centres, normals, &tangents);
    m.lattice_source = LatticeSource::Stencils;
    m.lattice = measured.square ? PerforationLattice::Square : PerforationLattice::Hexagonal;
    m.lattice_axis = measured.square && !measured.follows_field ? measured.axis : Vec3::UnitX();
    m.lattice_follows_field = measured.follows_field;
    m.lattice_field_angle = measured.follows_field ? measured.field_angle : 0.0;
    if (measured.turning)
      notes.push_back(fmt::format(
          "the stencils lie on a square lattice (median |psi4| {:.2f}) whose axes turn over the surface (a median "
          "{:.0f} degrees from the best single axis) and do not follow the orientation field either (a median {:.0f} "
          "degrees from it): the model takes the isotropic (hexagonal) calibration, which is up to a third off in "
          "stretch along or at 45 degrees to the axes",
          measured.order.square, measured.order.axis_misfit, measured.field_misfit));
  }
  attach_lattice_field(m, bvh, field);
  return m;
}

MechanicsSettings resolve_fill_stiffness(const MechanicsSettings& mechanics, const StencilLibrary& shapes,
                                         const Material& material, std::span<const StencilParams> stencils) {
  MechanicsSettings m = mechanics;
  if (m.stiffness == FillStiffness::Homogenised && m.stiffness_curve.empty()) {
    CellOptions options;
    options.lattice = m.lattice == PerforationLattice::Square ? CellLattice::Square : CellLattice::Hexagonal;
    m.stiffness_curve =
        calibrate_fill_stiffness(shapes, material, options, shape_weights(shapes, stencils), m.tool_radius > 0);
  }
  return m;
}

MechanicsSettings scene_mechanics(const Scene& scene, std::span<const StencilParams> stencils) {
  if (scene.mechanics.stiffness == FillStiffness::Linear) return scene.mechanics;
  return resolve_fill_stiffness(scene.mechanics, scene_stencil_library(scene), scene.material, stencils);
}

MechanicsSettings uncut_scene_mechanics(const Scene& scene) {
  MechanicsSettings m = scene_mechanics(scene);
  if (!m.lattice_axis_at) m.lattice_follows_field = false;
  return m;
}

CellFilter scene_cell_filter(const Scene& scene, const PatternContext& ctx, const SurfaceMesh& sim) {
  if (scene.mechanics.filter == FillFilter::None) return {};
  const int nf = sim.num_faces();
  const RowMatX3d& V = sim.vertices();
  const RowMatX3i& F = sim.faces();
  const PatternSurface& surface = ctx.surface();
  // The length the blend measures a triangle against: the narrowest shape's hydraulic diameter
  // 4A/P (its bounding diameter for a circle; 0.44 of it for the default star), because the faces a
  // stencil's outline cuts are a band of width ~h along P, a fraction ~4h/(4A/P) of its area.
  double resolved = 1;
  for (const StencilShape& shape : ctx.shapes().shapes())
    resolved = std::min(resolved, stencil_hydraulic_diameter(shape) / 2);
  Eigen::VectorXd spacing(nf), diameter(nf);
  for (int t = 0; t < nf; ++t) {
    const Vec3 c = (V.row(F(t, 0)) + V.row(F(t, 1)) + V.row(F(t, 2))).transpose() / 3.0;
    const double sigma = surface.sizing_at(surface.bvh().closest_point(c).where);
    diameter[t] = 2 * ctx.unit() * sigma * resolved;
    spacing[t] = (1 + scene.pattern.s) * 2 * ctx.unit() * sigma;
  }
  // Faces at a clamp keep their own α, and no other face's cell counts them (cell_filter.h).
  const LoadCase load_case = resolve_load_case(scene, sim);
  std::vector<bool> at_clamp(size_t(nf), false);
  for (int t = 0; t < nf; ++t)
    for (int k = 0; k < 3; ++k) at_clamp[size_t(t)] = at_clamp[size_t(t)] || load_case.clamped[size_t(F(t, k))];
  return CellFilter(sim, spacing, diameter, &at_clamp, load_case.symmetry_planes);
}

}  // namespace cutwork::solvers

#include "host/pattern/pattern_context.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "host/field/orientation_field.h"
#include "host/pattern/exemplar.h"
#include "host/pattern/poisson_disk.h"

namespace cutwork {

namespace {

/// Random sequential packing of exclusion disks saturates at ~54.7% of the area (Feder 1980);
/// the automatic unit uses it to relate a stencil count to a Poisson-disk scale.
constexpr double kPoissonJamming = 0.547;
/// The automatic unit aims at the paper's stencil counts (Table 1: 185–462).
constexpr double kAutomaticCount = 300;

/// Mean number of elements within r_N·size of the exemplar's elements (itself excluded).
double mean_neighbourhood_size(const Exemplar& ex, double r_N) {
  const double R = r_N * ex.size();
  double sum = 0;
  int count = 0;
  for (const auto& a : ex.elements) {
    if (ex.distance_to_boundary(a.position) < R) continue;
    for (const auto& b : ex.elements)
      if (&a != &b && (a.position - b.position).norm() <= R) ++sum;
    ++count;
  }
  return count ? sum / count : 1.0;
}

}  // namespace

StencilLibrary scene_stencil_library(const Scene& scene) {
  StencilLibrary lib;
  if (scene.shapes.empty()) {
    lib.add(make_builtin_stencil("circle", {}, "circle"));
    return lib;
  }
  for (const StencilShapeSpec& s : scene.shapes)
    lib.add(s.kind == "polygon" ? make_polygon_stencil(s.name, s.polygon)
                                : make_builtin_stencil(s.kind, s.params, s.name));
  return lib;
}

PatternContext::PatternContext(const Scene& scene, const SceneMeshes& meshes)
    : m_settings(scene.pattern), m_shapes(scene_stencil_library(scene)) {
  const PatternSettings& ps = m_settings;
  const SurfaceMesh& mesh = meshes.base;
  const std::string origin = scene_origin(scene);
  m_kind = ps.objective == PatternObjective::Exemplar ? PatternKind::Exemplar : PatternKind::Packing;

  // Exemplar first: its symmetry constrains the field's.
  std::optional<Exemplar> ex;
  std::vector<int> ex_types;
  std::vector<std::string> names;
  for (const auto& s : m_shapes.shapes()) names.push_back(s.name);
  if (m_kind == PatternKind::Exemplar) {
    ex = ps.exemplar_inline.is_null() ? builtin_exemplar(ps.exemplar)
                                      : parse_exemplar(ps.exemplar_inline, origin, "/pattern/exemplar");
    ex_types = map_exemplar_types(*ex, names, origin, "/pattern/exemplar");
  }

  std::vector<int> orders;
  for (const auto& s : m_shapes.shapes()) orders.push_back(polygon_symmetry_order(s.polygon));
  m_symmetry = ps.symmetry > 0 ? ps.symmetry : field_symmetry_for(orders, ex ? ex->symmetry : 0);
  for (size_t k = 0; k < orders.size(); ++k)
    if (orders[k] <= 12 && orders[k] % m_symmetry != 0)
      m_notes.push_back(fmt::format(
          "pattern.symmetry {} does not divide the {}-fold symmetry of stencil '{}': its orientation "
          "follows the field only up to a turn of 360°/{}",
          m_symmetry, orders[k], names[k], m_symmetry));

  SizingField sizing = SizingField::from_settings(ps, mesh);
  const double mean_inv2 = sizing.mean_power(mesh, -2.0);
  double area = mesh.face_areas().sum();
  // A half (quarter, eighth) on symmetry planes stands for the whole: the automatic scale is the
  // whole's (an explicit pattern.count counts the model's stencils).
  const Vec3 planes = scene_symmetry_planes(scene, meshes.sim);
  const int copies = 1 << int(planes.array().isFinite().count());
  const double one_plus_s = 1 + ps.s;

  // The unit ℓ (nominal stencil scale) and the exemplar's σ_0.
  double sigma0 = 0;
  if (ps.scale > 0) {
    m_unit = ps.scale;
  } else {
    const double count = ps.count > 0 ? double(ps.count) : kAutomaticCount / copies;
    if (m_kind == PatternKind::Packing) {
      m_unit = std::sqrt(kPoissonJamming * area * mean_inv2 / (std::numbers::pi * one_plus_s * one_plus_s * count));
    } else {
      sigma0 = std::sqrt(double(ex->elements.size()) / ex->area() * area * mean_inv2 / count);
      m_unit = sigma0 * ex->mean_scale();
    }
    if (ps.count == 0) {
      // A stencil at least a triangle across keeps the cut surface meshable.
      const double floor = 0.5 * mesh.mean_edge_length();
      if (m_unit < floor) {
        m_notes.push_back(fmt::format(
            "automatic stencil scale raised from {:.4g} m to half the base mesh's edge length {:.4g} m",
            m_unit, floor));
        m_unit = floor;
        sigma0 = 0;
      }
      m_notes.push_back(fmt::format("automatic stencil scale: {:.4g} m", m_unit));
    }
  }
  if (m_kind == PatternKind::Exemplar && !(sigma0 > 0)) sigma0 = m_unit / ex->mean_scale();

  // Boundary buckets about the reach of the largest stencil's boundary term.
  const double reach = 2 * one_plus_s * m_unit * sizing.max_value() * std::max(1.0, ps.scale_max);
  OrientationFieldOptions fo;
  fo.symmetry = m_symmetry;
  fo.strokes = ps.strokes;
  fo.stroke_weight = ps.stroke_weight;
  fo.mirror_planes = planes;
  // On symmetry planes the pattern sees its mirror images across them.
  m_surface = std::make_unique<PatternSurface>(mesh, fo, std::move(sizing), reach, planes);
  m_epsilon = ps.epsilon * m_surface->length();

  PatternEnergySettings es;
  es.kind = m_kind;
  es.safety = ps.s;
  es.epsilon = m_epsilon;
  es.unit = m_unit;
  if (m_kind == PatternKind::Exemplar) {
    // Every stencil is pulled by the DET springs of all neighbourhoods it belongs to (about
    // the exemplar's neighbourhood size k), so the collision stiffness scales with k to keep
    // the residue of the penalty as small as in the packing objective.
    es.weights.collision *= std::max(1.0, mean_neighbourhood_size(*ex, ps.r_N));
    DetSettings ds;
    ds.r_N = ps.r_N;
    ds.xi = ps.xi;
    ds.sigma = sigma0;
    ds.unit = m_unit;
    ds.symmetry = m_symmetry;
    ds.safety = ps.s;
    m_exemplar = std::make_unique<DetExemplar>(std::move(*ex), ex_types, ds);
  }
  m_energy = std::make_unique<PatternEnergy>(*m_surface, es, m_exemplar.get());
}

StencilLayout PatternContext::initialize(PatternRng& rng) const {
  StencilLayout layout;
  fill_holes(layout, rng);
  return layout;
}

int PatternContext::fill_holes(StencilLayout& layout, PatternRng& rng) const {
  if (m_kind == PatternKind::Packing) {
    PoissonDiskOptions o;
    o.unit = m_unit;
    o.safety = m_settings.s;
    o.count = m_settings.count;
    o.num_types = m_shapes.size();
    return poisson_disk_sample(*m_surface, layout, rng, o);
  }
  return det_grow(*m_exemplar, *m_surface, layout, rng, DetGrowthOptions{}).added;
}

void PatternContext::scale_bounds(const StencilLayout& layout, Eigen::VectorXd& lower,
                                  Eigen::VectorXd& upper) const {
  const int S = int(layout.size());
  lower.resize(S);
  upper.resize(S);
  double lo = m_unit, hi = m_unit;
  if (m_exemplar) {
    lo = INFINITY;
    hi = 0;
    for (const auto& e : m_exemplar->exemplar().elements) {
      lo = std::min(lo, e.scale);
      hi = std::max(hi, e.scale);
    }
    lo *= m_exemplar->settings().sigma;
    hi *= m_exemplar->settings().sigma;
  }
  for (int i = 0; i < S; ++i) {
    const double z = m_surface->sizing_at(layout[size_t(i)].where);
    lower[i] = m_settings.scale_min * lo * z;
    upper[i] = m_settings.scale_max * hi * z;
  }
}

}  // namespace cutwork

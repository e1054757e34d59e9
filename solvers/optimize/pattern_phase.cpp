#include "solvers/optimize/pattern_phase.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/timer.h"
#include "host/field/orientation_field.h"
#include "host/pattern/exemplar.h"
#include "host/pattern/overlaps.h"
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
  const double one_plus_s = 1 + ps.s;

  // The unit ℓ (nominal stencil scale) and the exemplar's σ_0.
  double sigma0 = 0;
  if (ps.scale > 0) {
    m_unit = ps.scale;
  } else {
    const double count = ps.count > 0 ? double(ps.count) : kAutomaticCount;
    if (m_kind == PatternKind::Packing) {
      m_unit = std::sqrt(kPoissonJamming * area * mean_inv2 / (M_PI * one_plus_s * one_plus_s * count));
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
  m_surface = std::make_unique<PatternSurface>(mesh, fo, std::move(sizing), reach);
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

std::vector<StencilParams> PatternPhaseResult::params() const {
  std::vector<StencilParams> out;
  out.reserve(layout.size());
  for (const auto& s : layout) out.push_back({s.position, s.scale, s.angle, s.type});
  return out;
}

namespace {

bool same_matching(const std::vector<DetNeighborhood>& a, const std::vector<DetNeighborhood>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].center != b[i].center || a[i].rotation != b[i].rotation || a[i].outputs != b[i].outputs ||
        a[i].matches != b[i].matches)
      return false;
  return true;
}

}  // namespace

double joint_objective(const PatternEnergy& energy, JointTerm* joint, double w_P, std::vector<StencilParams>& params,
                       const Eigen::VectorXi& types, Eigen::VectorXd* gradient) {
  if (joint) joint->restore(params);
  const int S = int(params.size());
  RowMatX3d q(S, 3);
  Eigen::VectorXd s(S);
  for (int i = 0; i < S; ++i) {
    q.row(i) = params[size_t(i)].position.transpose();
    s[i] = params[size_t(i)].scale;
  }
  RowMatX3d dq;
  Eigen::VectorXd ds;
  const bool g = gradient != nullptr;
  double v = w_P * energy.evaluate(q, s, types, g ? &dq : nullptr, g ? &ds : nullptr);
  if (joint) {
    v += joint->evaluate(params, gradient);
  } else if (g) {
    gradient->setZero(5 * S);
  }
  if (!g) return v;
  if (!std::isfinite(v)) {
    gradient->setConstant(5 * S, std::nan(""));
    return v;
  }
  for (int i = 0; i < S; ++i) {
    gradient->segment<3>(5 * i) += w_P * dq.row(i).transpose();
    (*gradient)[5 * i + 3] += w_P * ds[i];
  }
  if (joint) joint->restore_pullback(*gradient);
  return v;
}

void optimize_pattern(PatternContext& ctx, StencilLayout& layout, const PatternPhaseOptions& options,
                      PatternPhaseResult& result) {
  Stopwatch clock;
  const bool exemplar = ctx.kind() == PatternKind::Exemplar;
  const int budget = options.max_iterations >= 0 ? options.max_iterations : ctx.settings().max_iterations;
  const int per_round = options.iterations_per_round > 0 ? options.iterations_per_round : (exemplar ? 20 : 100);
  const double unit = ctx.unit();
  PatternEnergy& energy = ctx.energy();
  const PatternSurface& surface = ctx.surface();
  JointTerm* joint = options.joint;
  const double w_P = joint ? options.w_P : 1.0;
  // Variables per stencil, x = (q/ℓ, s/ℓ[, φ]): positions first (#S×3), then scales, then the
  // angles when the joint term sees them (P does not depend on φ).
  const int dofs = joint ? 5 : 4;

  Eigen::VectorXd lower, upper;
  ctx.scale_bounds(layout, lower, upper);
  Eigen::VectorXd angle0(Eigen::Index(layout.size()));
  for (size_t i = 0; i < layout.size(); ++i) angle0[Eigen::Index(i)] = layout[i].angle;
  std::vector<DetNeighborhood> previous;
  int used = 0;
  double scale = 0;  // the optimiser's last inverse-curvature estimate, scaling the next round's first step
  bool stopped_by_callback = false;
  bool matched = false;  // the neighbourhoods of the current layout are frozen in `energy`
  result.stop_reason = budget == 0 ? "iterations" : "";
  std::vector<StencilParams> params;
  Eigen::VectorXd g_params;
  double best_round_end = INFINITY;
  int stalled_rounds = 0;
  while (used < budget && !layout.empty() && !stopped_by_callback) {
    if (!matched) energy.rematch(layout);
    matched = false;
    const int S = int(layout.size());
    const Eigen::VectorXi types = layout_types(layout);
    Eigen::VectorXd x0(dofs * S), lb(dofs * S), ub(dofs * S);
    for (int i = 0; i < S; ++i) {
      x0.segment<3>(3 * i) = layout[size_t(i)].position / unit;
      x0[3 * S + i] = layout[size_t(i)].scale / unit;
      if (joint) x0[4 * S + i] = layout[size_t(i)].angle;
    }
    lb.head(3 * S).setConstant(-INFINITY);
    ub.head(3 * S).setConstant(INFINITY);
    lb.segment(3 * S, S) = lower / unit;
    ub.segment(3 * S, S) = upper / unit;
    if (joint) {
      lb.tail(S) = angle0.head(S).array() - options.max_rotation;
      ub.tail(S) = angle0.head(S).array() + options.max_rotation;
    }
    // x → stencil parameters (restored onto the joint term's constraint).
    auto unpack = [&](const Eigen::VectorXd& x) {
      params.resize(size_t(S));
      for (int i = 0; i < S; ++i)
        params[size_t(i)] = {x.segment<3>(3 * i) * unit, x[3 * S + i] * unit,
                             joint ? x[4 * S + i] : layout[size_t(i)].angle, types[i]};
    };
    double last_gradient_norm = 0;
    auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
      unpack(x);
      const double v = joint_objective(energy, joint, w_P, params, types, &g_params);
      g.resize(x.size());
      for (int i = 0; i < S; ++i) {
        g.segment<3>(3 * i) = g_params.segment<3>(5 * i) * unit;
        g[3 * S + i] = g_params[5 * i + 3] * unit;
        if (joint) g[4 * S + i] = g_params[5 * i + 4];
      }
      last_gradient_norm = g.norm();
      return v;
    };
    LbfgsbOptions lo;
    lo.max_iterations = std::min(per_round, budget - used);
    lo.first_scale = scale;
    const int round = result.rounds;
    auto cb = [&](int it, const Eigen::VectorXd&, double fx) {
      if (!options.progress) return true;
      PatternProgress p{"optimise", round, used + it, fx, S, clock.seconds(), last_gradient_norm};
      if (joint) {
        p.structure = joint->last_structure();
        p.W_max = joint->last_W_max();
      }
      if (!options.progress(p)) {
        stopped_by_callback = true;
        return false;
      }
      return true;
    };
    const LbfgsbResult res = minimize_lbfgsb(f, x0, lb, ub, lo, cb);
    // A round that moved nothing still spends one iteration of the budget: two matchings of
    // equal cost can alternate forever otherwise.
    used += std::max(1, res.iterations);
    if (res.scale > 0) scale = res.scale;
    result.iterations += res.iterations;
    result.evaluations += res.evaluations;
    result.round_histories.push_back(res.history);
    ++result.rounds;
    // The phase's reason: the optimiser's own ("gradient", "decrease", a line-search failure,
    // "callback"), "iterations" when the budget is spent, or "stalled" (below).
    if (res.converged || res.stop_reason == "callback" || res.stop_reason.rfind("line search", 0) == 0)
      result.stop_reason = res.stop_reason;
    else
      result.stop_reason = used >= budget ? "iterations" : "round";  // "round": the loop goes on
    unpack(res.x);
    if (joint) joint->restore(params);
    for (int i = 0; i < S; ++i) {
      const ClosestPoint cp = surface.project(params[size_t(i)].position);
      PlacedStencil& st = layout[size_t(i)];
      st.position = cp.point;
      st.where = cp.where;
      // L-BFGS-B keeps x inside the bounds; a restoration may scale past them (by design).
      st.scale = joint ? params[size_t(i)].scale : std::clamp(params[size_t(i)].scale, lower[i], upper[i]);
      st.angle = params[size_t(i)].angle;
    }
    bool settled = res.converged;
    if (exemplar) {
      energy.rematch(layout);
      matched = true;  // MWT11: match, vote, then optimise against this matching
      const int changes = det_vote_types(*ctx.exemplar(), energy.neighborhoods(), layout);
      result.type_changes += changes;
      // Converged without moving and no vote changed a type: the next round would start from
      // the same point, whatever the (possibly tie-broken differently) matching.
      settled = settled && changes == 0 && (res.iterations == 0 || same_matching(previous, energy.neighborhoods()));
      previous = energy.neighborhoods();
    }
    // Stalled: three rounds in a row ended less than round_tolerance (relative) below the best
    // round end so far. For exemplars each re-matching then takes back what the round gained;
    // for packing the growth term creeps on against the bounds.
    const double end = res.history.back();
    if (end < best_round_end - options.round_tolerance * std::max(1.0, std::abs(end))) {
      best_round_end = end;
      stalled_rounds = 0;
    } else {
      ++stalled_rounds;
    }
    if (!settled && stalled_rounds >= 3) {
      settled = true;
      result.stop_reason = "stalled";
    }
    if (settled) break;
  }

  // The lower bounds of the run (taken at the stencils' start) are the floor of the shrinking.
  // A joint term's restoration may have scaled a stencil below its bound on purpose; such a
  // stencil is removed only when it would lose more than a quarter of its size.
  Eigen::VectorXd floor = lower;
  if (joint)
    for (size_t i = 0; i < layout.size(); ++i)
      floor[Eigen::Index(i)] = 0.75 * std::min(lower[Eigen::Index(i)], layout[i].scale);
  result.removed += resolve_overlaps(surface, layout, ctx.settings().s, floor);
  if (joint) joint->finalize(surface, ctx.settings().s, layout);
  result.seconds_optimize += clock.seconds();
}

PatternPhaseResult run_pattern_phase(PatternContext& ctx, const PatternPhaseOptions& options) {
  Stopwatch clock;
  PatternPhaseResult result;
  result.objective = ctx.kind() == PatternKind::Exemplar ? "exemplar" : "packing";
  if (ctx.exemplar()) result.exemplar = ctx.exemplar()->exemplar().name;
  result.field_symmetry = ctx.symmetry();
  result.unit = ctx.unit();
  result.epsilon = ctx.epsilon();
  result.notes = ctx.notes();

  PatternRng rng(ctx.settings().seed);
  StencilLayout layout = ctx.initialize(rng);
  result.initial_count = int(layout.size());
  result.seconds_initialize = clock.seconds();
  if (options.progress) options.progress({"initialise", 0, 0, 0.0, int(layout.size()), clock.seconds()});
  if (layout.empty())
    throw InputError(fmt::format(
        "{}: no stencil fits on the surface at scale {:.4g} m with safety factor {:.4g}; lower "
        "pattern.scale or pattern.s",
        ctx.settings().objective == PatternObjective::Exemplar ? "pattern (exemplar)" : "pattern",
        ctx.unit(), ctx.settings().s));

  ctx.energy().rematch(layout);
  result.objective_start = ctx.energy().evaluate(layout);
  if (options.optimize) {
    optimize_pattern(ctx, layout, options, result);
    // §6.3: re-run the initialisation on the converged layout, optimise again if it grew.
    for (int k = 0; options.fill_holes && k < options.max_fill_rounds; ++k) {
      const int added = ctx.fill_holes(layout, rng);
      result.inserted_by_hole_filling += added;
      if (added == 0) break;
      optimize_pattern(ctx, layout, options, result);
    }
  } else {
    Eigen::VectorXd lower, upper;
    ctx.scale_bounds(layout, lower, upper);
    result.removed = resolve_overlaps(ctx.surface(), layout, ctx.settings().s, lower);
  }
  ctx.energy().rematch(layout);
  result.objective_end = ctx.energy().evaluate(layout, &result.terms_end);

  const int S = int(layout.size());
  result.normals.resize(S, 3);
  result.tangents.resize(S, 3);
  result.bounding_radii.resize(S);
  for (int i = 0; i < S; ++i) {
    Vec3 n, t, b;
    ctx.surface().frame_at(layout[size_t(i)].where, n, t, b);
    result.normals.row(i) = n.transpose();
    result.tangents.row(i) = t.transpose();
    result.bounding_radii[i] = layout[size_t(i)].scale;
  }
  result.layout = std::move(layout);
  result.seconds = clock.seconds();
  return result;
}

PatternPhaseResult run_pattern_phase(const Scene& scene, const SceneMeshes& meshes,
                                     const PatternPhaseOptions& options) {
  PatternContext ctx(scene, meshes);
  return run_pattern_phase(ctx, options);
}

}  // namespace cutwork

#include "solvers/optimize/joint_optimizer.h"

#include <algorithm>
#include <cmath>

#include "host/core/timer.h"
#include "host/pattern/overlaps.h"
#include "solvers/optimize/lbfgsb.h"

namespace cutwork::solvers {

namespace {

bool same_matching(const std::vector<DetNeighborhood>& a, const std::vector<DetNeighborhood>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].center != b[i].center || a[i].rotation != b[i].rotation || a[i].outputs != b[i].outputs ||
        a[i].matches != b[i].matches)
      return false;
  return true;
}

/// The optimiser's variables x = (q/ℓ, s/ℓ[, φ]) of a layout (see the file comment), their
/// bounds, and the maps between x and the stencil parameters.
class JointVariables {
 public:
  JointVariables(const StencilLayout& layout, const JointOptimizerState& bounds, double unit, bool angles,
                 double max_rotation)
      : m_layout(layout), m_unit(unit), m_angles(angles), m_S(int(layout.size())), m_types(layout_types(layout)) {
    const int S = m_S, n = (angles ? 5 : 4) * S;
    x0.resize(n);
    lb.resize(n);
    ub.resize(n);
    for (int i = 0; i < S; ++i) {
      x0.segment<3>(3 * i) = layout[size_t(i)].position / unit;
      x0[3 * S + i] = layout[size_t(i)].scale / unit;
      if (angles) x0[4 * S + i] = layout[size_t(i)].angle;
    }
    lb.head(3 * S).setConstant(-INFINITY);
    ub.head(3 * S).setConstant(INFINITY);
    lb.segment(3 * S, S) = bounds.lower / unit;
    ub.segment(3 * S, S) = bounds.upper / unit;
    if (angles) {
      lb.tail(S) = bounds.angle0.head(S).array() - max_rotation;
      ub.tail(S) = bounds.angle0.head(S).array() + max_rotation;
    }
  }

  const Eigen::VectorXi& types() const { return m_types; }
  int stencils() const { return m_S; }

  /// x → stencil parameters (not yet restored onto a joint term's constraint).
  void unpack(const Eigen::VectorXd& x, std::vector<StencilParams>& params) const {
    const int S = m_S;
    params.resize(size_t(S));
    for (int i = 0; i < S; ++i)
      params[size_t(i)] = {x.segment<3>(3 * i) * m_unit, x[3 * S + i] * m_unit,
                           m_angles ? x[4 * S + i] : m_layout[size_t(i)].angle, m_types[i]};
  }

  /// A gradient w.r.t. the stencil parameters (#S×5) → w.r.t. x.
  void pack_gradient(const Eigen::VectorXd& g_params, Eigen::VectorXd& g) const {
    const int S = m_S;
    g.resize((m_angles ? 5 : 4) * S);
    for (int i = 0; i < S; ++i) {
      g.segment<3>(3 * i) = g_params.segment<3>(5 * i) * m_unit;
      g[3 * S + i] = g_params[5 * i + 3] * m_unit;
      if (m_angles) g[4 * S + i] = g_params[5 * i + 4];
    }
  }

  Eigen::VectorXd x0, lb, ub;

 private:
  const StencilLayout& m_layout;
  double m_unit;
  bool m_angles;
  int m_S;
  Eigen::VectorXi m_types;
};

/// The rule that ends the rounds when they stop paying: three rounds in a row ended less than
/// `tolerance` (relative) below the best round end so far. For exemplars each re-matching then
/// takes back what the round gained; for packing the growth term creeps on against the bounds.
/// Records a round's end value in `st`; true when the rounds have stalled.
bool rounds_stalled(JointOptimizerState& st, double end, double tolerance) {
  if (end < st.best_round_end - tolerance * std::max(1.0, std::abs(end))) {
    st.best_round_end = end;
    st.stalled_rounds = 0;
  } else {
    ++st.stalled_rounds;
  }
  return st.stalled_rounds >= 3;
}

/// The layout after a round: the optimiser's point (restored onto the joint term's constraint),
/// projected back onto the surface.
void update_layout(const PatternSurface& surface, const JointOptimizerState& bounds, bool joint,
                   const std::vector<StencilParams>& params, StencilLayout& layout) {
  for (size_t i = 0; i < layout.size(); ++i) {
    const ClosestPoint cp = surface.project(params[i].position);
    PlacedStencil& st = layout[i];
    st.position = cp.point;
    st.where = cp.where;
    // L-BFGS-B keeps x inside the bounds; a restoration may scale past them (by design).
    const Eigen::Index k = Eigen::Index(i);
    st.scale = joint ? params[i].scale : std::clamp(params[i].scale, bounds.lower[k], bounds.upper[k]);
    st.angle = params[i].angle;
  }
}

/// One round: L-BFGS-B on `layout` against the energy's current matching, at most
/// `max_iterations` iterations (from `st`, or continuing `resume`); the layout is updated to the
/// result.
LbfgsbResult run_round(PatternContext& ctx, const JointOptimizerOptions& options, const JointOptimizerState& st,
                       int max_iterations, int round, const Stopwatch& clock, const LbfgsbState* resume,
                       StencilLayout& layout, bool& stopped_by_callback) {
  const JointOptimizerState& bounds = st;
  const int used = st.used;
  JointTerm* joint = options.joint;
  const double w_P = joint ? options.w_P : 1.0;
  const JointVariables vars(layout, bounds, ctx.unit(), joint != nullptr, options.max_rotation);
  std::vector<StencilParams> params;
  Eigen::VectorXd g_params;
  double last_gradient_norm = 0;
  auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
    vars.unpack(x, params);
    const double v = joint_objective(ctx.energy(), joint, w_P, params, vars.types(), &g_params);
    vars.pack_gradient(g_params, g);
    last_gradient_norm = g.norm();
    return v;
  };
  auto cb = [&](int it, const Eigen::VectorXd&, double fx) {
    if (!options.progress) return true;
    PatternProgress p{"optimise", round, used + it, fx, vars.stencils(), clock.seconds(), last_gradient_norm};
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
  LbfgsbOptions lo;
  lo.max_iterations = max_iterations;
  lo.first_scale = st.scale;
  LbfgsbCheckpoint checkpoint;
  if (options.checkpoint) checkpoint = [&](const LbfgsbState& l) { options.checkpoint(st, &l); };
  LbfgsbResult res = minimize_lbfgsb(f, vars.x0, vars.lb, vars.ub, lo, cb, checkpoint, resume);
  vars.unpack(res.x, params);
  if (joint) joint->restore(params);
  update_layout(ctx.surface(), bounds, joint != nullptr, params, layout);
  return res;
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

void optimize_pattern(PatternContext& ctx, StencilLayout& layout, const JointOptimizerOptions& options,
                      JointOptimizerStats& stats, const JointOptimizerState* resume) {
  Stopwatch clock;
  const bool exemplar = ctx.kind() == PatternKind::Exemplar;
  const int budget = options.max_iterations >= 0 ? options.max_iterations : ctx.settings().max_iterations;
  const int per_round = options.iterations_per_round > 0 ? options.iterations_per_round : (exemplar ? 20 : 100);
  PatternEnergy& energy = ctx.energy();
  JointTerm* joint = options.joint;

  // The loop's state lives in `st` (checkpoints see it; a resumed call starts from it).
  JointOptimizerState st;
  std::vector<DetNeighborhood> previous;
  bool matched = false;  // the neighbourhoods of the current layout are frozen in `energy`
  const LbfgsbState* inner = nullptr;  // a resumed round's minimisation
  if (resume) {
    st = *resume;
    st.lbfgsb.reset();
    inner = resume->lbfgsb ? &*resume->lbfgsb : nullptr;
    layout = st.layout;
    if (exemplar && st.round > 0) {  // the last round's matching (before its type vote)
      StencilLayout before_vote = layout;
      for (size_t i = 0; i < layout.size(); ++i) before_vote[i].type = st.matched_types.at(i);
      energy.rematch(before_vote);
      previous = energy.neighborhoods();
      matched = true;
    }
  } else {
    ctx.scale_bounds(layout, st.lower, st.upper);
    st.angle0.resize(Eigen::Index(layout.size()));
    for (size_t i = 0; i < layout.size(); ++i) st.angle0[Eigen::Index(i)] = layout[i].angle;
    stats.stop_reason = budget == 0 ? "iterations" : "";
  }
  bool stopped_by_callback = false;
  while (st.used < budget && !layout.empty() && !stopped_by_callback) {
    if (!matched) {
      energy.rematch(layout);
      st.matched_types.resize(layout.size());
      for (size_t i = 0; i < layout.size(); ++i) st.matched_types[i] = layout[i].type;
    }
    matched = false;
    st.layout = layout;
    if (!inner && options.checkpoint) options.checkpoint(st, nullptr);
    const LbfgsbResult res = run_round(ctx, options, st, std::min(per_round, budget - st.used), stats.rounds, clock,
                                       inner, layout, stopped_by_callback);
    inner = nullptr;
    // A round that moved nothing still spends one iteration of the budget: two matchings of
    // equal cost can alternate forever otherwise.
    st.used += std::max(1, res.iterations);
    if (res.scale > 0) st.scale = res.scale;
    ++st.round;
    stats.iterations += res.iterations;
    stats.evaluations += res.evaluations;
    stats.round_histories.push_back(res.history);
    ++stats.rounds;
    // The phase's reason: the optimiser's own ("gradient", "decrease", a line-search failure,
    // "callback"), "iterations" when the budget is spent, or "stalled" (below).
    if (res.converged || res.stop_reason == "callback" || res.stop_reason.rfind("line search", 0) == 0)
      stats.stop_reason = res.stop_reason;
    else
      stats.stop_reason = st.used >= budget ? "iterations" : "round";  // "round": the loop goes on
    bool settled = res.converged;
    if (exemplar) {
      energy.rematch(layout);
      matched = true;  // MWT11: match, vote, then optimise against this matching
      for (size_t i = 0; i < layout.size(); ++i) st.matched_types[i] = layout[i].type;
      const int changes = energy.vote_types(layout);
      stats.type_changes += changes;
      // Converged without moving and no vote changed a type: the next round would start from
      // the same point, whatever the (possibly tie-broken differently) matching.
      settled = settled && changes == 0 && (res.iterations == 0 || same_matching(previous, energy.neighborhoods()));
      previous = energy.neighborhoods();
    }
    if (rounds_stalled(st, res.history.back(), options.round_tolerance) && !settled) {
      settled = true;
      stats.stop_reason = "stalled";
    }
    if (settled) break;
  }

  // The lower bounds of the run (taken at the stencils' start) are the floor of the shrinking.
  // A joint term's restoration may have scaled a stencil below its bound on purpose; such a
  // stencil is removed only when it would lose more than a quarter of its size.
  Eigen::VectorXd floor = st.lower;
  if (joint)
    for (size_t i = 0; i < layout.size(); ++i)
      floor[Eigen::Index(i)] = 0.75 * std::min(st.lower[Eigen::Index(i)], layout[i].scale);
  stats.removed += resolve_overlaps(ctx.surface(), layout, ctx.settings().s, floor, options.min_gap);
  if (joint) joint->finalize(ctx.surface(), ctx.settings().s, options.min_gap, layout);
  stats.seconds_optimize += clock.seconds();
}

void fill_holes_and_reoptimize(const PatternContext& ctx, StencilLayout& layout, PatternRng& rng, int max_rounds,
                               int& inserted, const std::function<void(int round)>& reoptimize, int resume_round) {
  for (int j = std::max(1, resume_round); j <= max_rounds; ++j) {
    if (j != resume_round) {
      const int added = ctx.fill_holes(layout, rng);
      inserted += added;
      if (added == 0) break;
    }
    reoptimize(j);
  }
}

}  // namespace cutwork::solvers

#include "host/pattern/det.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <numbers>
#include <numeric>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "host/core/error.h"
#include "host/core/internal_error.h"

namespace cutwork {

namespace {

RowMatX3d embed(const std::vector<ExemplarElement>& elements) {
  RowMatX3d pts(Eigen::Index(elements.size()), 3);
  for (size_t i = 0; i < elements.size(); ++i)
    pts.row(Eigen::Index(i)) << elements[i].position.x(), elements[i].position.y(), 0.0;
  return pts;
}

}  // namespace

DetExemplar::DetExemplar(Exemplar exemplar, std::vector<int> stencil_types,
                         const DetSettings& settings)
    : m_ex(std::move(exemplar)), m_types(std::move(stencil_types)), m_settings(settings) {
  const int n = int(m_ex.elements.size());
  if (m_types.size() != m_ex.type_names.size())
    throw InternalError("DetExemplar: one stencil type per exemplar type is required");
  m_radius = settings.r_N * m_ex.size();
  const RowMatX3d pts = embed(m_ex.elements);
  const PointGrid grid(pts, 1.25 * m_radius);

  // Mean nearest-neighbour distance.
  std::vector<int> near;
  double nn_sum = 0;
  int nn_count = 0;
  m_nearest.assign(size_t(n), m_ex.size());
  for (int m = 0; m < n; ++m) {
    double best = INFINITY;
    double reach = m_radius;
    for (int attempt = 0; attempt < 8 && !std::isfinite(best); ++attempt, reach *= 2) {
      grid.in_ball(pts.row(m).transpose(), reach, near);
      for (int k : near)
        if (k != m) best = std::min(best, (pts.row(k) - pts.row(m)).norm());
    }
    if (std::isfinite(best)) {
      nn_sum += best;
      ++nn_count;
      m_nearest[size_t(m)] = best;
    }
  }
  m_spacing = nn_count ? nn_sum / nn_count : m_ex.size();

  for (int e = 0; e < n; ++e)
    if (m_ex.distance_to_boundary(m_ex.elements[size_t(e)].position) >= m_radius) m_centers.push_back(e);
  if (m_centers.empty())
    throw InputError(fmt::format(
        "exemplar '{}': no element lies at least r_N × size = {:.4g} (r_N = {:.4g}, size {:.4g}) "
        "inside the domain, so no neighbourhood can be matched; lower pattern.r_N or give a "
        "larger exemplar",
        m_ex.name, m_radius, settings.r_N, m_ex.size()));

  m_neighbors.resize(size_t(n));
  for (int e : m_centers) {
    const Vec3 c = pts.row(e).transpose();
    grid.in_ball(c, 1.25 * m_radius, near);
    std::vector<int>& out = m_neighbors[size_t(e)];
    for (int m : near)
      if (m != e) out.push_back(m);
    std::stable_sort(out.begin(), out.end(), [&](int a, int b) {
      return (pts.row(a).transpose() - c).squaredNorm() < (pts.row(b).transpose() - c).squaredNorm();
    });
  }

  // Covering radius over the domain's interior (one spacing inside the boundary).
  Vec2 lo = m_ex.domain.front(), hi = lo;
  for (const Vec2& p : m_ex.domain) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const int g = 64;
  m_covering = 0;
  for (int a = 0; a <= g; ++a)
    for (int b = 0; b <= g; ++b) {
      const Vec2 p(lo.x() + (hi.x() - lo.x()) * a / g, lo.y() + (hi.y() - lo.y()) * b / g);
      if (m_ex.distance_to_boundary(p) < m_spacing) continue;
      double best = INFINITY;
      for (const auto& el : m_ex.elements) best = std::min(best, (el.position - p).norm());
      m_covering = std::max(m_covering, best);
    }
  if (!(m_covering > 0)) m_covering = m_spacing;
}

Vec3 equidistant_offset(const Vec3& v, const Vec3& n, Eigen::Matrix3d* jacobian) {
  const Vec3 vt = v - n * n.dot(v);
  const double a = v.norm(), b = vt.norm();
  if (!(b > 0)) {
    if (jacobian) jacobian->setZero();
    return Vec3::Zero();
  }
  if (jacobian) {
    const Eigen::Matrix3d P = Eigen::Matrix3d::Identity() - n * n.transpose();
    // d(v_t a / b) = (a/b) P dv + v_t (vᵀ/(a b) − a v_tᵀ / b³) dv
    *jacobian = (a / b) * P + vt * (v.transpose() / (a * b) - (a / (b * b * b)) * vt.transpose());
  }
  return vt * (a / b);
}

DetNeighborhood det_match_one(const DetExemplar& ex, const PatternSurface& surface,
                              const StencilLayout& layout, int i, const std::vector<int>& neighbors) {
  const DetSettings& st = ex.settings();
  const Exemplar& E = ex.exemplar();
  const PlacedStencil& si = layout[size_t(i)];
  DetNeighborhood hood;
  hood.stencil = i;
  Vec3 n, t, b;
  surface.frame_at(si.where, n, t, b);
  hood.normal = n;
  hood.sigma = st.sigma * surface.sizing_at(si.where);
  const double sigma = hood.sigma;
  const double u2 = (sigma / st.unit) * (sigma / st.unit);  // exemplar units² → ℓ² units
  const double gate2 = ex.spacing() * ex.spacing();
  const double unmatched_cost = u2 * gate2;

  // Output neighbours in the field frame, exemplar units.
  struct Out {
    int id;
    Vec2 a;
    double rho;
    int type;
  };
  std::vector<Out> outs;
  for (int j : neighbors) {
    if (j == i) continue;
    const Vec3 p = equidistant_offset(layout[size_t(j)].position - si.position, n, nullptr);
    outs.push_back({j, Vec2(p.dot(t), p.dot(b)) / sigma, layout[size_t(j)].scale / sigma,
                    layout[size_t(j)].type});
  }
  hood.outputs.reserve(outs.size());
  for (const Out& o : outs) hood.outputs.push_back(o.id);

  const int N = std::max(1, st.symmetry);
  double best_cost = INFINITY;
  struct Pair {
    double cost;
    int j, m;
  };
  std::vector<Pair> pairs;
  std::vector<int> assign(outs.size()), best_assign(outs.size(), -1);
  std::vector<char> used;
  std::vector<Vec2> rotated(outs.size());
  for (int e : ex.centers()) {
    const ExemplarElement& ce = E.elements[size_t(e)];
    const double center_cost = u2 * (si.scale / sigma - ce.scale) * (si.scale / sigma - ce.scale) +
                               (si.type != ex.stencil_type(e) ? st.xi : 0.0);
    if (center_cost >= best_cost) continue;
    const std::vector<int>& cand = ex.neighbors(e);
    for (int k = 0; k < N; ++k) {
      const double th = 2 * std::numbers::pi * k / N, c = std::cos(th), s = std::sin(th);
      for (size_t q = 0; q < outs.size(); ++q)
        rotated[q] = Vec2(c * outs[q].a.x() + s * outs[q].a.y(), -s * outs[q].a.x() + c * outs[q].a.y());
      pairs.clear();
      for (size_t q = 0; q < outs.size(); ++q)
        for (size_t r = 0; r < cand.size(); ++r) {
          const ExemplarElement& em = E.elements[size_t(cand[r])];
          const double d2 = (rotated[q] - (em.position - ce.position)).squaredNorm();
          if (d2 > gate2) continue;
          const double ds = outs[q].rho - em.scale;
          pairs.push_back({u2 * (d2 + ds * ds) + (outs[q].type != ex.stencil_type(cand[r]) ? st.xi : 0.0),
                           int(q), int(r)});
        }
      std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
        if (x.cost != y.cost) return x.cost < y.cost;
        if (x.j != y.j) return x.j < y.j;
        return x.m < y.m;
      });
      std::fill(assign.begin(), assign.end(), -1);
      used.assign(cand.size(), 0);
      double cost = center_cost;
      size_t matched = 0;
      for (const Pair& p : pairs) {
        if (assign[size_t(p.j)] >= 0 || used[size_t(p.m)]) continue;
        assign[size_t(p.j)] = cand[size_t(p.m)];
        used[size_t(p.m)] = 1;
        cost += p.cost;
        if (++matched == outs.size()) break;
      }
      cost += double(outs.size() - matched) * unmatched_cost;
      if (cost < best_cost) {
        best_cost = cost;
        hood.center = e;
        hood.rotation = k;
        best_assign = assign;
      }
    }
  }
  hood.cost = best_cost;
  hood.matches = best_assign;
  const double th = 2 * std::numbers::pi * hood.rotation / N;
  hood.tangent = std::cos(th) * t + std::sin(th) * b;
  hood.bitangent = n.cross(hood.tangent);
  return hood;
}

std::vector<DetNeighborhood> det_match(const DetExemplar& ex, const PatternSurface& surface,
                                       const StencilLayout& layout, int centres) {
  const int S = centres >= 0 ? std::min(centres, int(layout.size())) : int(layout.size());
  std::vector<DetNeighborhood> hoods(static_cast<size_t>(S));
  if (S == 0) return hoods;
  const RowMatX3d pos = layout_positions(layout);
  const double rmax = ex.radius() * ex.settings().sigma * surface.sizing().max_value();
  const PointGrid grid(pos, rmax);
  tbb::parallel_for(0, S, [&](int i) {
    std::vector<int> near;
    const double R = ex.radius() * ex.settings().sigma * surface.sizing_at(layout[size_t(i)].where);
    grid.in_ball(pos.row(i).transpose(), R, near);
    hoods[size_t(i)] = det_match_one(ex, surface, layout, i, near);
  });
  return hoods;
}

double det_objective(const DetExemplar& ex, const std::vector<DetNeighborhood>& hoods,
                     const RowMatX3d& positions, const Eigen::VectorXd& scales,
                     const Eigen::VectorXi& types, RowMatX3d* d_positions,
                     Eigen::VectorXd* d_scales) {
  const Exemplar& E = ex.exemplar();
  const double inv = 1.0 / ex.settings().unit, inv2 = inv * inv;
  const double xi = ex.settings().xi;
  double value = 0;
  Eigen::Matrix3d J;
  for (const DetNeighborhood& h : hoods) {
    if (h.center < 0) continue;
    const int i = h.stencil;
    const ExemplarElement& ce = E.elements[size_t(h.center)];
    // Centre: scale and type of i against its match e.
    {
      const double ds = scales[i] - h.sigma * ce.scale;
      value += ds * ds * inv2;
      if (d_scales) (*d_scales)[i] += 2 * ds * inv2;
      if (types[i] != ex.stencil_type(h.center)) value += xi;
    }
    const Vec3 ci = positions.row(i).transpose();
    for (size_t q = 0; q < h.outputs.size(); ++q) {
      const int m = h.matches[q];
      if (m < 0) continue;
      const int j = h.outputs[q];
      const ExemplarElement& em = E.elements[size_t(m)];
      const Vec2 v = em.position - ce.position;
      const Vec3 target = h.sigma * (v.x() * h.tangent + v.y() * h.bitangent);
      const Vec3 p = equidistant_offset(positions.row(j).transpose() - ci, h.normal,
                                        d_positions ? &J : nullptr);
      const Vec3 D = p - target;
      value += D.squaredNorm() * inv2;
      if (d_positions) {
        const Vec3 g = 2 * inv2 * (J.transpose() * D);
        d_positions->row(j) += g.transpose();
        d_positions->row(i) -= g.transpose();
      }
      const double ds = scales[j] - h.sigma * em.scale;
      value += ds * ds * inv2;
      if (d_scales) (*d_scales)[j] += 2 * ds * inv2;
      if (types[j] != ex.stencil_type(m)) value += xi;
    }
  }
  return value;
}

int det_vote_types(const DetExemplar& ex, const std::vector<DetNeighborhood>& hoods,
                   StencilLayout& layout) {
  int num_types = 0;
  for (int m = 0; m < ex.num_elements(); ++m) num_types = std::max(num_types, ex.stencil_type(m) + 1);
  for (const auto& s : layout) num_types = std::max(num_types, s.type + 1);
  std::vector<int> votes(layout.size() * size_t(num_types), 0);
  auto vote = [&](int j, int type) { ++votes[size_t(j) * size_t(num_types) + size_t(type)]; };
  for (const DetNeighborhood& h : hoods) {
    if (h.center < 0) continue;
    vote(h.stencil, ex.stencil_type(h.center));
    for (size_t q = 0; q < h.outputs.size(); ++q)
      if (h.matches[q] >= 0) vote(h.outputs[q], ex.stencil_type(h.matches[q]));
  }
  int changed = 0;
  for (size_t j = 0; j < layout.size(); ++j) {
    const int* v = &votes[j * size_t(num_types)];
    const int best = *std::max_element(v, v + num_types);
    if (best == 0) continue;  // nobody voted
    int type = layout[j].type;
    if (v[type] != best) {
      type = int(std::find(v, v + num_types, best) - v);
      layout[j].type = type;
      ++changed;
    }
  }
  return changed;
}

namespace {

/// Inserts stencils for a growth step; shared by the seeding and the queue.
class Grower {
 public:
  Grower(const DetExemplar& ex, const PatternSurface& surface, StencilLayout& layout,
         const DetGrowthOptions& options)
      : m_ex(ex), m_surface(surface), m_layout(layout), m_options(options),
        m_grid(ex.radius() * ex.settings().sigma * surface.sizing().max_value()) {
    const DetSettings& st = ex.settings();
    double max_elem = 0;
    for (const auto& el : ex.exemplar().elements) max_elem = std::max(max_elem, el.scale);
    m_rmax = max_elem * st.sigma * surface.sizing().max_value();
    for (const auto& s : layout) {
      m_grid.insert(s.position);
      m_rmax = std::max(m_rmax, s.scale);
    }
    m_cap = options.max_stencils;
    if (m_cap <= 0) {
      const double expected = ex.density() * surface.area() * surface.sizing().mean_power(surface.mesh(), -2) /
                              (st.sigma * st.sigma);
      m_cap = int(std::min(4.0 * expected + 100.0, 5e7));
    }
  }

  bool capped() const { return m_capped; }
  const DynamicPointGrid& grid() const { return m_grid; }

  /// Tries to add a stencil at tangent-plane point x, keeping `min_distance` (m) from every
  /// stencil besides the overlap test. Returns its id, or −1.
  int try_insert(const Vec3& x, double max_offset, double min_distance, double scale, double angle,
                 int type) {
    if (int(m_layout.size()) >= m_cap) {
      m_capped = true;
      return -1;
    }
    const ClosestPoint cp = m_surface.project(x);
    if ((cp.point - x).norm() > max_offset) return -1;  // fell off the surface or onto another sheet
    const double f = m_options.overlap_factor * (1 + m_ex.settings().safety);
    if (m_surface.boundary_distance(cp.point, f * scale) < f * scale) return -1;
    // Against the stencils and, across symmetry planes, their images and its own (pattern_mirror.h).
    const PatternMirror& mirror = m_surface.mirror();
    for (int k = -1; k < mirror.num_reflections(); ++k) {
      const Vec3 y = k < 0 ? cp.point : mirror.image(cp.point, k);
      if (k >= 0 && (y - cp.point).norm() < std::max(2 * f * scale, min_distance)) return -1;
      m_grid.in_ball(y, std::max(f * (scale + m_rmax), min_distance), m_near);
      for (int j : m_near) {
        const double d = (m_layout[size_t(j)].position - y).norm();
        if (d < f * (scale + m_layout[size_t(j)].scale)) return -1;
        if (d < min_distance) return -1;
      }
    }
    m_layout.push_back({cp.point, cp.where, scale, angle, type});
    m_rmax = std::max(m_rmax, scale);
    return m_grid.insert(cp.point);
  }

 private:
  const DetExemplar& m_ex;
  const PatternSurface& m_surface;
  StencilLayout& m_layout;
  DetGrowthOptions m_options;
  DynamicPointGrid m_grid;
  std::vector<int> m_near;
  double m_rmax = 0;
  int m_cap = 0;
  bool m_capped = false;
};

}  // namespace

DetGrowthReport det_grow(const DetExemplar& ex, const PatternSurface& surface,
                         StencilLayout& layout, PatternRng& rng, const DetGrowthOptions& options) {
  const DetSettings& st = ex.settings();
  const Exemplar& E = ex.exemplar();
  const SurfaceMesh& mesh = surface.mesh();
  const int N = std::max(1, st.symmetry);
  const size_t initial = layout.size();
  DetGrowthReport report;
  Grower grower(ex, surface, layout, options);

  std::deque<int> queue;
  for (int i = 0; i < int(layout.size()); ++i) queue.push_back(i);
  std::vector<int> near;

  auto process_queue = [&] {
    while (!queue.empty() && !grower.capped()) {
      const int i = queue.front();
      queue.pop_front();
      const double R = ex.radius() * st.sigma * surface.sizing_at(layout[size_t(i)].where);
      grower.grid().in_ball(layout[size_t(i)].position, R, near);
      const DetNeighborhood h = det_match_one(ex, surface, layout, i, near);
      if (h.center < 0) continue;
      std::vector<char> matched(E.elements.size(), 0);
      matched[size_t(h.center)] = 1;
      for (int m : h.matches)
        if (m >= 0) matched[size_t(m)] = 1;
      const ExemplarElement& ce = E.elements[size_t(h.center)];
      const Vec3 ci = layout[size_t(i)].position;
      for (int m : ex.neighbors(h.center)) {
        if (matched[size_t(m)]) continue;
        const ExemplarElement& em = E.elements[size_t(m)];
        const Vec2 v = em.position - ce.position;
        const Vec3 x = ci + h.sigma * (v.x() * h.tangent + v.y() * h.bitangent);
        const int id = grower.try_insert(x, 0.5 * h.sigma * ex.spacing(),
                                         options.spacing_factor * h.sigma * ex.nearest_distance(m),
                                         h.sigma * em.scale, em.angle + 2 * std::numbers::pi * h.rotation / N,
                                         ex.stencil_type(m));
        if (id >= 0) queue.push_back(id);
      }
    }
  };
  process_queue();

  // Coverage: visit face centroids in a seeded random order; seed a patch where uncovered.
  std::vector<int> order(static_cast<size_t>(mesh.num_faces()));
  std::iota(order.begin(), order.end(), 0);
  for (int k = int(order.size()) - 1; k > 0; --k) std::swap(order[size_t(k)], order[size_t(rng.below(k + 1))]);
  for (int f : order) {
    if (grower.capped()) break;
    SurfacePoint where;
    where.face = f;
    where.bary = Vec3::Constant(1.0 / 3.0);
    const Vec3 c = mesh.point(where);
    const double sigma = st.sigma * surface.sizing_at(where);
    const double hole = 1.5 * sigma * ex.covering_radius();
    // Covered by a stencil or, across a symmetry plane, by an image.
    bool covered = false;
    for (int k = -1; !covered && k < surface.mirror().num_reflections(); ++k) {
      grower.grid().in_ball(k < 0 ? c : surface.mirror().image(c, k), hole, near);
      covered = !near.empty();
    }
    if (covered) continue;
    // A gap along the open boundary is where the pattern ends, not a hole: the growth reached
    // it and nothing more fits there.
    if (surface.boundary_distance(c, hole) < hole) continue;
    // Uncovered: copy the neighbourhood of a random matchable exemplar element here.
    const int e = ex.centers()[size_t(rng.below(int(ex.centers().size())))];
    Vec3 n, t, b;
    surface.frame_at(where, n, t, b);
    const ExemplarElement& ce = E.elements[size_t(e)];
    const double offset = 0.5 * sigma * ex.spacing();
    ++report.seeds;
    int placed = 0;
    const int id0 = grower.try_insert(c, offset, options.spacing_factor * sigma * ex.nearest_distance(e),
                                      sigma * ce.scale, ce.angle, ex.stencil_type(e));
    if (id0 >= 0) {
      queue.push_back(id0);
      ++placed;
    }
    for (int m : ex.neighbors(e)) {
      const ExemplarElement& em = E.elements[size_t(m)];
      if ((em.position - ce.position).norm() > ex.radius()) continue;
      const Vec2 v = em.position - ce.position;
      const int id = grower.try_insert(c + sigma * (v.x() * t + v.y() * b), offset,
                                       options.spacing_factor * sigma * ex.nearest_distance(m),
                                       sigma * em.scale, em.angle, ex.stencil_type(m));
      if (id >= 0) {
        queue.push_back(id);
        ++placed;
      }
    }
    process_queue();
  }
  report.added = int(layout.size() - initial);
  report.capped = grower.capped();
  return report;
}

}  // namespace cutwork

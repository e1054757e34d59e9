#include "host/pattern/overlaps.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "host/pattern/point_grid.h"

namespace cutwork {

namespace {

OverlapReport check(const PatternSurface& surface, const StencilLayout& layout, double safety, double gap,
                    const std::vector<PointPair>& candidates, const std::vector<ImagePair>& images,
                    bool brute) {
  OverlapReport rep;
  for (const ImagePair& p : images) {
    if (p.i > p.j) continue;  // (i, g j) and (j, g i) are one pair of the whole
    const double need = (1 + safety) * (layout[size_t(p.i)].scale + layout[size_t(p.j)].scale) + gap;
    if (need > p.distance) {
      ++rep.images;
      rep.worst = std::max(rep.worst, (need - p.distance) / need);
    }
  }
  for (const PointPair& p : candidates) {
    const double need = (1 + safety) * (layout[size_t(p.i)].scale + layout[size_t(p.j)].scale) + gap;
    const double d = (layout[size_t(p.i)].position - layout[size_t(p.j)].position).norm();
    if (need > d) {
      ++rep.pairs;
      rep.worst = std::max(rep.worst, (need - d) / need);
    }
  }
  for (const PlacedStencil& s : layout) {
    const double need = (1 + safety) * s.scale + gap;
    const auto bp = brute ? surface.boundary().nearest_brute_force(s.position, need)
                          : surface.boundary().nearest(s.position, need);
    if (bp && need > bp->signed_distance) {
      ++rep.boundary;
      rep.worst = std::max(rep.worst, (need - bp->signed_distance) / need);
    }
  }
  return rep;
}

double max_reach(const StencilLayout& layout, double safety, double gap) {
  double r = 0;
  for (const auto& s : layout) r = std::max(r, s.scale);
  return 2 * (1 + safety) * r + gap;
}

}  // namespace

OverlapReport find_overlaps(const PatternSurface& surface, const StencilLayout& layout,
                            double safety, double gap) {
  const double reach = max_reach(layout, safety, gap);
  const RowMatX3d pos = layout_positions(layout);
  return check(surface, layout, safety, gap, PointGrid(pos, reach).pairs_within(reach),
               image_pairs(surface.mirror(), pos, reach), false);
}

OverlapReport find_overlaps_brute_force(const PatternSurface& surface, const StencilLayout& layout,
                                        double safety, double gap) {
  const RowMatX3d pos = layout_positions(layout);
  const double reach = max_reach(layout, safety, gap);
  return check(surface, layout, safety, gap, pairs_within_brute_force(pos, reach),
               image_pairs_brute_force(surface.mirror(), pos, reach), true);
}

int resolve_overlaps(const PatternSurface& surface, StencilLayout& layout, double safety,
                     const Eigen::VectorXd& min_scales, double gap) {
  const int S = int(layout.size());
  const double reach = max_reach(layout, safety, gap);
  const RowMatX3d pos = layout_positions(layout);
  std::vector<double> factor(size_t(S), 1.0);
  for (const PointPair& p : PointGrid(pos, reach).pairs_within(reach)) {
    const double circles = (1 + safety) * (layout[size_t(p.i)].scale + layout[size_t(p.j)].scale);
    if (circles + gap > p.distance) {
      const double f = std::max(0.0, p.distance - gap) / circles;
      factor[size_t(p.i)] = std::min(factor[size_t(p.i)], f);
      factor[size_t(p.j)] = std::min(factor[size_t(p.j)], f);
    }
  }
  // The images across symmetry planes (a stencil's own image included): the same rule.
  for (const ImagePair& p : image_pairs(surface.mirror(), pos, reach)) {
    const double circles = (1 + safety) * (layout[size_t(p.i)].scale + layout[size_t(p.j)].scale);
    if (circles + gap > p.distance) {
      const double f = std::max(0.0, p.distance - gap) / circles;
      factor[size_t(p.i)] = std::min(factor[size_t(p.i)], f);
      factor[size_t(p.j)] = std::min(factor[size_t(p.j)], f);
    }
  }
  for (int i = 0; i < S; ++i) {
    const double circle = (1 + safety) * layout[size_t(i)].scale;
    const auto bp = surface.boundary().nearest(layout[size_t(i)].position, circle + gap);
    if (bp && circle + gap > bp->signed_distance)
      factor[size_t(i)] = std::min(factor[size_t(i)], std::max(0.0, bp->signed_distance - gap) / circle);
  }
  StencilLayout kept;
  kept.reserve(layout.size());
  int removed = 0;
  for (int i = 0; i < S; ++i) {
    PlacedStencil s = layout[size_t(i)];
    if (factor[size_t(i)] < 1.0) s.scale *= factor[size_t(i)] * (1 - 1e-9);
    if (!(s.scale >= min_scales[i]) || !(s.scale > 0)) {
      ++removed;
      continue;
    }
    kept.push_back(s);
  }
  layout = std::move(kept);
  return removed;
}

}  // namespace cutwork

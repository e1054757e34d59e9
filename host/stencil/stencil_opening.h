#pragma once
/// What a cutter makes of a stencil: the opening of its polygon by a disc.
///
/// A hole cut by a tool of radius r (a router's bit, a laser's kerf, a printer's nozzle) is the
/// union of the discs of radius r that fit inside the drawn outline — its morphological opening
/// by the disc: every corner of the hole that turns into the material (a star's tips) becomes an
/// arc of radius r, corners that turn away from it (the star's notches) stay sharp, and parts of
/// the hole narrower than 2r are not cut. The shell around a sharp tip has an unbounded stress
/// there, around the tool's round a finite one: this is the outline `cutwork verify` checks
/// (conforming_verification.h, the tool radius), so that its rim peak converges to the built
/// shell's.
///
/// Computed with CGAL's exact offsets (Minkowski_sum_2): the inset by r (erosion), then the
/// offset of the inset by r (dilation); arcs are written as polylines turning at most `arc_step`
/// per segment, with the inset's arcs (about the notches) circumscribed so that the notches come
/// back inside the material by at most r (1/cos(π/16) − 1) ≈ 0.02 r; the straight pieces lie
/// within 1e-5 r of the drawn sides (CGAL's ε of 1e-6 r per offset; measured up to 5e-6 r
/// outside, tests/host/stencil/stencil_opening_test.cpp). About 20 ms per star. A tool under
/// kFilletOpening (1e-3) of the polygon's size is written as the fillets themselves
/// (fillet_polygon), where they fit: there CGAL's offsets of the double-precision polygon left
/// needles of no width (the heart at 1e-4, the leaf at 1e-7), and the chair designed with a 0.1 µm
/// tool had two holes touching at a point (a 6e-17 m "ligament") and no printable solid.
///
/// A polygon is a smooth curve written as segments when none of its corners is sharp at r: every
/// vertex that turns towards the inside turns by at most kToolCornerTurn (30°, the rim recovery's
/// corner angle) and its fillet of radius r fits within half its edges (its local radius is about
/// r or more). The tool follows such a curve, so its drawn polygon is kept (its kinks are the
/// writing's, not corners: opened, every kink of the pavilion's flowers became a 0.5 mm round, and
/// the rim peak read those, 1.7× the one over the segments). Convex, it is kept outright (a disc of
/// radius r rolls freely inside it); otherwise the opening still says whether a neck splits it or
/// nothing fits. A star's tips (127.5°) and the bowl's smallest flowers' petals (a round of 0.42 mm,
/// its vertices 15° apart) are sharp at r = 0.5 mm; circles and the pavilion's flowers are not.
#include <span>
#include <string>
#include <vector>

#include "host/core/types.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {

/// Arcs of the opening: at most this turn per segment (5°).
inline constexpr double kOpeningArcStep = 5.0 * 3.14159265358979323846 / 180.0;
/// A vertex turning towards the inside by more than this (30°) is a corner (see above).
inline constexpr double kToolCornerTurn = 30.0 * 3.14159265358979323846 / 180.0;

/// Below this fraction of a polygon's size (its largest distance from its first vertex) a tool's
/// opening is written as fillets (fillet_polygon) where they fit, not by CGAL's offsets.
inline constexpr double kFilletOpening = 1e-3;

struct OpenedPolygon {
  std::vector<Vec2> polygon;  ///< counter-clockwise; empty when no disc of the radius fits inside
  int components = 0;         ///< pieces of the opening (a neck narrower than 2r splits it); the
                              ///< largest by area is `polygon`
  bool unchanged = false;     ///< no corner is sharp at r: the drawn polygon is returned
};

/// The opening of `polygon` (counter-clockwise, simple) by the disc of `radius` (> 0, the
/// polygon's units). Throws InputError for a radius that is not finite and positive or a polygon
/// of fewer than 3 points.
OpenedPolygon open_polygon(std::span<const Vec2> polygon, double radius, double arc_step = kOpeningArcStep);

/// The opening of `polygon` (counter-clockwise, simple) by a disc of `radius` far smaller than its
/// features, exactly: every vertex turning towards the inside by more than `arc_step` becomes the
/// arc of `radius` tangent to its two edges (points on the arc, at most `arc_step` apart), every
/// other vertex is kept (its fillet lies within r (1/cos(step/2) − 1) ≈ 1e-3 r of it). That is the
/// opening when each fillet fits within half of its edges and no two edges that share no vertex come
/// within 2r of each other (no neck the disc cannot pass): false otherwise (`out` then undefined).
/// open_polygon uses it below kFilletOpening of the polygon's size.
bool fillet_polygon(std::span<const Vec2> polygon, double radius, double arc_step, std::vector<Vec2>& out);

/// Stencils as a tool of radius `tool_radius` (m) cuts them: one shape per stencil, its shape's
/// polygon opened by tool_radius / s (its own scale s) in the reference frame — the same centre
/// and scale, so positions and frames are the stencils' own.
struct ToolCutStencils {
  StencilLibrary shapes;                ///< shape i is stencil i's cut ("<shape>@i")
  std::vector<StencilParams> stencils;  ///< the stencils, stencil i of type i
  int rounded = 0;                      ///< stencils whose outline the tool changed
  int too_small = 0;   ///< stencils no disc of the tool's radius fits in: kept as drawn (a tool
                       ///< cannot cut them at all; fabrication.min_feature says so beforehand)
  int split = 0;       ///< stencils the tool cuts in several pieces: the largest kept
};

/// The tool's cut of every stencil (parallel over stencils; the result does not depend on the
/// number of threads). tool_radius ≤ 0 keeps every outline as drawn (one shape per stencil still).
/// Throws InputError for a stencil whose type is not in `shapes` or whose scale is not positive.
ToolCutStencils tool_cut_stencils(const StencilLibrary& shapes, std::span<const StencilParams> stencils,
                                  double tool_radius);

}  // namespace cutwork

#pragma once
/// Private to host/surfaces: a planar polyline whose interior corners are rounded by circular
/// arcs, parametrised by arc length. The table and chair are such a profile (in the x-z plane)
/// extruded along y; meshing the (arc length × width) rectangle then gives an isometric map,
/// so the lattice's triangles stay near-equilateral in 3-D.
#include <vector>

#include "host/core/types.h"

namespace cutwork::shapes_detail {

class RoundedPolyline {
 public:
  /// corners: ≥ 2 points (metres), consecutive points distinct and no 180° turn-backs.
  /// radius: fillet radius of every interior corner, 0 ≤ radius ≤ max_radius(corners).
  /// The curve starts exactly at corners.front() and ends exactly at corners.back().
  RoundedPolyline(const std::vector<Vec2>& corners, double radius);

  /// Largest fillet radius for which the arcs of neighbouring corners do not overlap
  /// (a corner turning by δ consumes radius·tan(δ/2) of each adjacent segment).
  static double max_radius(const std::vector<Vec2>& corners);

  /// Total arc length (metres).
  double length() const { return m_length; }
  /// Point at arc length s ∈ [0, length()] (clamped).
  Vec2 point(double s) const;
  /// Unit tangent at arc length s (direction of increasing s).
  Vec2 tangent(double s) const;
  /// Arc lengths where the pieces (straight segments and fillet arcs) meet, with 0 first and
  /// length() last: where the curvature jumps.
  std::vector<double> breaks() const;
  /// Radius of curvature at arc length s: the fillet's radius on an arc, infinity on a segment.
  double radius_at(double s) const;

 private:
  struct Piece {
    bool arc = false;
    double begin = 0;  ///< arc length where the piece starts
    double length = 0;
    // line: start + σ·direction; arc: centre + radius·(cos, sin)(angle0 + turn·σ/radius)
    Vec2 start = Vec2::Zero(), direction = Vec2::Zero(), end = Vec2::Zero();
    Vec2 centre = Vec2::Zero();
    double radius = 0, angle0 = 0, turn = 1;  ///< turn = +1 (left, CCW) or −1 (right)
  };
  const Piece& piece_at(double s) const;

  std::vector<Piece> m_pieces;
  double m_length = 0;
};

}  // namespace cutwork::shapes_detail

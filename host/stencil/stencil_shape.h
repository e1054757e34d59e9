#pragma once
/// Stencil shapes: simple polygons (convex or not) in a 2-D reference frame, normalised so
/// that their minimum enclosing circle is the unit circle about the origin. The scale s of a
/// stencil is therefore its bounding-circle radius in metres, and the stencil's position q is
/// the centre of that circle — which is what the broad phase and the packing objective need.
///
/// Built-in kinds reproduce the shapes of the paper's Fig. 2 (stars, flowers, leaves, apples,
/// …); any simple polygon can be given instead (make_polygon_stencil). Several shapes form a
/// StencilLibrary, whose index is the stencil's type id.
#include <map>
#include <string>
#include <vector>

#include "host/core/types.h"
#include "kernels/clip/clip.h"

namespace cutwork {

/// Most vertices a stencil polygon may have (the clip kernel's cost per pair is linear in it).
inline constexpr int kMaxStencilPolygonVertices = 2048;

struct StencilShape {
  std::string name;            ///< unique within a design
  std::string kind;            ///< built-in kind, or "polygon"
  int type = -1;               ///< type id: index in the StencilLibrary (-1 until added)
  std::vector<Vec2> polygon;   ///< counter-clockwise, simple; minimum enclosing circle = unit
                               ///< circle about the origin (every |p| ≤ 1 + 1e-15)
  double area = 0;             ///< polygon area in reference units (m² = area · s²)
  double perimeter = 0;        ///< polygon perimeter in reference units (m = perimeter · s)
  double inner_radius = 0;     ///< radius of the largest origin-centred disk inside the polygon;
                               ///< 0 when the origin lies outside it (a crescent, a "C")
};

/// One parameter of a built-in kind.
struct StencilParamInfo {
  std::string name;
  double default_value = 0;
  double min = 0, max = 0;     ///< accepted range
  bool min_inclusive = true, max_inclusive = true;
  bool integer = false;
  std::string description;
};

struct StencilKindInfo {
  std::string kind;
  std::string description;
  std::vector<StencilParamInfo> params;
};

/// 4 A / P in reference units: the shape's hydraulic diameter, 2 (its bounding diameter) for a
/// circle, less for shapes with narrow features (0.885 for the default five-pointed star).
inline double stencil_hydraulic_diameter(const StencilShape& s) { return 4 * s.area / s.perimeter; }

/// Every built-in kind with its parameters, in a fixed order.
const std::vector<StencilKindInfo>& builtin_stencil_info();
/// The built-in kind names: circle, ellipse, square, star, flower, leaf, apple, heart, cross.
const std::vector<std::string>& builtin_stencil_kinds();

/// Builds a built-in shape. `params` may omit keys (defaults apply).
/// Throws InputError naming the shape, the kind or parameter and the accepted kinds / range,
/// for an unknown kind, an unknown parameter, a non-finite or out-of-range value, or a
/// non-integer value for an integer parameter.
StencilShape make_builtin_stencil(const std::string& kind,
                                  const std::map<std::string, double>& params,
                                  const std::string& name);

/// Builds a shape from a user polygon (any units, any position, either orientation).
/// Exact consecutive duplicates (including a closing point equal to the first) are dropped.
/// Throws InputError naming the shape for: fewer than 3 distinct points, more than
/// kMaxStencilPolygonVertices, non-finite coordinates, self-intersection (two edges that touch
/// or cross, other than neighbours at their shared point), zero area.
/// The polygon is oriented counter-clockwise, translated so that the centre of its minimum
/// enclosing circle is the origin, and scaled so that circle's radius is 1.
StencilShape make_polygon_stencil(const std::string& name, const std::vector<Vec2>& pts);

/// Signed area of a polygon (positive counter-clockwise), in its own units.
double polygon_signed_area(const std::vector<Vec2>& polygon);

/// Distance from `p` to the segment [a, b] (to a for a segment of no length).
double segment_distance(const Vec2& a, const Vec2& b, const Vec2& p);

/// Whether `p` lies inside the closed polygon `polygon` (either orientation; the even-odd rule, a
/// point on an edge either way).
bool point_in_polygon(const std::vector<Vec2>& polygon, const Vec2& p);

/// A shape whose polygon is given in its reference frame as it is (counter-clockwise, simple, every
/// |p| ≤ 1): not moved or rescaled, so it may lie strictly inside the unit circle — a stencil's
/// shape cut down about the same centre and scale (stencil_opening.h). Area, perimeter and inner
/// radius are measured; simplicity is the caller's. Throws InputError for fewer than 3 or more than
/// kMaxStencilPolygonVertices points, a point outside the unit circle or a clockwise polygon.
StencilShape shape_in_reference_frame(const std::string& name, const std::string& kind, std::vector<Vec2> polygon);

/// The shapes of one design; a shape's index is its type id.
class StencilLibrary {
 public:
  StencilLibrary() = default;
  /// Adds a shape, assigns its type id and returns it. Throws InputError on a duplicate name.
  int add(StencilShape shape);
  int size() const { return int(m_shapes.size()); }
  const StencilShape& operator[](int type) const { return m_shapes.at(size_t(type)); }
  const std::vector<StencilShape>& shapes() const { return m_shapes; }
  /// Type id of the shape called `name`, or -1.
  int find(const std::string& name) const;

  /// Kernel buffers: one ClipShape per type, and all polygons packed as (x, y) doubles.
  const std::vector<kernels::ClipShape>& clip_shapes() const { return m_clip_shapes; }
  const std::vector<double>& packed_polygons() const { return m_packed; }

 private:
  std::vector<StencilShape> m_shapes;
  std::vector<kernels::ClipShape> m_clip_shapes;
  std::vector<double> m_packed;
};

}  // namespace cutwork

#pragma once
/// Built-in procedural shapes: plate, sheet, bowl, pavilion, table, chair. Each is meshed from
/// a 2-D parameter domain with near-equilateral triangles at a target edge length, so one shape
/// gives both the base mesh (what is cut and exported) and a coarser simulation mesh.
///
/// Units and frame: SI (metres), z up, every shape resting on or centred in z = 0:
///   plate, sheet  flat in z = 0, centred at the origin (x ∈ ±width/2, y ∈ ±height/2).
///   bowl          spherical cap, bottom vertex at the origin, rim circle (radius) at z = depth.
///   pavilion      vault over the disk of `radius` about the z axis, crown vertex at
///                 (0, 0, height); each foot is a strip of the rim exactly on z = 0 (legs
///                 centred at angles (2k+1)·π/legs), so "z below 0.01" selects one cluster of
///                 rim vertices per leg.
///   table         ∩ profile in x-z extruded over y ∈ ±depth/2; panels at x = ±length/2 end
///                 exactly on z = 0, top exactly at z = height.
///   chair         "Z" profile (x forward) extruded over y ∈ ±width/2; the floor runner lies
///                 exactly on z = 0, the back rest top edge at (−back_recline, back_height).
/// Orientation (faces CCW about their normal): normals point to the outside of the object —
/// up on flat parts (plate, sheet, table top, chair seat and runner), outward on the table's
/// side panels, forward (towards the sitter) on the chair's back rest, and to the convex side
/// of the curved shells (pavilion: up/out; bowl: away from the sphere's centre, i.e. down/out).
///
/// Meshers and triangle quality (smallest angle at the default parameters):
///   plate, sheet, table, chair  a staggered lattice on a rectangle (for table and chair the
///       (arc length × width) rectangle of the extruded profile, an isometric map); every angle
///       ≥ 30° on the flat shapes, ≥ 29° on the extruded ones when an arc is coarser than the
///       edge length (chords). Boundary vertices lie exactly on the rectangle's sides.
///   bowl      hexagonal-ring disk (ring k has 6k vertices) mapped by the azimuthal
///       equidistant (geodesic polar) map onto the cap, then tangentially relaxed: ≥ 42°
///       (≥ 35° for a hemisphere).
///   pavilion  the same disk placed evenly in 3-D arc length along every ray, then
///       tangentially relaxed: ≥ 34° at the defaults, ≥ 25° over the admissible parameters.
/// The mean edge length is within a few percent of the requested one; the face count scales
/// as 1/edge_length². Generation is deterministic (no randomness, no threading).
#include <map>
#include <string>
#include <vector>

#include "host/mesh/surface_mesh.h"

namespace cutwork {

/// Named shape parameters in metres/radians/counts, e.g. {"width": 0.2}. Missing keys take the
/// shape's defaults; unknown keys are rejected.
using ShapeParameters = std::map<std::string, double>;

struct ShapeInfo {
  std::string name;
  std::string description;               ///< one line
  ShapeParameters defaults;              ///< every accepted parameter with its default
  double base_edge_length = 0;           ///< default base-mesh resolution (m)
  double sim_edge_length = 0;            ///< default simulation-mesh resolution (m)
};

/// All built-in shapes, in a fixed order.
const std::vector<ShapeInfo>& builtin_shapes();
/// The entry for `name`, or nullptr.
const ShapeInfo* find_shape(const std::string& name);

/// Meshes shape `name` with target edge length `edge_length` (m); params override defaults.
/// Returns a connected, consistently oriented disk (Euler characteristic 1, one boundary loop)
/// whose SurfaceMesh `what` is "shape '<name>'".
/// Throws InputError for an unknown name, an unknown or out-of-range parameter
/// ("shape 'bowl': parameter 'depth' must be in [0.0075, 0.15] (got 0.2)"; bounds that depend
/// on other parameters are stated as numbers), an edge length that is not finite and positive
/// or coarser than the shape allows (the message gives the admissible interval), or one that
/// would exceed `max_faces` faces (the message gives the finest edge length that fits).
/// `length_key` names the edge length in messages (a scene's "edge_length" or "sim_edge_length").
inline constexpr int default_max_faces = 4'000'000;
SurfaceMesh generate_shape(const std::string& name, const ShapeParameters& params,
                           double edge_length, int max_faces = default_max_faces,
                           const std::string& length_key = "edge_length");

}  // namespace cutwork

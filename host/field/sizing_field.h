#pragma once
/// The sizing field of §4.4: a per-vertex scalar multiplier of the stencil scale, interpolated
/// linearly inside each face. Packing uses it as the local target scale (scale × sizing);
/// discrete element textures scale the exemplar by it when matching (6).
///
/// Sources, combined in this order:
///  1. a constant (`pattern.sizing`, default 1);
///  2. optionally a file with one value per base-mesh vertex, multiplied into the constant;
///  3. brush strokes (centre, radius, value), painted in scene order: each moves the field
///     towards its value with weight 1 within half the radius, falling smoothly (C¹, cubic) to
///     0 at the radius — a brush "paints" an absolute multiplier, as a user expects from a
///     painting tool; a later brush paints over an earlier one.
/// All values must be finite and positive.
#include <filesystem>
#include <vector>

#include "host/mesh/surface_mesh.h"
#include "host/scene/scene.h"

namespace cutwork {

class SizingField {
 public:
  SizingField() = default;
  /// A field with one value per vertex (#V, finite, > 0). Throws InputError otherwise,
  /// naming `what`.
  SizingField(Eigen::VectorXd vertex_values, const std::string& what = "sizing");

  /// The field of a scene's pattern settings on `mesh` (constant × file, then brushes).
  /// Throws InputError naming the file (and line) for an unreadable file, a value that is not a
  /// finite positive number, or a count different from the mesh's vertex count.
  static SizingField from_settings(const PatternSettings& settings, const SurfaceMesh& mesh);

  /// #V per-vertex values.
  const Eigen::VectorXd& vertex_values() const { return m_values; }
  /// Linear interpolation at a surface point of `mesh` (the mesh the field was built on).
  double value(const SurfaceMesh& mesh, const SurfacePoint& p) const;
  double min_value() const { return m_values.size() ? m_values.minCoeff() : 1.0; }
  double max_value() const { return m_values.size() ? m_values.maxCoeff() : 1.0; }
  /// ∫ value^k dA / ∫ dA over the mesh (one-point quadrature per face at the centroid value),
  /// used to relate a stencil count to a scale when the field is not constant.
  double mean_power(const SurfaceMesh& mesh, double k) const;

 private:
  Eigen::VectorXd m_values;
};

/// Reads one value per line (blank lines and lines starting with '#' ignored).
/// Throws InputError("<file>:<line>: ...") for unreadable files and bad values.
Eigen::VectorXd read_sizing_file(const std::filesystem::path& file);

/// The brush weight at normalised distance t = |x − centre| / radius: 1 for t ≤ ½, a cubic
/// smoothstep down to 0 at t = 1, 0 beyond.
double brush_weight(double t);

}  // namespace cutwork

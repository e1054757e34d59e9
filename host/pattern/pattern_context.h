#pragma once
/// PatternContext gathers everything derived from a scene that pattern code needs — stencil
/// shapes, the orientation field (symmetry matched to the shapes and exemplar), the sizing
/// field, the surface queries, the exemplar, the units — so that the pattern phase and the
/// joint optimiser of the structural phase (solvers/optimize/joint_optimizer.h) share one
/// objective, one set of bounds, one re-matching and one hole filling. Host code only.
///
/// Units and automatic choices:
///  - ℓ (`unit`): the nominal stencil scale (bounding radius, m): pattern.scale when given;
///    else from pattern.count (packing: a maximal Poisson-disk packing of that many stencils;
///    exemplar: the exemplar's density); else automatic: the scale at which ~300 stencils
///    (the paper's Table 1: 185–462) cover the surface, but at least one base-mesh edge length.
///    On symmetry planes the surface is the whole's (~300 / 2^planes stencils on the model; an
///    explicit pattern.count counts the model's stencils).
///  - ε = pattern.epsilon × the object's length (longest bounding-box side, of the whole on
///    symmetry planes), §4.2.
///  - σ_0 (exemplar → metres) = ℓ / the exemplar's mean element scale.
///  - Scale bounds: packing [scale_min, scale_max] × ℓ × sizing at the stencil's start;
///    exemplar [scale_min × smallest, scale_max × largest] exemplar scale × σ_0 × sizing.
///  - The field symmetry N: pattern.symmetry, or field_symmetry_for(shapes, exemplar).
#include <memory>
#include <string>
#include <vector>

#include "host/pattern/det.h"
#include "host/pattern/pattern_energy.h"
#include "host/pattern/pattern_surface.h"
#include "host/scene/scene.h"
#include "host/stencil/frame.h"
#include "host/stencil/stencil_shape.h"

namespace cutwork {

/// The stencil shapes of a scene as a library (type id = index in scene.shapes); a scene
/// without shapes gets one built-in circle.
StencilLibrary scene_stencil_library(const Scene& scene);

class PatternContext {
 public:
  /// Builds shapes, fields, surface queries and the exemplar for the scene's base mesh
  /// (`meshes.base`, which must outlive the context). Throws InputError for a bad exemplar,
  /// sizing file, or stroke.
  PatternContext(const Scene& scene, const SceneMeshes& meshes);
  PatternContext(const PatternContext&) = delete;
  PatternContext& operator=(const PatternContext&) = delete;

  const PatternSettings& settings() const { return m_settings; }
  const StencilLibrary& shapes() const { return m_shapes; }
  const PatternSurface& surface() const { return *m_surface; }
  PatternKind kind() const { return m_kind; }
  /// Exemplar model (nullptr for packing).
  const DetExemplar* exemplar() const { return m_exemplar.get(); }
  PatternEnergy& energy() { return *m_energy; }
  const PatternEnergy& energy() const { return *m_energy; }
  double unit() const { return m_unit; }
  double epsilon() const { return m_epsilon; }
  int symmetry() const { return m_symmetry; }
  /// Notes for the report (automatic choices, adjustments).
  const std::vector<std::string>& notes() const { return m_notes; }

  /// A fresh initial layout (Poisson disk or DET growth), deterministic for the seed.
  StencilLayout initialize(PatternRng& rng) const;
  /// §6.3: re-runs the initialisation on an existing layout; returns the number added.
  int fill_holes(StencilLayout& layout, PatternRng& rng) const;
  /// Scale bounds (m) of each stencil of `layout` (see the file comment).
  void scale_bounds(const StencilLayout& layout, Eigen::VectorXd& lower, Eigen::VectorXd& upper) const;

 private:
  PatternSettings m_settings;
  StencilLibrary m_shapes;
  std::unique_ptr<PatternSurface> m_surface;
  PatternKind m_kind = PatternKind::Packing;
  std::unique_ptr<DetExemplar> m_exemplar;
  std::unique_ptr<PatternEnergy> m_energy;
  double m_unit = 0, m_epsilon = 0;
  int m_symmetry = 1;
  std::vector<std::string> m_notes;
};

}  // namespace cutwork

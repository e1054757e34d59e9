#pragma once
/// The files a designer opens and prints beside report.json: fields.vtu and stencils.vtp
/// (ParaView), cut_solid.stl and cut_solid.3mf (the printable solid, checked by CGAL), and the
/// pictures render_W.png, render_alpha.png, render_design.png. Everything is computed by
/// prepare_design_files, before anything is written; write() then only writes (atomically,
/// file by file) into a folder given by the caller, and report() is what report.json records.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/core/output_set.h"
#include "host/cut/cut_surface.h"
#include "host/export/min_feature.h"
#include "host/export/solid.h"
#include "host/export/vtk_files.h"
#include "host/render/pictures.h"

namespace cutwork {

struct DesignFileInputs {
  std::string title;                       ///< the scene's name (picture titles, 3MF object name)
  const SurfaceMesh* base = nullptr;       ///< the base mesh (what was cut)
  const SurfaceMesh* sim = nullptr;        ///< the simulation mesh
  MeshFields sim_fields;                   ///< per-face alpha, W, … and per-vertex displacement on `sim`
  double beta = std::numeric_limits<double>::quiet_NaN();  ///< threshold β (J/m²), NaN: none
  /// The stencils' outlines on the surface (stencil_outlines) and their type ids; none: no .vtp.
  std::optional<std::vector<RowMatX3d>> outlines;
  Eigen::VectorXd outline_types;
  /// The cut surface; null: no solid, no minimum-feature check, and render_design shows `base`.
  const CutSurface* cut = nullptr;
  /// false: `cut` is only drawn (a simulation of a design's stencils): no solid, no check.
  bool fabrication = true;
  double thickness = 0;                    ///< material thickness (m), for the solid
  double min_feature = 0.001;              ///< printable minimum (m)
  /// The symmetry planes the model is a half (or quarter) on (LoadCase::symmetry_planes: x = .x(), …;
  /// NaN: none). The solid is then the whole: the cut surface completed by its mirror images, each
  /// plane in turn, thickened along the mirrored base's normals. The minimum-feature check reads the
  /// modelled part (a margin to the plane counts as one to a boundary: the whole's ligament across
  /// the plane is twice it).
  Vec3 symmetry_planes = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct DesignFileOptions {
  bool render = true;                      ///< false: no PNGs (--no-render)
  render::PictureOptions pictures;
  /// Called with a short stage name ("solid", "minimum feature", "render W", …) before each
  /// step that takes a while (progress display); may be empty.
  std::function<void(const std::string&)> progress;
};

class DesignFiles {
 public:
  /// report.json's `fabrication` object: {thickness, min_feature, solid {written, valid,
  /// problem, vertices, triangles, volume, area, closed, manifold, self_intersecting, outward},
  /// narrowest_between_stencils, narrowest_to_boundary, holes, violations [{kind, width,
  /// point_a, point_b}], units}; null when there is no cut surface.
  nlohmann::json fabrication_report() const { return m_fabrication; }
  /// The file names write() will write, in order.
  std::vector<std::string> file_names() const;
  /// Writes every file where `place` puts it (a folder that exists, or an output set's staging);
  /// returns the paths written.
  std::vector<std::filesystem::path> write(const FilePlacer& place) const;
  std::vector<std::filesystem::path> write(const std::filesystem::path& dir) const { return write(placer(dir)); }

 private:
  friend DesignFiles prepare_design_files(const DesignFileInputs&, const DesignFileOptions&);
  DesignFileInputs m_in;
  std::optional<Solid> m_solid;  ///< only when CGAL found it valid
  nlohmann::json m_fabrication;
  std::vector<std::pair<std::string, std::string>> m_pictures;  ///< file name, PNG bytes
};

/// Computes the solid and its check, the minimum-feature check and the pictures. Throws
/// InputError for inconsistent inputs (field sizes); a solid that fails CGAL's check is not an
/// error: it is not written and the report says why.
DesignFiles prepare_design_files(const DesignFileInputs& inputs, const DesignFileOptions& options);

}  // namespace cutwork

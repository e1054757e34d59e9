#include "host/export/design_files.h"

#include <cmath>

#include <fmt/format.h>

#include "host/core/atomic_file.h"
#include "host/core/error.h"
#include "host/mesh/mirror.h"

namespace cutwork {
namespace {

nlohmann::json point_json(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

nlohmann::json solid_json(const Solid& s, const SolidCheck& c, bool written) {
  return {{"written", written},          {"valid", c.valid()},
          {"problem", c.problem},        {"vertices", s.vertices.rows()},
          {"triangles", s.faces.rows()}, {"volume", c.volume},
          {"area", c.area},              {"closed", c.closed},
          {"manifold", c.manifold},      {"self_intersecting", c.self_intersecting},
          {"outward", c.outward}};
}

nlohmann::json min_feature_json(const MinFeatureReport& m) {
  nlohmann::json v = nlohmann::json::array();
  for (const LigamentViolation& x : m.violations)
    v.push_back({{"kind", x.kind}, {"width", x.width}, {"point_a", point_json(x.point_a)},
                 {"point_b", point_json(x.point_b)}});
  return {{"holes", m.holes},
          {"narrowest_between_stencils", finite_or_null(m.narrowest_between_stencils)},
          {"narrowest_to_boundary", finite_or_null(m.narrowest_to_boundary)},
          {"violation_count", m.violations.size()},
          {"violations", v}};
}

}  // namespace

DesignFiles prepare_design_files(const DesignFileInputs& in, const DesignFileOptions& options) {
  auto stage = [&](const std::string& s) {
    if (options.progress) options.progress(s);
  };
  DesignFiles d;
  d.m_in = in;
  if (in.cut != nullptr && in.fabrication) {
    stage("solid");
    // The whole a half model stands for: the cut surface and the base mirrored in each symmetry
    // plane in turn, vertices on a plane shared.
    RowMatX3d cut_v = in.cut->vertices, base_v = in.base->vertices();
    RowMatX3i cut_f = in.cut->faces, base_f = in.base->faces();
    nlohmann::json mirrored = nlohmann::json::array();
    const double snap = 1e-9 * (in.base->bbox_max() - in.base->bbox_min()).norm();
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(in.symmetry_planes[a])) continue;
      MirroredMesh c = mirror_across_plane(cut_v, cut_f, a, in.symmetry_planes[a], snap);
      MirroredMesh b = mirror_across_plane(base_v, base_f, a, in.symmetry_planes[a], snap);
      cut_v = std::move(c.vertices), cut_f = std::move(c.faces);
      base_v = std::move(b.vertices), base_f = std::move(b.faces);
      mirrored.push_back(std::string(1, char('x' + a)));
    }
    // Offset along the base surface's smooth Phong normals: the cut's sliver triangles along
    // the outlines would otherwise fold the offset where the surface bends (the pavilion's feet).
    const std::optional<SurfaceMesh> whole_base =
        mirrored.empty() ? std::nullopt : std::optional<SurfaceMesh>(SurfaceMesh(base_v, base_f, "the mirrored base mesh"));
    const FaceBvh base_bvh(whole_base ? *whole_base : *in.base);
    const RowMatX3d normals = surface_normals_at(base_bvh, cut_v);
    const Solid solid = thicken_surface(cut_v, cut_f, in.thickness, &normals);
    const SolidCheck check = check_solid(solid);
    if (check.valid()) d.m_solid = solid;
    stage("minimum feature");
    const MinFeatureReport mf = check_min_feature(*in.cut, *in.base, in.min_feature, in.symmetry_planes);
    d.m_fabrication = min_feature_json(mf);
    d.m_fabrication["thickness"] = in.thickness;
    d.m_fabrication["min_feature"] = in.min_feature;
    d.m_fabrication["solid"] = solid_json(solid, check, check.valid());
    d.m_fabrication["solid"]["mirrored"] = mirrored;  // the planes the solid is completed across
    d.m_fabrication["units"] = {{"thickness", "m"}, {"min_feature", "m"}, {"width", "m"}, {"volume", "m^3"},
                                {"area", "m^2"}, {"files", "mm"}};
  }
  if (options.render) {
    render::DesignFields f;
    f.title = in.title;
    f.sim_vertices = &in.sim->vertices();
    f.sim_faces = &in.sim->faces();
    if (auto it = in.sim_fields.face.find("W"); it != in.sim_fields.face.end()) f.energy_density = it->second;
    if (auto it = in.sim_fields.face.find("alpha"); it != in.sim_fields.face.end()) f.fill_ratio = it->second;
    f.beta = in.beta;
    f.cut_vertices = in.cut ? &in.cut->vertices : &in.base->vertices();
    f.cut_faces = in.cut ? &in.cut->faces : &in.base->faces();
    for (render::Field field : {render::Field::EnergyDensity, render::Field::FillRatio, render::Field::Design}) {
      if (field == render::Field::EnergyDensity && f.energy_density.size() == 0) continue;
      if (field == render::Field::FillRatio && f.fill_ratio.size() == 0) continue;
      stage(fmt::format("render {}", render::to_string(field)));
      d.m_pictures.emplace_back(fmt::format("render_{}.png", render::to_string(field)),
                                render::encode_png(render::draw_picture(f, field, options.pictures)));
    }
  }
  return d;
}

std::vector<std::string> DesignFiles::file_names() const {
  std::vector<std::string> names = {"fields.vtu"};
  if (m_in.outlines) names.push_back("stencils.vtp");
  if (m_solid) {
    names.push_back("cut_solid.stl");
    names.push_back("cut_solid.3mf");
  }
  for (const auto& [name, bytes] : m_pictures) names.push_back(name);
  return names;
}

std::vector<std::filesystem::path> DesignFiles::write(const FilePlacer& place) const {
  std::vector<std::filesystem::path> written;
  auto put = [&](const std::string& name) { return written.emplace_back(place(name)); };
  write_vtu(put("fields.vtu"), *m_in.sim, m_in.sim_fields);
  if (m_in.outlines) {
    std::map<std::string, Eigen::VectorXd> cells = {
        {"stencil", Eigen::VectorXd::LinSpaced(Eigen::Index(m_in.outlines->size()), 0,
                                               double(m_in.outlines->size()) - 1)}};
    if (m_in.outline_types.size() == Eigen::Index(m_in.outlines->size())) cells["type"] = m_in.outline_types;
    write_vtp_polylines(put("stencils.vtp"), *m_in.outlines, true, cells);
  }
  if (m_solid) {
    write_stl(put("cut_solid.stl"), *m_solid);
    write_3mf(put("cut_solid.3mf"), *m_solid, m_in.title);
  }
  for (const auto& [name, bytes] : m_pictures) write_file_atomic(put(name), bytes);
  return written;
}

}  // namespace cutwork

#include "host/field/sizing_field.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/core/input_file.h"

namespace cutwork {

SizingField::SizingField(Eigen::VectorXd vertex_values, const std::string& what)
    : m_values(std::move(vertex_values)) {
  for (Eigen::Index i = 0; i < m_values.size(); ++i)
    if (!std::isfinite(m_values[i]) || !(m_values[i] > 0))
      throw InputError(fmt::format("{}: vertex {}: sizing value {} is not a finite positive number",
                                   what, i, m_values[i]));
}

double brush_weight(double t) {
  if (!(t < 1.0)) return 0.0;
  if (t <= 0.5) return 1.0;
  const double u = (t - 0.5) / 0.5;
  return 1.0 - u * u * (3.0 - 2.0 * u);
}

Eigen::VectorXd read_sizing_file(const std::filesystem::path& file) {
  std::istringstream in(read_input_file(file, max_json_file_bytes, "a sizing file (one number per line)"));
  std::vector<double> values;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ls(line);
    double v = 0;
    std::string rest;
    if (!(ls >> v) || (ls >> rest))
      throw InputError(fmt::format("{}:{}: expected one number per line, got '{}'", file.string(),
                                   line_no, line));
    if (!std::isfinite(v) || !(v > 0))
      throw InputError(fmt::format("{}:{}: sizing value {} must be finite and positive",
                                   file.string(), line_no, v));
    values.push_back(v);
  }
  if (in.bad()) throw InputError(file.string() + ": read error");
  return Eigen::Map<Eigen::VectorXd>(values.data(), Eigen::Index(values.size()));
}

SizingField SizingField::from_settings(const PatternSettings& settings, const SurfaceMesh& mesh) {
  Eigen::VectorXd v = Eigen::VectorXd::Constant(mesh.num_vertices(), settings.sizing);
  if (!settings.sizing_file.empty()) {
    const Eigen::VectorXd file = read_sizing_file(settings.sizing_file);
    if (file.size() != mesh.num_vertices())
      throw InputError(fmt::format(
          "{}: has {} sizing values but the base mesh has {} vertices (one value per vertex, in "
          "vertex order)",
          settings.sizing_file.string(), file.size(), mesh.num_vertices()));
    v = v.cwiseProduct(file);
  }
  const RowMatX3d& X = mesh.vertices();
  for (const SizingBrush& b : settings.brushes)
    for (int i = 0; i < mesh.num_vertices(); ++i) {
      const double w = brush_weight((X.row(i).transpose() - b.center).norm() / b.radius);
      v[i] += w * (b.value - v[i]);
    }
  return SizingField(std::move(v), "pattern.sizing");
}

double SizingField::value(const SurfaceMesh& mesh, const SurfacePoint& p) const {
  const auto f = mesh.faces().row(p.face);
  return p.bary[0] * m_values[f[0]] + p.bary[1] * m_values[f[1]] + p.bary[2] * m_values[f[2]];
}

double SizingField::mean_power(const SurfaceMesh& mesh, double k) const {
  double num = 0, den = 0;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto t = mesh.faces().row(f);
    const double c = (m_values[t[0]] + m_values[t[1]] + m_values[t[2]]) / 3.0;
    num += mesh.face_areas()[f] * std::pow(c, k);
    den += mesh.face_areas()[f];
  }
  return den > 0 ? num / den : 1.0;
}

}  // namespace cutwork

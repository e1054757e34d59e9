#include "solvers/objective/structural_quantities.h"

#include "solvers/objective/energy_density.h"
#include "solvers/objective/peak_energy_density.h"
#include "solvers/shell/fill_ratio_partials.h"
#include "solvers/shell/shell_energy.h"

namespace cutwork::solvers {

namespace {

void zero_fixed_rows(const ShellModel& model, RowMatX3d& m) {
  for (int v = 0; v < model.num_vertices(); ++v)
    if (model.vertex_node()[v] < 0) m.row(v).setZero();
}

}  // namespace

std::vector<bool> material_faces(const Eigen::VectorXd& alpha) {
  std::vector<bool> m(size_t(alpha.size()));
  bool any = false;
  for (Eigen::Index f = 0; f < alpha.size(); ++f) {
    m[size_t(f)] = alpha[f] > kMaterialFillRatio;
    any = any || m[size_t(f)];
  }
  if (!any) m.assign(m.size(), true);
  return m;
}

std::vector<bool> material_vertices(const RowMatX3i& faces, int num_vertices, const std::vector<bool>& material) {
  std::vector<bool> v(size_t(num_vertices), false);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    if (material[size_t(f)])
      for (int k = 0; k < 3; ++k) v[size_t(faces(f, k))] = true;
  return v;
}

EquilibriumSummary summarize_equilibrium(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha,
                                         const Eigen::VectorXd* concentration_weight,
                                         const ShapeCover* cover) {
  EquilibriumSummary s;
  s.strain_energy = shell_energy(model, x, alpha);
  const RowMatX3d u = x - model.rest_positions();
  s.compliance = (model.external_forces(alpha).array() * u.array()).sum();
  const Eigen::VectorXd un = u.rowwise().norm();
  const std::vector<bool> faces = material_faces(alpha);
  const std::vector<bool> vertices = material_vertices(model.mesh().faces(), model.num_vertices(), faces);
  for (int v = 0; v < model.num_vertices(); ++v)
    if (vertices[size_t(v)] && (s.max_displacement_vertex < 0 || un[v] > s.max_displacement)) {
      s.max_displacement = un[v];
      s.max_displacement_vertex = v;
    }
  s.energy_density = energy_density(model, x, alpha);
  for (int f = 0; f < model.num_faces(); ++f)
    if (faces[size_t(f)] && (s.W_max_face < 0 || s.energy_density[f] > s.W_max)) {
      s.W_max = s.energy_density[f];
      s.W_max_face = f;
    }
  const ConcentrationMap K = ConcentrationMap::for_mechanics(model.mechanics(), model.material());
  if (!K.empty()) {
    s.peak_energy_density = peak_energy_density(model, x, alpha, K, concentration_weight, cover);
    for (int f = 0; f < model.num_faces(); ++f)
      if (faces[size_t(f)] && (s.W_peak_max_face < 0 || s.peak_energy_density[f] > s.W_peak_max)) {
        s.W_peak_max = s.peak_energy_density[f];
        s.W_peak_max_face = f;
      }
    if (K.thick_scale() > 0) {
      s.W_peak_thick_scale = K.thick_scale();
      s.peak_energy_density_kirchhoff = peak_energy_density(
          model, x, alpha, ConcentrationMap(model.mechanics().stiffness_curve), concentration_weight, cover);
      for (int f = 0; f < model.num_faces(); ++f)
        if (faces[size_t(f)] && !(s.peak_energy_density_kirchhoff[f] <= s.W_peak_kirchhoff_max))
          s.W_peak_kirchhoff_max = s.peak_energy_density_kirchhoff[f];
    }
    if (K.by_biaxiality() && s.W_peak_max_face >= 0) {
      const Eigen::MatrixX2d rho = stress_biaxiality(model, x, alpha, K);
      s.W_peak_membrane_biaxiality = rho(s.W_peak_max_face, 0);
      s.W_peak_bending_biaxiality = rho(s.W_peak_max_face, 1);
    }
  }
  return s;
}

ObjectiveTerms strain_energy_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  ShellAssembly a;
  assemble_shell(model, x, alpha, false, a);
  ObjectiveTerms t;
  t.value = a.energy;
  t.d_positions = RowMatX3d::Zero(model.num_vertices(), 3);
  model.scatter_free(a.gradient, t.d_positions);
  t.d_alpha = energy_alpha_gradient(model, x, alpha);
  return t;
}

ObjectiveTerms compliance_terms(const ShellModel& model, const RowMatX3d& x, const Eigen::VectorXd& alpha) {
  const RowMatX3d u = x - model.rest_positions();
  ObjectiveTerms t;
  t.d_positions = model.external_forces(alpha);
  t.value = (t.d_positions.array() * u.array()).sum();
  zero_fixed_rows(model, t.d_positions);
  t.d_alpha.setZero(model.num_faces());
  model.add_load_alpha_product(u, alpha, t.d_alpha);
  return t;
}

}  // namespace cutwork::solvers

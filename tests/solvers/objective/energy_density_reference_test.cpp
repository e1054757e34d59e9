// The converging reference energy density (energy_density_reference.h): its definition on a small
// hand-made field, and on a clamped L-shaped plate, whose W_max grows like 1/h at the re-entrant
// corner while the area quantile W_q(2%) stays put under refinement.
#include <gtest/gtest.h>

#include <vector>

#include "host/core/error.h"
#include "solvers/equilibrium/equilibrium_solver.h"
#include "solvers/objective/energy_density_reference.h"
#include "solvers/objective/structural_quantities.h"

namespace cutwork::solvers {
namespace {

TEST(EnergyDensityReference, TheQuantileLeavesOutTheTopAreaFraction) {
  // Five faces of material (areas 1, 1, 2, 4, 2; W 9, 7, 5, 3, 1) and a filler face at W = 100.
  const Eigen::VectorXd W = (Eigen::VectorXd(6) << 9, 7, 5, 3, 1, 100).finished();
  const Eigen::VectorXd A = (Eigen::VectorXd(6) << 1, 1, 2, 4, 2, 1).finished();
  const std::vector<bool> material = {true, true, true, true, true, false};
  EnergyDensityQuantile q = energy_density_quantile(W, A, material, 0.0);
  EXPECT_EQ(q.value, 9);  // W_max over material
  EXPECT_EQ(q.faces_above, 0);
  EXPECT_EQ(q.material_area, 10);
  q = energy_density_quantile(W, A, material, 0.1);  // 1 m² may go: the face at 9
  EXPECT_EQ(q.value, 7);
  EXPECT_EQ(q.faces_above, 1);
  EXPECT_EQ(q.area_above, 1);
  q = energy_density_quantile(W, A, material, 0.39);  // 3.9 m²: 9 and 7 go, 5 (2 m²) does not fit
  EXPECT_EQ(q.value, 5);
  EXPECT_EQ(q.area_above, 2);
  // Equal W goes whole or not at all.
  const Eigen::VectorXd tied = (Eigen::VectorXd(6) << 9, 9, 5, 3, 1, 100).finished();
  EXPECT_EQ(energy_density_quantile(tied, A, material, 0.15).value, 9);
  EXPECT_THROW(energy_density_quantile(W, A, material, 1.0), InputError);
  EXPECT_THROW(energy_density_quantile(W, A, std::vector<bool>(6, false), 0.1), InputError);
  EXPECT_THROW(energy_density_quantile(W, A.head(5), material, 0.1), InputError);
}

/// [-1, 1]² without the quadrant (0, 1]², a grid of spacing 1/n; the two edges that meet at the
/// re-entrant corner (0, 0) clamped; 1 Pa downwards. W_max and W_q(2%) at equilibrium.
std::pair<double, EnergyDensityQuantile> l_plate(int n) {
  const int N = 2 * n + 1;
  std::vector<int> id(size_t(N * N), -1);
  std::vector<Vec3> P;
  for (int j = 0; j < N; ++j)
    for (int i = 0; i < N; ++i)
      if (!(i > n && j > n)) {
        id[size_t(j * N + i)] = int(P.size());
        P.emplace_back(-1 + double(i) / n, -1 + double(j) / n, 0);
      }
  std::vector<Eigen::Vector3i> faces;
  for (int j = 0; j + 1 < N; ++j)
    for (int i = 0; i + 1 < N; ++i) {
      if (i >= n && j >= n) continue;
      const int a = id[size_t(j * N + i)], b = id[size_t(j * N + i + 1)], c = id[size_t((j + 1) * N + i)],
                d = id[size_t((j + 1) * N + i + 1)];
      if ((i + j) % 2) {
        faces.emplace_back(a, b, d);
        faces.emplace_back(a, d, c);
      } else {
        faces.emplace_back(a, b, c);
        faces.emplace_back(b, d, c);
      }
    }
  RowMatX3d V(Eigen::Index(P.size()), 3);
  for (size_t k = 0; k < P.size(); ++k) V.row(Eigen::Index(k)) = P[k].transpose();
  RowMatX3i F(Eigen::Index(faces.size()), 3);
  for (size_t k = 0; k < faces.size(); ++k) F.row(Eigen::Index(k)) = faces[k].transpose();
  const SurfaceMesh mesh(V, F, "L-shaped plate");
  LoadCase lc;
  lc.fixed.assign(P.size(), false);
  lc.clamped.assign(P.size(), false);
  lc.forces = RowMatX3d::Zero(Eigen::Index(P.size()), 3);
  for (size_t k = 0; k < P.size(); ++k) {
    const Vec3& p = P[k];
    if ((p.y() == 0 && p.x() >= 0) || (p.x() == 0 && p.y() >= 0)) lc.fixed[k] = lc.clamped[k] = true;
  }
  for (int f = 0; f < mesh.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) lc.forces(F(f, k), 2) -= mesh.face_areas()[f] / 3;
  Material m;
  m.youngs_modulus = 1e9;
  m.poisson_ratio = 0.3;
  m.thickness = 0.01;
  m.density = 1000;
  const ShellModel model(mesh, m, lc);
  EquilibriumSolver solver(model);
  const Eigen::VectorXd alpha = Eigen::VectorXd::Ones(mesh.num_faces());
  solver.solve(alpha);
  const EquilibriumSummary s = summarize_equilibrium(model, solver.positions(), alpha);
  return {s.W_max, energy_density_quantile(s.energy_density, mesh.face_areas(), material_faces(alpha))};
}

TEST(EnergyDensityReference, ConvergesAtAClampedReentrantCornerWhereWmaxDiverges) {
  // Measured: W_max 0.0284 → 0.0564 J/m² (x1.99) from h = 1/16 to 1/32, at the corner's faces;
  // W_q(2%) 5.241 → 5.250 mJ/m² (0.2%).
  const auto [w16, q16] = l_plate(16);
  const auto [w32, q32] = l_plate(32);
  EXPECT_GT(w32 / w16, 1.8);
  EXPECT_LT(std::abs(q32.value - q16.value), 0.01 * q32.value);
  EXPECT_LT(q32.value, 0.2 * w32);
  for (const EnergyDensityQuantile& q : {q16, q32}) {
    EXPECT_GT(q.faces_above, 0);
    EXPECT_LE(q.area_above, kReferenceAreaFraction * q.material_area);
  }
}

}  // namespace
}  // namespace cutwork::solvers

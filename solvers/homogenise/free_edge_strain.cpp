#include "solvers/homogenise/free_edge_strain.h"

#include <algorithm>
#include <map>
#include <utility>

namespace cutwork::solvers {

std::vector<FreeEdgeStrain> free_edge_strains(const RowMatX3d& X, const RowMatX3i& F, const RowMatX3d& u,
                                              int first_face, int num_faces) {
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      ++uses[std::minmax(a, b)];
    }
  const int last = num_faces < 0 ? int(F.rows()) : std::min(int(F.rows()), first_face + num_faces);
  std::vector<FreeEdgeStrain> out;
  for (int f = first_face; f < last; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if (uses[std::minmax(a, b)] != 1) continue;
      const Vec3 d = (X.row(b) - X.row(a)).transpose();
      const double L = d.norm();
      const Vec3 du = (u.row(b) - u.row(a)).transpose();
      out.push_back({f, a, b, d.dot(du) / (L * L)});
    }
  return out;
}

double free_edge_energy_density(const Material& m, double strain, double curvature, double twist) {
  const double E = m.youngs_modulus, h = m.thickness, nu = m.poisson_ratio;
  const double D = E * h * h * h / (12 * (1 - nu * nu));
  return 0.5 * E * h * strain * strain + 0.5 * D * (1 - nu * nu) * curvature * curvature +
         D * (1 - nu) * twist * twist;
}

}  // namespace cutwork::solvers

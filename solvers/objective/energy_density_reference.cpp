#include "solvers/objective/energy_density_reference.h"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork::solvers {

EnergyDensityQuantile energy_density_quantile(const Eigen::VectorXd& W, const Eigen::VectorXd& areas,
                                              const std::vector<bool>& material, double fraction) {
  if (areas.size() != W.size() || Eigen::Index(material.size()) != W.size())
    throw InputError(fmt::format("energy density quantile: {} energy densities, {} areas, {} material flags",
                                 W.size(), areas.size(), material.size()));
  if (!(fraction >= 0) || !(fraction < 1))
    throw InputError(fmt::format("energy density quantile: area fraction {} out of range [0, 1)", fraction));
  std::vector<int> faces;
  for (int f = 0; f < int(W.size()); ++f)
    if (material[size_t(f)]) faces.push_back(f);
  if (faces.empty()) throw InputError("energy density quantile: no face of material");
  // Highest W first; ties by index, so the result does not depend on the sort.
  std::sort(faces.begin(), faces.end(), [&](int a, int b) { return W[a] != W[b] ? W[a] > W[b] : a < b; });
  EnergyDensityQuantile q;
  for (int f : faces) q.material_area += areas[f];
  const double budget = fraction * q.material_area;
  // Faces are left out from the top while their area fits the budget; a run of equal W goes
  // whole or not at all (W > W_q must hold for every face left out).
  size_t k = 0;
  double area = 0;
  while (k < faces.size()) {
    size_t end = k;
    double run = 0;
    while (end < faces.size() && W[faces[end]] == W[faces[k]]) run += areas[faces[end++]];
    if (end == faces.size() || area + run > budget) break;
    area += run;
    k = end;
  }
  q.value = W[faces[k]];
  q.faces_above = int(k);
  q.area_above = area;
  return q;
}

}  // namespace cutwork::solvers

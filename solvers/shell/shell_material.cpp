#include "solvers/shell/shell_material.h"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "host/core/error.h"

namespace cutwork::solvers {

ShellStiffness shell_stiffness(const Material& m) {
  auto bad = [](const char* field, double value, const char* range) {
    throw InputError(fmt::format("material: {} = {} is not accepted ({})", field, value, range));
  };
  if (!std::isfinite(m.youngs_modulus) || m.youngs_modulus <= 0)
    bad("youngs_modulus", m.youngs_modulus, "a finite E > 0 in Pa");
  if (!std::isfinite(m.poisson_ratio) || m.poisson_ratio < 0 || m.poisson_ratio >= 0.5)
    bad("poisson_ratio", m.poisson_ratio, "0 <= nu < 0.5");
  if (!std::isfinite(m.thickness) || m.thickness <= 0)
    bad("thickness", m.thickness, "a finite h > 0 in m");
  if (!std::isfinite(m.density) || m.density < 0) bad("density", m.density, "a finite rho >= 0 in kg/m^3");

  const double E = m.youngs_modulus, nu = m.poisson_ratio, h = m.thickness;
  ShellStiffness s;
  s.mu = E * h / (2.0 * (1.0 + nu));
  s.lambda = E * h * nu / (1.0 - nu * nu);
  s.bending = E * h * h * h / (12.0 * (1.0 - nu * nu));
  s.areal_mass = m.density * h;
  return s;
}

}  // namespace cutwork::solvers

#include "solvers/conforming/richardson.h"

#include <algorithm>

namespace cutwork::solvers {

Richardson richardson_extrapolate(std::span<const double> values) {
  Richardson r;
  const size_t n = values.size();
  if (n == 0) return r;
  const double finest = values[n - 1];
  r.extrapolated = finest;
  if (n == 1) return r;
  const double d2 = finest - values[n - 2];
  if (n == 2) {
    r.extrapolated = finest + d2;  // first order assumed
    r.error_bar = std::abs(d2);
    return r;
  }
  const double d1 = values[n - 2] - values[n - 3];
  if (d1 * d2 > 0 && std::abs(d2) < std::abs(d1)) {
    r.asymptotic = true;
    r.order = std::log2(d1 / d2);
    r.extrapolated = finest + d2 / (std::exp2(r.order) - 1);
    r.error_bar = std::abs(r.extrapolated - finest);
    return r;
  }
  r.error_bar = std::max(std::abs(d1), std::abs(d2));
  return r;
}

}  // namespace cutwork::solvers

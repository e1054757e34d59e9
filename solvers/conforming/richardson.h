#pragma once
/// Richardson extrapolation of a quantity computed on meshes of edge length h, h/2, h/4, … (the
/// conforming verification's levels, the discretisation estimate's refinements).
///
/// With the last three values Q₁, Q₂, Q₃ and their differences d₁ = Q₂ − Q₁, d₂ = Q₃ − Q₂:
///  - of one sign and shrinking (|d₂| < |d₁|): the asymptotic range; observed order
///    p = log₂(d₁/d₂), Q∞ = Q₃ + d₂/(2^p − 1), error bar |Q∞ − Q₃|;
///  - otherwise (a sign change, or growing differences): no asymptotic range is seen; Q∞ = Q₃ and
///    the error bar is the larger difference — the values have not settled.
/// With two values, p = 1 is assumed (the slowest a conforming discretisation converges, e.g. at
/// re-entrant clamped corners): Q∞ = 2Q₂ − Q₁, error bar |d|. With one, nothing is known.
#include <cmath>
#include <span>

namespace cutwork::solvers {

struct Richardson {
  double extrapolated = NAN;  ///< Q∞ (the finest value when no extrapolation is possible)
  double order = NAN;         ///< p, when three values converge monotonically
  double error_bar = NAN;     ///< |Q∞ − Q_finest| (see above); NaN with one value
  bool asymptotic = false;    ///< three values of one sign, shrinking
};

/// `values`: coarsest first, each level at half the previous edge length.
Richardson richardson_extrapolate(std::span<const double> values);

}  // namespace cutwork::solvers

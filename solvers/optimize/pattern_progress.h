#pragma once
/// What the optimisers tell a progress display (host/cli/cli_common.h's ProgressLine) while a
/// phase runs.
#include <cmath>
#include <string>

namespace cutwork::solvers {

/// Live progress of a phase (a callback may show it; returning false stops the optimiser).
struct PatternProgress {
  std::string stage;       ///< "initialise", "optimise"
  int round = 0;           ///< match/optimise round (DET), or optimiser run
  int iteration = 0;       ///< accepted L-BFGS-B iterations so far (over rounds)
  double objective = 0;    ///< the objective of the current iterate: P, or J = w_S S + w_P P
  int stencils = 0;
  double seconds = 0;      ///< since the phase started
  double gradient_norm = 0;///< ‖∇‖₂ of the objective at the last evaluation (optimiser units)
  double structure = std::nan("");  ///< S (joint phase only)
  double W_max = std::nan("");      ///< J/m² (joint phase only)
};

}  // namespace cutwork::solvers

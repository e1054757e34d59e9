#pragma once
/// Where a phase of a design is, between two optimiser iterations: what checkpoints save
/// (DesignOptions::checkpoint, host/cli/checkpoint.h) and what a resumed phase starts from.
/// Plain data: the solvers know nothing of files or JSON.
#include <functional>
#include <string>
#include <vector>

#include "host/pattern/random.h"
#include "solvers/optimize/joint_optimizer.h"

namespace cutwork::solvers {

/// A phase's position in its sequence of optimize_pattern calls.
struct PhaseCursor {
  int outer = 0;  ///< the structural phase's adaptive β updates done (0 in the pattern phase)
  int fill = 0;   ///< 0: the optimisation of the layout; j ≥ 1: the one after the j-th hole filling
};

/// A phase's state at a boundary, by reference to the live objects (valid during the call).
struct PhaseSnapshot {
  const PhaseCursor& cursor;
  const PatternRng& rng;                 ///< the hole filling's generator
  const JointOptimizerState& optimizer;  ///< the optimize_pattern call in progress
  const LbfgsbState* lbfgsb;             ///< inside a round; null at a round's start
};

/// A phase's state read back from a checkpoint: the phase continues from it.
struct PhaseResume {
  PhaseCursor cursor;
  std::string rng;                       ///< PatternRng::state()
  JointOptimizerState optimizer;         ///< with `lbfgsb` inside a round
};

/// A phase's checkpoint hooks: `save` sees the phase's result so far (`Result`'s figures as
/// they are at that moment) and its state at every optimiser boundary; with `resume` and
/// `resume_result` (both from a `save`) the phase continues from there instead of starting.
template <typename Result>
struct PhaseCheckpoints {
  std::function<void(const Result& partial, const PhaseSnapshot& state)> save;
  const Result* resume_result = nullptr;
  const PhaseResume* resume = nullptr;
};

}  // namespace cutwork::solvers

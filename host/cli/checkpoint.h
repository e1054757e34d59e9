#pragma once
/// Checkpoints of `cutwork design` (issue 15): the pattern phase's complete result, written
/// atomically into the output folder as `.cutwork-checkpoint.json` as soon as the phase ends, so
/// that `--resume` after a kill, an out-of-memory or a reboot continues with the structural phase
/// and reaches the same design as an uninterrupted run, bit for bit (doubles are written with 17
/// significant digits and read back exactly; the structural phase is deterministic on the CPU).
///
/// Granularity: phase boundaries. A run killed during the pattern phase starts again; one killed
/// during the structural phase loses that phase's work only. (Checkpoints inside a phase, every N
/// seconds, would need the optimiser's L-BFGS-B memory and the rounds' state: not done.)
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "solvers/optimize/pattern_phase.h"

namespace cutwork::cli {

/// The checkpoint file of output folder `dir`.
std::filesystem::path checkpoint_path(const std::filesystem::path& dir);

/// What a checkpoint must match to be resumed: the scene (its complete JSON) and the options that
/// change the design.
nlohmann::json checkpoint_fingerprint(const Scene& scene, int iterations);

/// Writes the pattern phase's result atomically.
void write_pattern_checkpoint(const std::filesystem::path& dir, const nlohmann::json& fingerprint,
                              const PatternPhaseResult& pattern);

/// The pattern phase's result of `dir`'s checkpoint; nullopt when there is none. Throws
/// InputError naming the file when it is unreadable or was made for another scene or options.
std::optional<PatternPhaseResult> read_pattern_checkpoint(const std::filesystem::path& dir,
                                                          const nlohmann::json& fingerprint);

}  // namespace cutwork::cli

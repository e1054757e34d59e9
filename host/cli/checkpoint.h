#pragma once
/// Checkpoints of `cutwork design` (issue 15): the design's complete state, written atomically
/// into the output folder as `.cutwork-checkpoint.json`, so that `--resume` after a kill, an
/// out-of-memory or a reboot continues where the run was and reaches the same design as an
/// uninterrupted run, bit for bit on the CPU.
///
/// When: at optimiser iteration boundaries — inside the pattern and the structural phase, the
/// first boundary after `--checkpoint-every` seconds (default 60; 0: phase ends only) — and at
/// each phase end; SIGINT/SIGTERM write one at the next boundary and end the run. A kill loses
/// at most the work since the last checkpoint (about the interval plus one iteration).
///
/// What (solvers/optimize/design_pipeline.h, DesignSnapshot): the stage (inside or at the end
/// of a phase), each phase's result so far, where the phase is in its sequence of optimisations
/// (adaptive β updates, hole filling), the hole filling's random generator, the optimize_pattern
/// call's state (the layout at the round's start, its bounds, the iteration budget spent, the
/// stall rule) with the L-BFGS-B state inside a round (iterate, gradient, direction, the
/// correction pairs since the run began, the decrease test's history, the best point and its
/// counts), and in the structural phase the shell's stencils and last equilibrium (its warm
/// start). DET matchings are recomputed from the layout; the shell's factor from the equilibrium.
///
/// Format: one JSON object; scalars as JSON numbers with 17 significant digits (exact), vectors
/// as base64 of their little-endian IEEE doubles (exact and compact), with an FNV-1a digest of
/// the content: a damaged file, or one made for another scene or other options, is refused with
/// one line naming it (exit 2).
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "solvers/optimize/design_pipeline.h"

namespace cutwork::cli {

/// The checkpoint file of output folder `dir`.
std::filesystem::path checkpoint_path(const std::filesystem::path& dir);

/// What a checkpoint must match to be resumed: the scene (its complete JSON) and the options that
/// change the design.
nlohmann::json checkpoint_fingerprint(const Scene& scene, int iterations);

/// Writes the design's state atomically; returns the file's size in bytes.
std::uintmax_t write_checkpoint(const std::filesystem::path& dir, const nlohmann::json& fingerprint,
                                const solvers::DesignSnapshot& state);

/// The state of `dir`'s checkpoint; nullopt when there is none. Throws InputError naming the file
/// when it is unreadable, damaged, or was made for another scene or other options.
std::optional<solvers::DesignResume> read_checkpoint(const std::filesystem::path& dir,
                                                     const nlohmann::json& fingerprint);

/// The stage's name in messages ("the pattern phase", "the end of the structural phase", …).
const char* stage_description(solvers::DesignStage stage);

}  // namespace cutwork::cli

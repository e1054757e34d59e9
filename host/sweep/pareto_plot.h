#pragma once
/// pareto.png of a sweep: two panels, material left against W_max and against compliance, every
/// successful variant as a grey dot and the non-dominated ones in colour, joined by the front's
/// staircase and labelled with their ids. Drawn with cairo; axes labelled with units.
#include <filesystem>
#include <vector>

#include "host/sweep/sweep_results.h"

namespace cutwork {

/// Writes the plot as a PNG (atomic). `title` heads it (the sweep's name). Throws InputError
/// naming `path` when it cannot be written.
void write_pareto_png(const std::filesystem::path& path, const std::string& title,
                      const std::vector<VariantResult>& results, const ParetoFronts& fronts);

}  // namespace cutwork

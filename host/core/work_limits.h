#pragma once
/// Limits on the work one request may ask for, checked up front against estimates (see
/// host/scene/work_estimate.h) so that an absurd request is refused with one line naming the
/// setting and the estimate, instead of running out of memory or time much later. Process-wide:
/// the command line sets them from --max-faces, --max-stencils and --max-factor-gb before it reads
/// anything.
namespace cutwork {

struct WorkLimits {
  int max_faces = 4'000'000;     ///< faces of a base or simulation mesh (generated or read)
  int max_stencils = 100'000;    ///< stencils the pattern phase would place (estimated)
  double max_factor_gb = 32;     ///< memory of the stiffness matrix's Cholesky factor (GB, from the analysis)
};

/// The limits in force (defaults above until changed).
WorkLimits& work_limits();

}  // namespace cutwork

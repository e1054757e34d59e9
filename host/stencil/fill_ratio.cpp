#include "host/stencil/fill_ratio.h"

#include <tbb/parallel_for.h>

#include <cmath>

#include "host/core/error.h"

namespace cutwork {

static_assert(sizeof(int) == sizeof(int32_t), "faces are passed to the kernels as int32");

const char* to_string(FillBackend backend) {
  switch (backend) {
    case FillBackend::Reference: return "reference";
    case FillBackend::Tbb: return "tbb";
  }
  return "?";
}

FillRatioEvaluator::FillRatioEvaluator(const FaceBvh& surface, const FaceBvh& sim,
                                       const StencilLibrary& shapes, const TangentField* field,
                                       FillRatioOptions options)
    : m_surface(&surface),
      m_sim(&sim),
      m_shapes(&shapes),
      m_field(field),
      m_options(options),
      m_broad(sim, options.broad_phase) {
  if (surface.mesh() == nullptr || sim.mesh() == nullptr)
    throw InputError("fill ratios: the BVH has no mesh");
  if (shapes.size() == 0) throw InputError("fill ratios: no stencil shapes");
  if (!(options.min_fill > 0 && options.min_fill < 1))
    throw InputError("fill ratios: min_fill must lie in (0, 1)");
  if (m_field == nullptr) {
    m_own_field = std::make_unique<AxisTangentField>();
    m_field = m_own_field.get();
  }
  m_alpha = Eigen::VectorXd::Ones(sim.mesh()->num_faces());
}

FillRatioEvaluator::FillRatioEvaluator(const FaceBvh& surface, const StencilLibrary& shapes,
                                       FillRatioOptions options)
    : FillRatioEvaluator(surface, surface, shapes, nullptr, options) {}

FillRatioEvaluator::~FillRatioEvaluator() = default;

void FillRatioEvaluator::evaluate(std::span<const StencilParams> stencils) {
  const int n = int(stencils.size());
  for (int i = 0; i < n; ++i) {
    const StencilParams& p = stencils[size_t(i)];
    const std::string who = "stencil " + std::to_string(i) + ": ";
    if (!p.position.allFinite()) throw InputError(who + "position is not finite");
    if (!(std::isfinite(p.scale) && p.scale > 0))
      throw InputError(who + "scale must be finite and > 0 (got " + std::to_string(p.scale) + ")");
    if (!std::isfinite(p.angle)) throw InputError(who + "angle is not finite");
    if (p.type < 0 || p.type >= m_shapes->size())
      throw InputError(who + "type " + std::to_string(p.type) + " is not in [0, " +
                       std::to_string(m_shapes->size()) + ")");
  }
  m_num_stencils = n;
  m_frames.resize(size_t(n));
  m_clip_stencils.resize(size_t(n));
  m_centers.resize(size_t(n));
  m_scales.resize(size_t(n));
  const bool derivatives = m_options.derivatives;
  auto frame_of = [&](int i) {
    const StencilParams& p = stencils[size_t(i)];
    FrameJacobian jac;
    m_frames[size_t(i)] = compute_frame(*m_surface, *m_field, p.position, derivatives ? &jac : nullptr);
    m_clip_stencils[size_t(i)] = make_clip_stencil(m_frames[size_t(i)], jac, p.scale, p.angle, p.type);
    m_centers[size_t(i)] = m_frames[size_t(i)].origin;
    m_scales[size_t(i)] = p.scale;
  };
  if (m_options.backend == FillBackend::Reference) {
    for (int i = 0; i < n; ++i) frame_of(i);
  } else {
    tbb::parallel_for(0, n, frame_of);
  }

  m_requeried = m_broad.update(m_centers, m_scales);

  const SurfaceMesh& sim = *m_sim->mesh();
  const auto& pairs = m_broad.pairs();
  kernels::ClipInputs in;
  in.vertices = std::span<const double>(sim.vertices().data(), size_t(sim.vertices().size()));
  in.faces = std::span<const int32_t>(sim.faces().data(), size_t(sim.faces().size()));
  in.shapes = m_shapes->clip_shapes();
  in.polygons = m_shapes->packed_polygons();
  in.stencils = m_clip_stencils;
  in.pairs = pairs;
  kernels::ClipOptions clip_options;
  clip_options.derivatives = derivatives ? 1 : 0;
  m_overlaps.resize(pairs.size());
  kernels::FillParams fill_params;
  fill_params.min_fill = m_options.min_fill;
  fill_params.derivatives = derivatives ? 1 : 0;
  m_alpha.resize(sim.num_faces());
  m_d_alpha.resize(derivatives ? 5 * pairs.size() : 0);
  const kernels::FillInputs fill_in{m_overlaps, m_broad.face_offsets()};
  const kernels::FillOutputs fill_out{std::span<double>(m_alpha.data(), size_t(m_alpha.size())),
                                      m_d_alpha};
  if (m_options.backend == FillBackend::Reference) {
    kernels::clip_ref(in, clip_options, m_overlaps, m_workspace);
    kernels::fill_ref(fill_in, fill_params, fill_out);
  } else {
    kernels::clip_tbb(in, clip_options, m_overlaps, m_workspace);
    kernels::fill_tbb(fill_in, fill_params, fill_out);
  }
}

void FillRatioEvaluator::pullback(const Eigen::VectorXd& d_objective_d_alpha,
                                  Eigen::VectorXd& d_objective_d_params) const {
  if (!m_options.derivatives)
    throw InputError("fill ratios: derivatives were switched off for this evaluator");
  if (d_objective_d_alpha.size() != m_alpha.size())
    throw InputError("fill ratios: the gradient has " + std::to_string(d_objective_d_alpha.size()) +
                     " entries for " + std::to_string(m_alpha.size()) + " faces");
  d_objective_d_params.resize(5 * m_num_stencils);
  const kernels::FillPullbackInputs in{m_broad.pairs(), m_d_alpha, m_broad.stencil_pairs(),
                                       m_broad.stencil_offsets()};
  const std::span<const double> g(d_objective_d_alpha.data(), size_t(d_objective_d_alpha.size()));
  const std::span<double> out(d_objective_d_params.data(), size_t(d_objective_d_params.size()));
  if (m_options.backend == FillBackend::Reference)
    kernels::fill_pullback_ref(in, g, out);
  else
    kernels::fill_pullback_tbb(in, g, out);
}

Eigen::SparseMatrix<double, Eigen::RowMajor> FillRatioEvaluator::jacobian() const {
  std::vector<Eigen::Triplet<double>> entries;
  const auto& pairs = m_broad.pairs();
  for (size_t i = 0; i < pairs.size() && !m_d_alpha.empty(); ++i) {
    for (int k = 0; k < 5; ++k) {
      const double v = m_d_alpha[5 * i + size_t(k)];
      if (v != 0) entries.emplace_back(pairs[i].face, 5 * pairs[i].stencil + k, v);
    }
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> J(m_alpha.size(), 5 * m_num_stencils);
  J.setFromTriplets(entries.begin(), entries.end());
  return J;
}

}  // namespace cutwork

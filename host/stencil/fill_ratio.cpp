#include "host/stencil/fill_ratio.h"

#include <tbb/parallel_for.h>

#include <chrono>
#include <cmath>

#include "host/core/error.h"
#include "host/core/internal_error.h"
#include "host/vulkan/backend.h"

#if CUTWORK_WITH_VULKAN
#include "host/vulkan/clip_fill_vk.h"
#endif

namespace cutwork {

static_assert(sizeof(int) == sizeof(int32_t), "faces are passed to the kernels as int32");

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

const char* to_string(FillBackend backend) {
  switch (backend) {
    case FillBackend::Reference: return "reference";
    case FillBackend::Tbb: return "tbb";
    case FillBackend::Vulkan: return "vulkan";
  }
  return "?";
}

FillRatioOptions FillRatioOptions::for_backend(const ComputeBackend& backend) {
  FillRatioOptions o;
  if (backend.kind == ComputeBackend::Kind::Vulkan) {
    if (backend.context == nullptr)
      throw InternalError("fill ratios: the Vulkan compute backend has no context");
    o.backend = FillBackend::Vulkan;
    o.vulkan_context = backend.context;
  } else {
    o.backend = FillBackend::Tbb;
  }
  return o;
}

std::optional<double> FillRatioReport::device_ms() const {
  if (dispatches.empty()) return std::nullopt;
  double sum = 0;
  for (const Dispatch& d : dispatches) {
    if (!d.device_ms) return std::nullopt;
    sum += *d.device_ms;
  }
  return sum;
}

#if CUTWORK_WITH_VULKAN
/// One ClipFillVk for the evaluator's life: its buffers persist across evaluations, so each
/// one uploads only what changed.
struct FillRatioEvaluator::Device {
  explicit Device(std::shared_ptr<vulkan::Context> context) : clip_fill(std::move(context)) {}
  vulkan::ClipFillVk clip_fill;
  /// The device still holds the pairs and dα/dp of the last evaluate() (pullback_last may run).
  bool holds_last_evaluation = false;

  /// Copies the device's report of its last call into `report`.
  void copy_report(FillRatioReport& report) const {
    const vulkan::BatchReport& b = clip_fill.last_report();
    report.dispatches.clear();
    for (const auto& d : b.dispatches) report.dispatches.push_back({d.kernel, d.items, d.device_ms});
    report.uploads = b.uploads;
    report.upload_bytes = b.upload_bytes;
    report.download_bytes = b.download_bytes;
  }
};
#else
struct FillRatioEvaluator::Device {};
#endif

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
    throw InternalError("fill ratios: the BVH has no mesh");
  if (shapes.size() == 0) throw InputError("fill ratios: no stencil shapes");
  if (!(options.min_fill > 0 && options.min_fill < 1))
    throw InputError("fill ratios: min_fill must lie in (0, 1)");
  if (options.backend == FillBackend::Vulkan) {
#if CUTWORK_WITH_VULKAN
    if (options.vulkan_context == nullptr)
      throw InternalError(
          "fill ratios: the Vulkan backend needs FillRatioOptions::vulkan_context (see "
          "select_compute_backend and FillRatioOptions::for_backend)");
    m_device = std::make_unique<Device>(options.vulkan_context);
#else
    throw DeviceError(
        "fill ratios: this cutwork was built without Vulkan (CUTWORK_WITH_VULKAN=OFF); use the "
        "TBB backend (--device cpu)");
#endif
  }
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
  const Clock::time_point start = Clock::now();
  m_report = FillRatioReport{};
  m_report.call = "evaluate";
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
  m_report.frames_ms = ms_since(start);

  const Clock::time_point broad_start = Clock::now();
  m_requeried = m_broad.update(m_centers, m_scales);
  m_report.broad_phase_ms = ms_since(broad_start);

  const Clock::time_point kernels_start = Clock::now();
  const kernels::ClipInputs in = clip_inputs();
  m_alpha.resize(m_sim->mesh()->num_faces());
  m_d_alpha.resize(derivatives ? 5 * in.pairs.size() : 0);
  if (m_device) {
    evaluate_on_device(in);
  } else {
    kernels::ClipOptions clip_options;
    clip_options.derivatives = derivatives ? 1 : 0;
    m_overlaps.resize(in.pairs.size());
    m_overlaps_current = true;
    kernels::FillParams fill_params;
    fill_params.min_fill = m_options.min_fill;
    fill_params.derivatives = derivatives ? 1 : 0;
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
  m_report.kernels_ms = ms_since(kernels_start);
  m_report.total_ms = ms_since(start);
}

kernels::ClipInputs FillRatioEvaluator::clip_inputs() const {
  const SurfaceMesh& sim = *m_sim->mesh();
  kernels::ClipInputs in;
  in.vertices = std::span<const double>(sim.vertices().data(), size_t(sim.vertices().size()));
  in.faces = std::span<const int32_t>(sim.faces().data(), size_t(sim.faces().size()));
  in.shapes = m_shapes->clip_shapes();
  in.polygons = m_shapes->packed_polygons();
  in.stencils = m_clip_stencils;
  in.pairs = m_broad.pairs();
  return in;
}

#if CUTWORK_WITH_VULKAN

void FillRatioEvaluator::evaluate_on_device(const kernels::ClipInputs& in) {
  const bool derivatives = m_options.derivatives;
  kernels::ClipOptions clip_options;
  clip_options.derivatives = derivatives ? 1 : 0;
  kernels::FillParams fill_params;
  fill_params.min_fill = m_options.min_fill;
  fill_params.derivatives = derivatives ? 1 : 0;
  const bool download = m_options.download_overlaps;
  m_overlaps.resize(download ? in.pairs.size() : 0);
  m_device->holds_last_evaluation = false;  // until the submission below succeeds
  m_overlaps_current = false;
  m_device->clip_fill.evaluate(
      in, clip_options, m_broad.face_offsets(), fill_params,
      download ? std::span<kernels::ClipResult>(m_overlaps) : std::span<kernels::ClipResult>(),
      {std::span<double>(m_alpha.data(), size_t(m_alpha.size())), m_d_alpha});
  m_device->holds_last_evaluation = derivatives;
  m_overlaps_current = download;
  m_device->copy_report(m_report);
}

const std::vector<kernels::ClipResult>& FillRatioEvaluator::overlaps() const {
  if (m_overlaps_current) return m_overlaps;
  // The clip results of the last evaluation stayed on the device: the same kernel on the same
  // (unchanged, so not re-uploaded) inputs computes the same bits again.
  const Clock::time_point start = Clock::now();
  const kernels::ClipInputs in = clip_inputs();
  kernels::ClipOptions clip_options;
  clip_options.derivatives = m_options.derivatives ? 1 : 0;
  m_overlaps.resize(in.pairs.size());
  m_device->holds_last_evaluation = false;  // clip() overwrites the device's last evaluation
  m_device->clip_fill.clip(in, clip_options, m_overlaps);
  m_overlaps_current = true;
  m_report = FillRatioReport{};
  m_report.call = "overlaps";
  m_device->copy_report(m_report);
  m_report.kernels_ms = m_report.total_ms = ms_since(start);
  return m_overlaps;
}

#else

void FillRatioEvaluator::evaluate_on_device(const kernels::ClipInputs&) {
  throw DeviceError("fill ratios: this cutwork was built without Vulkan");
}

const std::vector<kernels::ClipResult>& FillRatioEvaluator::overlaps() const { return m_overlaps; }

#endif

void FillRatioEvaluator::pullback(const Eigen::VectorXd& d_objective_d_alpha,
                                  Eigen::VectorXd& d_objective_d_params) const {
  if (!m_options.derivatives)
    throw InternalError("fill ratios: derivatives were switched off for this evaluator");
  if (d_objective_d_alpha.size() != m_alpha.size())
    throw InternalError("fill ratios: the gradient has " + std::to_string(d_objective_d_alpha.size()) +
                     " entries for " + std::to_string(m_alpha.size()) + " faces");
  const Clock::time_point start = Clock::now();
  m_report = FillRatioReport{};
  m_report.call = "pullback";
  d_objective_d_params.resize(5 * m_num_stencils);
  const kernels::FillPullbackInputs in{m_broad.pairs(), m_d_alpha, m_broad.stencil_pairs(),
                                       m_broad.stencil_offsets()};
  const std::span<const double> g(d_objective_d_alpha.data(), size_t(d_objective_d_alpha.size()));
  const std::span<double> out(d_objective_d_params.data(), size_t(d_objective_d_params.size()));
  if (m_options.backend == FillBackend::Reference) {
    kernels::fill_pullback_ref(in, g, out);
  } else if (!m_device || in.pairs.empty()) {
    kernels::fill_pullback_tbb(in, g, out);  // (no pairs: zeros, nothing worth a submission)
  } else {
#if CUTWORK_WITH_VULKAN
    if (m_device->holds_last_evaluation)
      m_device->clip_fill.pullback_last(in.stencil_pairs, in.stencil_offsets, g, out);
    else  // overlaps() re-ran the clip since: upload the pairs and dα/dp again
      m_device->clip_fill.pullback(in, g, out);
    m_device->copy_report(m_report);
#endif
  }
  m_report.kernels_ms = m_report.total_ms = ms_since(start);
}

Eigen::MatrixXd FillRatioEvaluator::covered_by_shape(std::span<const double> weight) const {
  if (!weight.empty() && weight.size() != size_t(m_num_stencils))
    throw InternalError("fill ratios: " + std::to_string(weight.size()) + " weights for " +
                        std::to_string(m_num_stencils) + " stencils");
  const std::vector<kernels::ClipResult>& results = overlaps();
  const auto& pairs = m_broad.pairs();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m_alpha.size(), m_shapes->size());
  for (size_t i = 0; i < pairs.size(); ++i) {
    const int s = pairs[i].stencil;
    h(pairs[i].face, m_clip_stencils[size_t(s)].shape) += weight.empty() ? results[i].fraction
                                                                         : weight[size_t(s)] * results[i].fraction;
  }
  return h;
}

void FillRatioEvaluator::pullback_by_shape(const Eigen::MatrixXd& d_objective_d_covered,
                                           Eigen::VectorXd& d_objective_d_params, std::span<const double> weight,
                                           std::span<const double> d_weight_d_scale) const {
  if (!m_options.derivatives)
    throw InternalError("fill ratios: derivatives were switched off for this evaluator");
  if (d_objective_d_covered.rows() != m_alpha.size() || d_objective_d_covered.cols() != m_shapes->size())
    throw InternalError("fill ratios: the gradient by shape is " + std::to_string(d_objective_d_covered.rows()) + "×" +
                        std::to_string(d_objective_d_covered.cols()) + " for " + std::to_string(m_alpha.size()) +
                        " faces and " + std::to_string(m_shapes->size()) + " shapes");
  if ((!weight.empty() && weight.size() != size_t(m_num_stencils)) ||
      (!d_weight_d_scale.empty() && d_weight_d_scale.size() != weight.size()))
    throw InternalError("fill ratios: the weights do not match the stencils");
  const std::vector<kernels::ClipResult>& results = overlaps();
  const auto& pairs = m_broad.pairs();
  d_objective_d_params.setZero(5 * m_num_stencils);
  for (size_t i = 0; i < pairs.size(); ++i) {
    const int s = pairs[i].stencil;
    const double g = d_objective_d_covered(pairs[i].face, m_clip_stencils[size_t(s)].shape);
    if (g == 0) continue;
    const double w = weight.empty() ? 1.0 : weight[size_t(s)];
    for (int k = 0; k < 5; ++k) d_objective_d_params[5 * s + k] += g * w * results[i].d_fraction[k];
    if (!d_weight_d_scale.empty()) d_objective_d_params[5 * s + 3] += g * results[i].fraction * d_weight_d_scale[size_t(s)];
  }
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

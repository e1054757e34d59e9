#include "host/vulkan/clip_fill_vk.h"

#include <stdexcept>
#include <string>

#include "host/vulkan/context.h"
#include "kernels/clip/clip_vk.h"
#include "kernels/fill/fill_vk.h"

namespace cutwork::vulkan {
namespace {

[[noreturn]] void bad(const std::string& what) {
  throw std::invalid_argument("ClipFillVk: " + what);
}

uint32_t count32(size_t n, const char* what) {
  if (n > size_t(INT32_MAX)) bad(std::string(what) + ": more than 2^31 entries");
  return uint32_t(n);
}

// The device reads wherever these indices point; the CPU twins take them on trust (their
// callers build them), but on a GPU a stray index is a device fault, not a wrong number.
void validate_clip_inputs(const kernels::ClipInputs& in) {
  if (in.vertices.size() % 3 != 0) bad("vertices is not #V×3");
  if (in.faces.size() % 3 != 0) bad("faces is not #F×3");
  if (in.polygons.size() % 2 != 0) bad("polygons is not 2×#vertices");
  const int64_t nv = int64_t(in.vertices.size() / 3), nf = int64_t(in.faces.size() / 3);
  const int64_t np = int64_t(in.polygons.size() / 2), nk = int64_t(in.shapes.size());
  const int64_t ns = int64_t(in.stencils.size());
  for (int32_t v : in.faces)
    if (v < 0 || v >= nv) bad("face corner " + std::to_string(v) + " out of range");
  for (const kernels::ClipShape& s : in.shapes)
    if (s.polygon_offset < 0 || s.polygon_count < 3 ||
        int64_t(s.polygon_offset) + s.polygon_count > np)
      bad("shape polygon range out of range");
  for (const kernels::ClipStencil& s : in.stencils)
    if (s.shape < 0 || s.shape >= nk)
      bad("stencil shape " + std::to_string(s.shape) + " out of range");
  for (const kernels::ClipPair& p : in.pairs)
    if (p.stencil < 0 || p.stencil >= ns || p.face < 0 || p.face >= nf)
      bad("pair (" + std::to_string(p.stencil) + ", " + std::to_string(p.face) + ") out of range");
  count32(in.pairs.size(), "pairs");
  count32(in.faces.size(), "faces");
}

void validate_offsets(std::span<const int32_t> offsets, size_t items, const char* what) {
  if (offsets.empty()) bad(std::string(what) + " is empty (needs #+1 entries)");
  int32_t prev = 0;
  for (int32_t o : offsets) {
    if (o < prev) bad(std::string(what) + " is not non-decreasing from 0");
    prev = o;
  }
  if (size_t(prev) > items) bad(std::string(what) + " points past the end of its list");
}

}  // namespace

ClipFillVk::ClipFillVk(std::shared_ptr<Context> context, uint32_t workgroup_size)
    : m_ctx(std::move(context)),
      m_workgroup_size(workgroup_size),
      m_vertices(*m_ctx, "vertices"),
      m_faces(*m_ctx, "faces"),
      m_shapes(*m_ctx, "shapes"),
      m_polygons(*m_ctx, "polygons"),
      m_stencils(*m_ctx, "stencils"),
      m_pairs(*m_ctx, "pairs"),
      m_results(*m_ctx, "clip results"),
      m_face_offsets(*m_ctx, "face_offsets"),
      m_alpha(*m_ctx, "alpha"),
      m_d_alpha(*m_ctx, "d_alpha"),
      m_stencil_pairs(*m_ctx, "stencil_pairs"),
      m_stencil_offsets(*m_ctx, "stencil_offsets"),
      m_d_objective_d_alpha(*m_ctx, "d_objective_d_alpha"),
      m_d_objective_d_params(*m_ctx, "d_objective_d_params") {}

ClipFillVk::~ClipFillVk() = default;

ClipFillVk::Stage& ClipFillVk::clip_stage() {
  if (!m_clip.pipeline) {
    m_clip.pipeline =
        std::make_unique<ComputePipeline>(*m_ctx, kernels::clip_gpu_kernel(), m_workgroup_size);
    m_clip.set = std::make_unique<DescriptorSet>(
        *m_ctx, *m_clip.pipeline,
        std::vector<StorageBuffer*>{&m_vertices, &m_faces, &m_shapes, &m_polygons, &m_stencils,
                                    &m_pairs, &m_results});
  }
  return m_clip;
}

ClipFillVk::Stage& ClipFillVk::fill_stage() {
  if (!m_fill.pipeline) {
    m_fill.pipeline =
        std::make_unique<ComputePipeline>(*m_ctx, kernels::fill_gpu_kernel(), m_workgroup_size);
    m_fill.set = std::make_unique<DescriptorSet>(
        *m_ctx, *m_fill.pipeline,
        std::vector<StorageBuffer*>{&m_results, &m_face_offsets, &m_alpha, &m_d_alpha});
  }
  return m_fill;
}

ClipFillVk::Stage& ClipFillVk::pullback_stage() {
  if (!m_pullback.pipeline) {
    m_pullback.pipeline = std::make_unique<ComputePipeline>(
        *m_ctx, kernels::fill_pullback_gpu_kernel(), m_workgroup_size);
    m_pullback.set = std::make_unique<DescriptorSet>(
        *m_ctx, *m_pullback.pipeline,
        std::vector<StorageBuffer*>{&m_pairs, &m_d_alpha, &m_stencil_pairs, &m_stencil_offsets,
                                    &m_d_objective_d_alpha, &m_d_objective_d_params});
  }
  return m_pullback;
}

void ClipFillVk::upload_clip_inputs(CommandBatch& batch, const kernels::ClipInputs& in) {
  batch.upload(m_vertices, in.vertices);
  batch.upload(m_faces, in.faces);
  batch.upload(m_shapes, in.shapes);
  batch.upload(m_polygons, in.polygons);
  batch.upload(m_stencils, in.stencils);
  batch.upload(m_pairs, in.pairs);
}

void ClipFillVk::evaluate(const kernels::ClipInputs& in, const kernels::ClipOptions& clip_options,
                          std::span<const int32_t> face_offsets,
                          const kernels::FillParams& fill_params,
                          std::span<kernels::ClipResult> results, const kernels::FillOutputs& out) {
  validate_clip_inputs(in);
  const size_t pairs = in.pairs.size();
  validate_offsets(face_offsets, pairs, "face_offsets");
  const uint32_t faces = count32(face_offsets.size() - 1, "face_offsets");
  const bool derivatives = fill_params.derivatives != 0;
  if (!results.empty() && results.size() != pairs) bad("results must be empty or #P");
  if (out.alpha.size() != faces) bad("alpha must have #F entries");
  if (derivatives && !out.d_alpha.empty() && out.d_alpha.size() != 5 * pairs)
    bad("d_alpha must be empty or #P×5");

  Stage& clip = clip_stage();
  Stage& fill = fill_stage();
  CommandBatch batch(*m_ctx);
  upload_clip_inputs(batch, in);
  batch.upload(m_face_offsets, face_offsets);
  batch.allocate(m_results, pairs * sizeof(kernels::ClipResult));
  batch.allocate(m_alpha, size_t(faces) * sizeof(double));
  if (derivatives) batch.allocate(m_d_alpha, 5 * pairs * sizeof(double));
  batch.dispatch(*clip.pipeline, *clip.set, kernels::ClipPushVk{{}, clip_options}, uint32_t(pairs));
  batch.dispatch(*fill.pipeline, *fill.set, kernels::FillPushVk{{}, fill_params}, faces);
  if (!results.empty()) batch.download(m_results, results);
  batch.download(m_alpha, out.alpha);
  if (derivatives && !out.d_alpha.empty()) batch.download(m_d_alpha, out.d_alpha);
  m_report = batch.submit();
  m_last_pairs = pairs;
  m_last_derivatives = derivatives;
}

void ClipFillVk::clip(const kernels::ClipInputs& in, const kernels::ClipOptions& options,
                      std::span<kernels::ClipResult> results) {
  validate_clip_inputs(in);
  if (results.size() != in.pairs.size()) bad("results must have #P entries");
  Stage& clip = clip_stage();
  CommandBatch batch(*m_ctx);
  upload_clip_inputs(batch, in);
  batch.allocate(m_results, results.size() * sizeof(kernels::ClipResult));
  batch.dispatch(*clip.pipeline, *clip.set, kernels::ClipPushVk{{}, options},
                 uint32_t(results.size()));
  batch.download(m_results, results);
  m_report = batch.submit();
  m_last_pairs = 0;  // the device no longer holds a complete evaluate()
  m_last_derivatives = false;
}

void ClipFillVk::fill(const kernels::FillInputs& in, const kernels::FillParams& params,
                      const kernels::FillOutputs& out) {
  validate_offsets(in.face_offsets, in.clip.size(), "face_offsets");
  const uint32_t faces = count32(in.face_offsets.size() - 1, "face_offsets");
  const bool derivatives = params.derivatives != 0;
  if (out.alpha.size() != faces) bad("alpha must have #F entries");
  if (derivatives && out.d_alpha.size() != 5 * in.clip.size())
    bad("d_alpha must have #P×5 entries");
  Stage& fill = fill_stage();
  CommandBatch batch(*m_ctx);
  batch.upload(m_results, in.clip);
  batch.upload(m_face_offsets, in.face_offsets);
  batch.allocate(m_alpha, size_t(faces) * sizeof(double));
  if (derivatives) batch.allocate(m_d_alpha, out.d_alpha.size() * sizeof(double));
  batch.dispatch(*fill.pipeline, *fill.set, kernels::FillPushVk{{}, params}, faces);
  batch.download(m_alpha, out.alpha);
  if (derivatives) batch.download(m_d_alpha, out.d_alpha);
  m_report = batch.submit();
  m_last_pairs = 0;
  m_last_derivatives = false;
}

void ClipFillVk::pullback(const kernels::FillPullbackInputs& in,
                          std::span<const double> d_objective_d_alpha,
                          std::span<double> d_objective_d_params) {
  const size_t pairs = in.pairs.size();
  if (in.d_alpha.size() != 5 * pairs) bad("d_alpha must have #P×5 entries");
  if (in.stencil_pairs.size() != pairs) bad("stencil_pairs must have #P entries");
  validate_offsets(in.stencil_offsets, pairs, "stencil_offsets");
  const uint32_t stencils = count32(in.stencil_offsets.size() - 1, "stencil_offsets");
  if (d_objective_d_params.size() != 5 * size_t(stencils)) bad("d_objective_d_params must be #S×5");
  for (int32_t i : in.stencil_pairs)
    if (i < 0 || size_t(i) >= pairs) bad("stencil_pairs entry out of range");
  for (const kernels::ClipPair& p : in.pairs)
    if (p.face < 0 || size_t(p.face) >= d_objective_d_alpha.size())
      bad("pair face out of range of dS/dα");
  Stage& stage = pullback_stage();
  CommandBatch batch(*m_ctx);
  m_last_pairs = 0;  // overwrites the pairs and dα/dp an evaluate() left on the device
  m_last_derivatives = false;
  batch.upload(m_pairs, in.pairs);
  batch.upload(m_d_alpha, in.d_alpha);
  batch.upload(m_stencil_pairs, in.stencil_pairs);
  batch.upload(m_stencil_offsets, in.stencil_offsets);
  batch.upload(m_d_objective_d_alpha, d_objective_d_alpha);
  batch.allocate(m_d_objective_d_params, d_objective_d_params.size() * sizeof(double));
  batch.dispatch(*stage.pipeline, *stage.set, kernels::FillPullbackPushVk{{}}, stencils);
  batch.download(m_d_objective_d_params, d_objective_d_params);
  m_report = batch.submit();
}

void ClipFillVk::pullback_last(std::span<const int32_t> stencil_pairs,
                               std::span<const int32_t> stencil_offsets,
                               std::span<const double> d_objective_d_alpha,
                               std::span<double> d_objective_d_params) {
  if (!m_last_derivatives) bad("pullback_last needs a previous evaluate() with derivatives on");
  const size_t pairs = m_last_pairs;
  if (stencil_pairs.size() != pairs)
    bad("stencil_pairs must have #P entries of the last evaluate()");
  validate_offsets(stencil_offsets, pairs, "stencil_offsets");
  const uint32_t stencils = count32(stencil_offsets.size() - 1, "stencil_offsets");
  if (d_objective_d_params.size() != 5 * size_t(stencils)) bad("d_objective_d_params must be #S×5");
  if (d_objective_d_alpha.size() != m_alpha.size() / sizeof(double))
    bad("dS/dα must have #F entries");
  for (int32_t i : stencil_pairs)
    if (i < 0 || size_t(i) >= pairs) bad("stencil_pairs entry out of range");
  Stage& stage = pullback_stage();
  CommandBatch batch(*m_ctx);
  batch.upload(m_stencil_pairs, stencil_pairs);
  batch.upload(m_stencil_offsets, stencil_offsets);
  batch.upload(m_d_objective_d_alpha, d_objective_d_alpha);
  batch.allocate(m_d_objective_d_params, d_objective_d_params.size() * sizeof(double));
  batch.dispatch(*stage.pipeline, *stage.set, kernels::FillPullbackPushVk{{}}, stencils);
  batch.download(m_d_objective_d_params, d_objective_d_params);
  m_report = batch.submit();
}

}  // namespace cutwork::vulkan

// The Vulkan twin of the rasteriser: raster.comp's embedded SPIR-V and its runner.
#include "host/render/rasterizer_vk.h"

#include <cstddef>
#include <span>

#include <fmt/format.h>

#include "host/core/error.h"
#include "host/vulkan/context.h"
#include "raster_spv.h"  // generated at build time (third_party/cmake/CutworkSpirv.cmake)

namespace cutwork::render {

static_assert(offsetof(RasterViewVk, scale) == 120 && offsetof(RasterViewVk, sw) == 128 &&
              offsetof(RasterViewVk, background) == 144);
static_assert(sizeof(Rgb) == 3 * sizeof(double), "colours are uploaded as #F×3 doubles");
static_assert(kSupersample == 2, "raster.comp's kSupersample");

kernels::GpuKernel raster_gpu_kernel() {
  kernels::GpuKernel k;
  k.name = "raster";
  k.spirv = std::span<const uint32_t>(raster_spv);
  k.storage_buffers = kRasterBindingCount;
  k.push_constant_bytes = sizeof(RasterPushVk);
  k.default_workgroup_size = 64;
  k.needs_float64 = true;
  return k;
}

namespace {

RasterViewVk view_block(const Projection& p, int width, int height, uint32_t background, size_t faces) {
  RasterViewVk v{};
  for (int k = 0; k < 3; ++k) {
    v.centre[k] = p.centre[k];
    v.right[k] = p.right[k];
    v.up[k] = p.up[k];
    v.forward[k] = p.forward[k];
    v.light[k] = p.light[k];
  }
  v.scale = p.scale;
  v.sw = p.sw;
  v.sh = p.sh;
  v.width = width;
  v.height = height;
  v.background = background;
  v.face_count = uint32_t(faces);
  return v;
}

uint32_t count32(size_t n, const char* what) {
  if (n > size_t(INT32_MAX)) throw DeviceError(fmt::format("render on the device: more than 2^31 {}", what));
  return uint32_t(n);
}

}  // namespace

RasterizerVk::RasterizerVk(std::shared_ptr<vulkan::Context> context, uint32_t workgroup_size)
    : m_ctx(std::move(context)),
      m_workgroup_size(workgroup_size),
      m_view(*m_ctx, "render view"),
      m_vertices(*m_ctx, "render vertices"),
      m_faces(*m_ctx, "render faces"),
      m_colours(*m_ctx, "render colours"),
      m_shaded(*m_ctx, "render shaded"),
      m_depth(*m_ctx, "render depth"),
      m_winner(*m_ctx, "render winner"),
      m_pixels(*m_ctx, "render pixels") {}

RasterizerVk::~RasterizerVk() = default;

Image RasterizerVk::rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                              const ViewSetup& setup, int width, int height) {
  if (!m_pipeline) {
    m_pipeline = std::make_unique<vulkan::ComputePipeline>(*m_ctx, raster_gpu_kernel(), m_workgroup_size);
    m_set = std::make_unique<vulkan::DescriptorSet>(
        *m_ctx, *m_pipeline,
        std::vector<vulkan::StorageBuffer*>{&m_view, &m_vertices, &m_faces, &m_colours, &m_shaded, &m_depth,
                                            &m_winner, &m_pixels});
  }
  const Projection pr = projection_for(setup, width, height);
  const uint32_t nf = count32(size_t(faces.rows()), "faces");
  const uint32_t samples = count32(size_t(pr.sw) * size_t(pr.sh), "samples");
  const uint32_t pixels = uint32_t(size_t(width) * size_t(height));
  const RasterViewVk view = view_block(pr, width, height, pack(setup.background), size_t(nf));
  Image image{width, height, std::vector<uint32_t>(pixels)};

  vulkan::CommandBatch batch(*m_ctx);
  batch.upload(m_view, std::span<const RasterViewVk>(&view, 1));
  batch.upload(m_vertices, std::span<const double>(vertices.data(), size_t(vertices.size())));
  batch.upload(m_faces, std::span<const int32_t>(faces.data(), size_t(faces.size())));
  batch.upload(m_colours, std::span<const Rgb>(face_colours));
  batch.allocate(m_shaded, size_t(nf) * sizeof(uint32_t));
  batch.allocate(m_depth, size_t(samples) * sizeof(uint32_t));
  batch.allocate(m_winner, size_t(samples) * sizeof(uint32_t));
  batch.allocate(m_pixels, size_t(pixels) * sizeof(uint32_t));
  batch.dispatch(*m_pipeline, *m_set, RasterPushVk{{}, RasterPass::Clear}, samples);
  batch.dispatch(*m_pipeline, *m_set, RasterPushVk{{}, RasterPass::Depth}, nf);
  batch.dispatch(*m_pipeline, *m_set, RasterPushVk{{}, RasterPass::Winner}, nf);
  batch.dispatch(*m_pipeline, *m_set, RasterPushVk{{}, RasterPass::Resolve}, pixels);
  batch.download(m_pixels, std::span<uint32_t>(image.pixels));
  m_report = batch.submit();
  return image;
}

}  // namespace cutwork::render

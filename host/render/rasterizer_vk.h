#pragma once
/// The Vulkan twin of the rasteriser (rasterizer.h): raster.comp, a compute-shader rasteriser
/// run on the project's Vulkan context (host/vulkan), behind render::Rasterizer.
///
/// Why compute and not a graphics pipeline: the Context opens one compute queue (on a real GPU
/// often a dedicated one, which cannot draw), and the fixed-function rasteriser's coverage and
/// depth rules (top-left fill rule, depth precision and interpolation) differ from the CPU
/// twin's, so its pictures would match only approximately. raster.comp runs the CPU twin's
/// arithmetic in double and resolves visibility with 32-bit atomicMin on depth keys, then on face
/// indices — nearest wins, ties to the lower face — so on an IEEE double device (lavapipe) the
/// two twins give the same pixels; elsewhere double division and sqrt may differ by a few ULP,
/// which can flip a sample exactly on a triangle edge or change a channel by one level (the
/// parity contract in tests/host/render/rasterizer_vk_test.cpp).
///
/// One submission per picture panel: upload the view (152 B), the mesh and the face colours
/// (only the blocks that changed since the last call: the nine panels of a design share the
/// mesh), then clear → depth → winner → resolve, and download the image.
///
/// Load balance: one invocation per face walks that face's whole sample box. The simulation and
/// cut meshes have small triangles (a few to a few hundred samples each); a single triangle
/// filling an 8192-pixel panel would be one long invocation (splitting large faces' boxes over
/// several invocations is the next step if that ever matters).
#include <cstdint>
#include <memory>

#include "host/render/rasterizer.h"
#include "host/vulkan/buffer.h"
#include "host/vulkan/command_batch.h"
#include "host/vulkan/pipeline.h"
#include "kernels/common/gpu_kernel.h"

namespace cutwork::vulkan {
class Context;
}

namespace cutwork::render {

/// Storage-buffer bindings of raster.comp, set 0.
enum RasterBinding : uint32_t {
  kRasterView = 0,  ///< RasterViewVk
  kRasterVertices,  ///< #V×3 double
  kRasterFaces,     ///< #F×3 int32
  kRasterColours,   ///< #F×3 double (Rgb)
  kRasterShaded,    ///< #F uint32, the shaded face colours (written by the depth pass)
  kRasterDepth,     ///< sw×sh uint32 depth keys
  kRasterWinner,    ///< sw×sh uint32 winning faces
  kRasterPixels,    ///< width×height uint32 0xFFRRGGBB (written)
  kRasterBindingCount
};

/// raster.comp's view block (std430): the Projection, the sizes and the background.
struct RasterViewVk {
  double centre[3], right[3], up[3], forward[3], light[3];
  double scale;
  int32_t sw, sh, width, height;
  uint32_t background, face_count;
};
static_assert(sizeof(RasterViewVk) == 152);

/// raster.comp's passes (push-block field `pass`).
enum class RasterPass : uint32_t { Clear = 0, Depth = 1, Winner = 2, Resolve = 3 };

/// raster.comp's push block: {uint first; uint count; uint pass; uint pad;}.
struct RasterPushVk {
  kernels::DispatchRange range;
  RasterPass pass = RasterPass::Clear;
  uint32_t pad = 0;
};
static_assert(sizeof(RasterPushVk) == 16);

/// raster.comp as a GpuKernel (8 storage buffers, double precision).
kernels::GpuKernel raster_gpu_kernel();

class RasterizerVk {
 public:
  /// Builds nothing yet: the pipeline is made on the first rasterize().
  explicit RasterizerVk(std::shared_ptr<vulkan::Context> context, uint32_t workgroup_size = 0);
  ~RasterizerVk();
  RasterizerVk(const RasterizerVk&) = delete;
  RasterizerVk& operator=(const RasterizerVk&) = delete;

  /// render::rasterize's contract (inputs checked by the caller, Rasterizer::rasterize). Throws
  /// DeviceError when the device fails or a buffer exceeds its limits.
  Image rasterize(const RowMatX3d& vertices, const RowMatX3i& faces, const std::vector<Rgb>& face_colours,
                  const ViewSetup& setup, int width, int height);

  /// The last call's transfers and per-pass device times.
  const vulkan::BatchReport& last_report() const { return m_report; }
  const vulkan::Context& context() const { return *m_ctx; }

 private:
  std::shared_ptr<vulkan::Context> m_ctx;
  uint32_t m_workgroup_size;
  vulkan::StorageBuffer m_view, m_vertices, m_faces, m_colours, m_shaded, m_depth, m_winner, m_pixels;
  std::unique_ptr<vulkan::ComputePipeline> m_pipeline;
  std::unique_ptr<vulkan::DescriptorSet> m_set;
  vulkan::BatchReport m_report;
};

}  // namespace cutwork::render

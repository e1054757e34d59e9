// host/vulkan against a CPU twin, on whatever device the context chooses (lavapipe in CI), with
// the validation layer on and zero messages required (VulkanTest's TearDown).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <random>
#include <span>
#include <sstream>
#include <vector>

#include "host/core/error.h"
#include "host/vulkan/backend.h"
#include "host/vulkan/buffer.h"
#include "host/vulkan/command_batch.h"
#include "host/vulkan/context.h"
#include "host/vulkan/pipeline.h"
#include "host/vulkan/vk_check.h"
#include "kernels/common/gpu_kernel.h"
#include "segmented_sum_selftest_spv.h"
#include "tests/host/vulkan/vk_test_support.h"

namespace cutwork::test {
namespace {

using vulkan::BatchReport;
using vulkan::CommandBatch;
using vulkan::ComputePipeline;
using vulkan::Context;
using vulkan::ContextOptions;
using vulkan::DescriptorSet;
using vulkan::StorageBuffer;

struct SelftestPush {
  kernels::DispatchRange range;
  double scale;
};
static_assert(sizeof(SelftestPush) == 16);

kernels::GpuKernel selftest_kernel() {
  kernels::GpuKernel k;
  k.name = "segmented_sum_selftest";
  k.spirv = std::span<const uint32_t>(segmented_sum_selftest_spv);
  k.storage_buffers = 3;
  k.push_constant_bytes = sizeof(SelftestPush);
  k.default_workgroup_size = 64;
  k.needs_float64 = true;
  return k;
}

/// Random segments: offsets #S+1 (lengths 0…max_len), values uniform in [−1, 1] with a few
/// large magnitudes so that the summation order matters in the last bits.
struct Segments {
  std::vector<int32_t> offsets;
  std::vector<double> values;
};

Segments random_segments(int count, int max_len, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> len(0, max_len);
  std::uniform_real_distribution<double> val(-1.0, 1.0);
  Segments s;
  s.offsets.push_back(0);
  for (int i = 0; i < count; ++i) s.offsets.push_back(s.offsets.back() + len(rng));
  s.values.resize(size_t(s.offsets.back()));
  for (size_t j = 0; j < s.values.size(); ++j) s.values[j] = val(rng) * (j % 17 == 0 ? 1e8 : 1.0);
  return s;
}

/// CPU twin of the self-test shader: same order of operations, so the results agree bit for bit.
std::vector<double> segmented_sum_cpu(const Segments& s, double scale) {
  std::vector<double> out(s.offsets.size() - 1);
  for (size_t i = 0; i + 1 < s.offsets.size(); ++i) {
    double sum = 0.0;
    for (int32_t j = s.offsets[i]; j < s.offsets[i + 1]; ++j) sum += s.values[size_t(j)];
    out[i] = scale * sum;
  }
  return out;
}

/// A persistent runner, as a kernel's host side would be: buffers and pipeline live across calls.
class SelftestRunner {
 public:
  SelftestRunner(Context& ctx, uint32_t workgroup_size = 0)
      : m_ctx(ctx),
        m_kernel(selftest_kernel()),
        m_pipeline(ctx, m_kernel, workgroup_size),
        m_offsets(ctx, "offsets"),
        m_values(ctx, "values"),
        m_sums(ctx, "sums"),
        m_set(ctx, m_pipeline, {&m_offsets, &m_values, &m_sums}) {}

  std::vector<double> run(const Segments& s, double scale, BatchReport* report = nullptr) {
    const uint32_t segments = uint32_t(s.offsets.size() - 1);
    std::vector<double> out(segments);
    CommandBatch batch(m_ctx);
    batch.upload(m_offsets, std::span<const int32_t>(s.offsets));
    batch.upload(m_values, std::span<const double>(s.values));
    batch.allocate(m_sums, segments * sizeof(double));
    batch.dispatch(m_pipeline, m_set, SelftestPush{{}, scale}, segments);
    batch.download(m_sums, std::span<double>(out));
    const BatchReport r = batch.submit();
    if (report != nullptr) *report = r;
    return out;
  }

  const ComputePipeline& pipeline() const { return m_pipeline; }
  StorageBuffer& values() { return m_values; }
  StorageBuffer& offsets() { return m_offsets; }

 private:
  Context& m_ctx;
  kernels::GpuKernel m_kernel;
  ComputePipeline m_pipeline;
  StorageBuffer m_offsets, m_values, m_sums;
  DescriptorSet m_set;
};

void expect_bitwise_equal(const std::vector<double>& gpu, const std::vector<double>& cpu) {
  ASSERT_EQ(gpu.size(), cpu.size());
  size_t mismatches = 0, first = gpu.size();
  for (size_t i = 0; i < gpu.size(); ++i) {
    if (gpu[i] != cpu[i]) {
      if (mismatches++ == 0) first = i;
    }
  }
  EXPECT_EQ(mismatches, 0u) << "first mismatch at " << first << ": gpu " << gpu[first] << " cpu "
                            << cpu[first];
}

// --- device choice (pure logic, no device needed) -------------------------------------------

vulkan::PhysicalDeviceInfo fake(uint32_t index, const char* name, vulkan::DeviceType type,
                                bool fp64 = true, int queue = 0) {
  vulkan::PhysicalDeviceInfo d;
  d.index = index;
  d.name = name;
  d.type = type;
  d.float64 = fp64;
  d.compute_queue_family = queue;
  return d;
}

TEST(VulkanDeviceChoiceVk, ScoresDiscreteOverIntegratedOverVirtualOverCpu) {
  using vulkan::DeviceType;
  const std::vector<vulkan::PhysicalDeviceInfo> devices = {
      fake(0, "llvmpipe (LLVM 15)", DeviceType::Cpu), fake(1, "Virtio GPU", DeviceType::Virtual),
      fake(2, "Intel(R) UHD Graphics", DeviceType::Integrated),
      fake(3, "NVIDIA GeForce RTX 4090", DeviceType::Discrete)};
  EXPECT_EQ(vulkan::choose_device(devices, "", false), 3u);
  EXPECT_EQ(vulkan::choose_device(std::span(devices).first(3), "", false), 2u);
  EXPECT_EQ(vulkan::choose_device(std::span(devices).first(2), "", false), 1u);
  EXPECT_EQ(vulkan::choose_device(std::span(devices).first(1), "", false), 0u);
}

TEST(VulkanDeviceChoiceVk, SkipsUnusableDevices) {
  using vulkan::DeviceType;
  // A discrete GPU without fp64 (e.g. Intel Arc) loses to lavapipe when fp64 is required; a
  // device without a compute queue is never chosen.
  const std::vector<vulkan::PhysicalDeviceInfo> devices = {
      fake(0, "Intel(R) Arc(tm) A770", DeviceType::Discrete, /*fp64=*/false),
      fake(1, "display-only", DeviceType::Integrated, true, /*queue=*/-1),
      fake(2, "llvmpipe", DeviceType::Cpu)};
  EXPECT_EQ(vulkan::choose_device(devices, "", true), 2u);
  EXPECT_EQ(vulkan::choose_device(devices, "", false), 0u);
  EXPECT_EQ(vulkan::device_score(devices[1], false), -1);
}

TEST(VulkanDeviceChoiceVk, SelectorByIndexOrNameSubstring) {
  using vulkan::DeviceType;
  const std::vector<vulkan::PhysicalDeviceInfo> devices = {
      fake(0, "NVIDIA GeForce RTX 4090", DeviceType::Discrete),
      fake(1, "llvmpipe (LLVM 15.0.6, 256 bits)", DeviceType::Cpu)};
  EXPECT_EQ(vulkan::choose_device(devices, "1", true), 1u);
  EXPECT_EQ(vulkan::choose_device(devices, "LLVMPIPE", true), 1u);
  EXPECT_EQ(vulkan::choose_device(devices, "rtx", true), 0u);
  try {
    vulkan::choose_device(devices, "radeon", true);
    FAIL() << "expected DeviceError";
  } catch (const DeviceError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("radeon"), std::string::npos) << what;
    EXPECT_NE(what.find("llvmpipe"), std::string::npos) << "should list the devices: " << what;
  }
  EXPECT_THROW(vulkan::choose_device(devices, "7", true), DeviceError);
  EXPECT_THROW(vulkan::choose_device({}, "", true), DeviceError);
  // Selecting an unusable device explicitly is an error that says why.
  std::vector<vulkan::PhysicalDeviceInfo> no_fp64 = {fake(0, "Arc", DeviceType::Discrete, false)};
  try {
    vulkan::choose_device(no_fp64, "arc", true);
    FAIL() << "expected DeviceError";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("shaderFloat64"), std::string::npos) << e.what();
  }
}

// --- context, buffers, pipelines, dispatch ---------------------------------------------------

TEST_F(VulkanTest, ContextDescribesItsDevice) {
  const vulkan::PhysicalDeviceInfo& d = ctx().info();
  EXPECT_FALSE(d.name.empty());
  EXPECT_FALSE(d.driver.empty());
  EXPECT_GE(d.compute_queue_family, 0);
  EXPECT_TRUE(ctx().validation_enabled());
  EXPECT_GT(ctx().max_workgroups_per_dispatch(), 0u);
  // The automatic choice is the best-scoring device.
  for (const auto& other : ctx().devices()) {
    EXPECT_LE(vulkan::device_score(other, false), vulkan::device_score(d, false)) << other.name;
  }
  std::cout << "[ device ] " << d.name << " | " << d.driver << " | " << vulkan::to_string(d.type)
            << (d.uma ? " | UMA" : "") << (d.float64 ? " | fp64" : "") << "\n";
}

TEST_F(VulkanTest, ProbeNamesTheDeviceAContextWouldChooseWithoutBuildingIt) {
  // The same options, with and without a selector: probe() and the constructor agree.
  for (const char* selector : {"", "0"}) {
    ContextOptions options = ctx().options();
    options.device = selector;
    const vulkan::PhysicalDeviceInfo probed = Context::probe(options);
    const Context full(options);
    EXPECT_EQ(probed.index, full.info().index) << selector;
    EXPECT_EQ(probed.name, full.info().name);
    EXPECT_EQ(probed.driver, full.info().driver);
    EXPECT_EQ(probed.type, full.info().type);
    expect_no_validation_messages(full);
  }
  ContextOptions bad = ctx().options();
  bad.device = "no such device anywhere";
  EXPECT_THROW(Context::probe(bad), DeviceError);
}

TEST_F(VulkanTest, ValidationMessagesAreCounted) {
  // The zero-message requirement is only worth something if the counter works: provoke one
  // harmless error (a buffer with no usage flags; drivers accept it, the layer does not).
  vulkan::ContextOptions o = validated_options();
  o.print_validation_messages = false;
  Context noisy(o);
  auto info = vulkan::vk_struct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
  info.size = 256;
  info.usage = 0;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer = VK_NULL_HANDLE;
  if (vkCreateBuffer(noisy.device(), &info, nullptr, &buffer) == VK_SUCCESS) {
    vkDestroyBuffer(noisy.device(), buffer, nullptr);
  }
  EXPECT_GE(noisy.validation_message_count(), 1u);
  ASSERT_FALSE(noisy.validation_messages().empty());
  EXPECT_NE(noisy.validation_messages()[0].find("usage"), std::string::npos)
      << noisy.validation_messages()[0];
}

TEST_F(VulkanTest, SynchronisationValidationIsOn) {
  // CommandBatch's barriers are only proven by a silent layer if the layer would speak up:
  // record by hand a kernel that writes a buffer followed by a copy into the same buffer with
  // no barrier between them (what CommandBatch::download guards against).
  vulkan::ContextOptions o = validated_options();
  o.print_validation_messages = false;
  Context noisy(o);
  const kernels::GpuKernel k = selftest_kernel();
  ComputePipeline pipeline(noisy, k);
  StorageBuffer offsets(noisy, "offsets"), values(noisy, "values"), sums(noisy, "sums");
  DescriptorSet set(noisy, pipeline, {&offsets, &values, &sums});
  set.refresh();
  VkCommandBuffer cb = noisy.command_buffer();
  auto begin =
      vulkan::vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  ASSERT_EQ(vkBeginCommandBuffer(cb, &begin), VK_SUCCESS);
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.handle());
  const VkDescriptorSet handle = set.handle();
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.layout(), 0, 1, &handle, 0,
                          nullptr);
  // count 0: the shader returns at once, but the layer tracks the whole bound range as written.
  const SelftestPush push{{0, 0}, 1.0};
  vkCmdPushConstants(cb, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
  vkCmdDispatch(cb, 1, 1, 1);
  vkCmdFillBuffer(cb, sums.handle(), 0, VK_WHOLE_SIZE, 0u);  // write-after-write hazard
  ASSERT_EQ(vkEndCommandBuffer(cb), VK_SUCCESS);
  noisy.submit_and_wait();
  EXPECT_GE(noisy.validation_message_count(), 1u);
  bool hazard = false;
  for (const std::string& m : noisy.validation_messages())
    hazard = hazard || m.find("HAZARD") != std::string::npos;
  EXPECT_TRUE(hazard) << "expected a SYNC-HAZARD message";
}

TEST_F(VulkanTest, SegmentedSumMatchesCpuTwinBitForBit) {
  const Segments s = random_segments(20000, 12, 7);
  SelftestRunner runner(ctx());
  BatchReport report;
  const std::vector<double> gpu = runner.run(s, 0.25, &report);
  expect_bitwise_equal(gpu, segmented_sum_cpu(s, 0.25));
  ASSERT_EQ(report.dispatches.size(), 1u);
  EXPECT_EQ(report.dispatches[0].items, 20000u);
  EXPECT_EQ(report.dispatches[0].kernel, "segmented_sum_selftest");
  if (ctx().timestamps_supported()) {
    ASSERT_TRUE(report.dispatches[0].device_ms.has_value());
    EXPECT_GE(*report.dispatches[0].device_ms, 0.0);
    EXPECT_LE(*report.dispatches[0].device_ms, report.wall_ms + 1.0);
  }
}

TEST_F(VulkanTest, AnyWorkgroupSizeGivesTheSameBits) {
  const Segments s = random_segments(3001, 9, 11);
  const std::vector<double> cpu = segmented_sum_cpu(s, -3.0);
  for (uint32_t wg : {1u, 7u, 32u, 64u, 256u}) {
    SelftestRunner runner(ctx(), wg);
    EXPECT_EQ(runner.pipeline().workgroup_size(),
              std::min(wg, ctx().limits().maxComputeWorkGroupSize[0]));
    SCOPED_TRACE("workgroup size " + std::to_string(wg));
    expect_bitwise_equal(runner.run(s, -3.0), cpu);
  }
}

TEST_F(VulkanTest, EmptyLaunchAndEmptyBuffers) {
  Segments s;
  s.offsets = {0};
  SelftestRunner runner(ctx());
  EXPECT_TRUE(runner.run(s, 1.0).empty());
  // Segments that are all empty: every sum is exactly 0.
  s.offsets.assign(100, 0);
  const std::vector<double> gpu = runner.run(s, 1.0);
  EXPECT_TRUE(std::all_of(gpu.begin(), gpu.end(), [](double v) { return v == 0.0; }));
}

TEST_F(VulkanTest, UploadsOnlyWhatChanged) {
  // Large enough for many 16-KiB blocks: 200k doubles = 1.6 MB.
  Segments s = random_segments(40000, 10, 3);
  SelftestRunner runner(ctx());
  BatchReport first, second, third, fourth;
  runner.run(s, 1.0, &first);
  const size_t full = s.offsets.size() * sizeof(int32_t) + s.values.size() * sizeof(double);
  EXPECT_EQ(first.upload_bytes, full);

  // Same inputs: nothing moves, results unchanged.
  const std::vector<double> again = runner.run(s, 1.0, &second);
  EXPECT_EQ(second.upload_bytes, 0u);
  expect_bitwise_equal(again, segmented_sum_cpu(s, 1.0));

  // One value changes: one block of `values` moves, and the result sees it.
  s.values[s.values.size() / 2] += 1.0;
  const std::vector<double> changed = runner.run(s, 1.0, &third);
  EXPECT_EQ(third.upload_bytes, StorageBuffer::kBlockBytes);
  EXPECT_EQ(runner.values().last_upload_bytes(), StorageBuffer::kBlockBytes);
  EXPECT_EQ(runner.offsets().last_upload_bytes(), 0u);
  expect_bitwise_equal(changed, segmented_sum_cpu(s, 1.0));

  // The problem grows past capacity: buffers are reallocated, descriptors re-pointed, and
  // everything is uploaded again.
  const uint64_t generation = runner.values().generation();
  Segments bigger = random_segments(120000, 10, 4);
  const std::vector<double> grown = runner.run(bigger, 2.0, &fourth);
  EXPECT_NE(runner.values().generation(), generation);
  EXPECT_EQ(fourth.upload_bytes,
            bigger.offsets.size() * sizeof(int32_t) + bigger.values.size() * sizeof(double));
  expect_bitwise_equal(grown, segmented_sum_cpu(bigger, 2.0));

  // And shrinks again: no reallocation, results still right.
  const uint64_t g2 = runner.values().generation();
  expect_bitwise_equal(runner.run(s, 1.0), segmented_sum_cpu(s, 1.0));
  EXPECT_EQ(runner.values().generation(), g2);
}

TEST_F(VulkanTest, PhasesMustComeInOrder) {
  SelftestRunner runner(ctx());
  StorageBuffer extra(ctx(), "extra");
  std::vector<double> host(4, 1.0);
  {
    CommandBatch batch(ctx());
    batch.upload(extra, std::span<const double>(host));
    std::vector<double> out(4);
    batch.download(extra, std::span<double>(out));
    EXPECT_THROW(batch.upload(extra, std::span<const double>(host)), std::logic_error);
    std::vector<double> too_many(5);
    EXPECT_THROW(batch.download(extra, std::span<double>(too_many)), std::logic_error);
    batch.submit();
    EXPECT_EQ(out, host);  // upload → download round trip with no kernel in between
  }
  // A batch dropped without submit() leaves the context usable.
  {
    CommandBatch dropped(ctx());
    dropped.upload(extra, std::span<const double>(host));
  }
  const Segments s = random_segments(100, 5, 1);
  expect_bitwise_equal(runner.run(s, 1.0), segmented_sum_cpu(s, 1.0));
}

TEST_F(VulkanTest, KernelOutputsStayOnTheDeviceAcrossBatches) {
  // Batch 1 computes sums; batch 2 reads them back without recomputing — the barrier at the
  // start of every batch orders it after the earlier batch's writes.
  const Segments s = random_segments(5000, 6, 21);
  const kernels::GpuKernel k = selftest_kernel();
  ComputePipeline pipeline(ctx(), k);
  StorageBuffer offsets(ctx(), "offsets"), values(ctx(), "values"), sums(ctx(), "sums");
  DescriptorSet set(ctx(), pipeline, {&offsets, &values, &sums});
  {
    CommandBatch batch(ctx());
    batch.upload(offsets, std::span<const int32_t>(s.offsets));
    batch.upload(values, std::span<const double>(s.values));
    batch.allocate(sums, 5000 * sizeof(double));
    batch.dispatch(pipeline, set, SelftestPush{{}, 1.0}, 5000);
    batch.submit();
  }
  std::vector<double> out(5000);
  {
    CommandBatch batch(ctx());
    batch.download(sums, std::span<double>(out));
    batch.submit();
  }
  expect_bitwise_equal(out, segmented_sum_cpu(s, 1.0));
}

class VulkanStagingTest : public VulkanTest {
 protected:
  vulkan::ContextOptions options() const override {
    vulkan::ContextOptions o = validated_options();
    o.force_staging = true;  // the discrete-GPU path, on any device
    return o;
  }
};

TEST_F(VulkanStagingTest, StagingPathMatchesCpuTwin) {
  EXPECT_TRUE(ctx().uses_staging());
  Segments s = random_segments(30000, 10, 5);
  SelftestRunner runner(ctx());
  BatchReport r1, r2;
  expect_bitwise_equal(runner.run(s, 0.5, &r1), segmented_sum_cpu(s, 0.5));
  s.values[123] = 42.0;
  expect_bitwise_equal(runner.run(s, 0.5, &r2), segmented_sum_cpu(s, 0.5));
  EXPECT_EQ(r2.upload_bytes, StorageBuffer::kBlockBytes);
}

class VulkanChunkedTest : public VulkanTest {
 protected:
  vulkan::ContextOptions options() const override {
    vulkan::ContextOptions o = validated_options();
    o.max_workgroups_per_dispatch = 3;  // forces many vkCmdDispatch chunks
    return o;
  }
};

TEST_F(VulkanChunkedTest, LargeLaunchesAreSplitIntoChunks) {
  const Segments s = random_segments(1000, 4, 9);
  SelftestRunner runner(ctx(), 16);
  BatchReport report;
  expect_bitwise_equal(runner.run(s, 1.0, &report), segmented_sum_cpu(s, 1.0));
  ASSERT_EQ(report.dispatches.size(), 1u);
  EXPECT_EQ(report.dispatches[0].chunks, (1000u + 47u) / 48u);  // 3 groups × 16 per chunk
}

// --- errors ------------------------------------------------------------------------------------

TEST_F(VulkanTest, UnknownDeviceSelectorIsADeviceError) {
  vulkan::ContextOptions o = validated_options();
  o.device = "no-such-gpu-anywhere";
  try {
    Context c(o);
    FAIL() << "expected DeviceError";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpu-anywhere"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(ctx().info().name), std::string::npos) << e.what();
  }
}

/// Sets an environment variable for one scope (value nullptr: unsets it).
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : m_name(name) {
    if (const char* old = std::getenv(name)) m_old = old;
    if (value != nullptr)
      ::setenv(name, value, 1);
    else
      ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (m_old)
      ::setenv(m_name.c_str(), m_old->c_str(), 1);
    else
      ::unsetenv(m_name.c_str());
  }

 private:
  std::string m_name;
  std::optional<std::string> m_old;
};

TEST(VulkanNoDriverVk, MissingDriverIsADeviceErrorAndAutoFallsBack) {
  // Point the loader at a driver manifest that does not exist: the same as a machine without
  // any Vulkan driver. (VK_ICD_FILENAMES for older loaders, VK_DRIVER_FILES for newer ones.)
  ScopedEnv icd("VK_ICD_FILENAMES", "/nonexistent/cutwork_no_driver.json");
  ScopedEnv drivers("VK_DRIVER_FILES", "/nonexistent/cutwork_no_driver.json");
  vulkan::ContextOptions o;
  o.print_validation_messages = false;
  try {
    Context c(o);
    FAIL() << "expected DeviceError without a driver";
  } catch (const DeviceError& e) {
    EXPECT_NE(std::string(e.what()).find("--device cpu"), std::string::npos) << e.what();
  }
  EXPECT_THROW(select_compute_backend(DeviceRequest::Vulkan, nullptr), DeviceError);
  std::ostringstream warnings;
  const ComputeBackend b = select_compute_backend(DeviceRequest::Auto, &warnings);
  EXPECT_EQ(b.kind, ComputeBackend::Kind::Cpu);
  EXPECT_EQ(b.kind_name(), "cpu");
  EXPECT_FALSE(b.fallback_reason.empty());
  const std::string w = warnings.str();
  EXPECT_EQ(std::count(w.begin(), w.end(), '\n'), 1) << "exactly one warning line: " << w;
  EXPECT_EQ(w.rfind("cutwork: warning:", 0), 0u) << w;
}

TEST(VulkanRequiredVk, CutworkRequireVulkanIsReadFromTheEnvironment) {
  {
    ScopedEnv require("CUTWORK_REQUIRE_VULKAN", "1");
    EXPECT_TRUE(vulkan_required());
  }
  {
    ScopedEnv require("CUTWORK_REQUIRE_VULKAN", "0");
    EXPECT_FALSE(vulkan_required());
  }
}

// select_compute_backend makes its contexts from the environment, so CUTWORK_VK_VALIDATION=1
// puts them under the validation layer too, and this test fails on any message from them as
// the fixture does for its own.
class VulkanBackendVk : public VulkanTest {};

TEST_F(VulkanBackendVk, AutoAndVulkanChooseTheDevice) {
  ScopedEnv validation("CUTWORK_VK_VALIDATION", "1");
  std::ostringstream warnings;
  ScopedEnv no_selector("CUTWORK_VK_DEVICE", nullptr);
  const ComputeBackend b = select_compute_backend(DeviceRequest::Auto, &warnings);
  const ComputeBackend v = select_compute_backend(DeviceRequest::Vulkan, &warnings);
  ASSERT_EQ(v.kind, ComputeBackend::Kind::Vulkan);  // every device here has fp64 (lavapipe does)
  EXPECT_TRUE(warnings.str().empty()) << warnings.str();
  ASSERT_NE(v.context, nullptr);
  EXPECT_TRUE(v.context->validation_enabled());
  EXPECT_EQ(v.name, v.context->info().name);
  EXPECT_EQ(v.driver, v.context->info().driver);
  EXPECT_EQ(v.kind_name(), "vulkan");
  EXPECT_EQ(v.reason, "--device vulkan");
  expect_no_validation_messages(*v.context);
  // auto takes the device `vulkan` takes exactly when it is a GPU; lavapipe is left alone.
  const bool gpu = v.context->info().type != vulkan::DeviceType::Cpu &&
                   v.context->info().type != vulkan::DeviceType::Other;
  EXPECT_FALSE(b.reason.empty());
  if (gpu) {
    ASSERT_EQ(b.kind, ComputeBackend::Kind::Vulkan);
    ASSERT_NE(b.context, nullptr);
    EXPECT_TRUE(b.context->validation_enabled());
    expect_no_validation_messages(*b.context);
  } else {
    EXPECT_EQ(b.kind, ComputeBackend::Kind::Cpu);
    EXPECT_EQ(b.context, nullptr);
    EXPECT_TRUE(b.fallback_reason.empty()) << "a CPU-only Vulkan machine is not a failure";
    EXPECT_NE(b.reason.find(v.name), std::string::npos) << b.reason;
    EXPECT_NE(b.reason.find("CPU"), std::string::npos) << b.reason;
  }
}

// The lavapipe-only machine (CI, and any machine without a GPU): auto runs the TBB kernels.
TEST_F(VulkanBackendVk, AutoPicksTheCpuWhenTheOnlyVulkanDeviceIsACpuDevice) {
  ScopedEnv no_selector("CUTWORK_VK_DEVICE", nullptr);
  for (const auto& d : ctx().devices())
    if (d.type != vulkan::DeviceType::Cpu) GTEST_SKIP() << "a non-CPU Vulkan device is present: " << d.name;
  std::ostringstream warnings;
  const ComputeBackend b = select_compute_backend(DeviceRequest::Auto, &warnings);
  EXPECT_EQ(b.kind, ComputeBackend::Kind::Cpu);
  EXPECT_EQ(b.context, nullptr);
  EXPECT_TRUE(warnings.str().empty()) << warnings.str();
  EXPECT_NE(b.reason.find("no GPU"), std::string::npos) << b.reason;
  // Naming the CPU device explicitly still uses it.
  ScopedEnv selector("CUTWORK_VK_DEVICE", "0");
  const ComputeBackend named = select_compute_backend(DeviceRequest::Auto, &warnings);
  EXPECT_EQ(named.kind, ComputeBackend::Kind::Vulkan);
}

}  // namespace
}  // namespace cutwork::test

// Backend selection parts that need no Vulkan device (this file is built with or without
// CUTWORK_WITH_VULKAN); the device paths are in vulkan_context_vk_test.cpp (label gpu).
#include "host/vulkan/backend.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "host/core/error.h"

namespace cutwork {
namespace {

TEST(DeviceRequest, ParsesTheThreeValues) {
  EXPECT_EQ(parse_device_request("cpu"), DeviceRequest::Cpu);
  EXPECT_EQ(parse_device_request("Vulkan"), DeviceRequest::Vulkan);
  EXPECT_EQ(parse_device_request("AUTO"), DeviceRequest::Auto);
  for (DeviceRequest r : {DeviceRequest::Cpu, DeviceRequest::Vulkan, DeviceRequest::Auto}) {
    EXPECT_EQ(parse_device_request(to_string(r)), r);
  }
}

TEST(DeviceRequest, RejectsOtherValuesWithAUsableMessage) {
  try {
    parse_device_request("gpu");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'gpu'"), std::string::npos) << what;
    EXPECT_NE(what.find("cpu, vulkan or auto"), std::string::npos) << what;
  }
  EXPECT_THROW(parse_device_request(""), InputError);
}

TEST(ComputeBackendSelection, CpuNeverTouchesVulkanAndNeverWarns) {
  std::ostringstream warnings;
  const ComputeBackend b = select_compute_backend(DeviceRequest::Cpu, &warnings);
  EXPECT_EQ(b.kind, ComputeBackend::Kind::Cpu);
  EXPECT_EQ(b.kind_name(), "cpu");
  EXPECT_EQ(b.context, nullptr);
  EXPECT_FALSE(b.name.empty());
  EXPECT_NE(b.driver.find("TBB"), std::string::npos) << b.driver;
  EXPECT_TRUE(b.fallback_reason.empty());
  EXPECT_TRUE(warnings.str().empty());
}

TEST(ComputeBackendSelection, WithoutVulkanInTheBuildAutoWarnsOnceAndVulkanFails) {
  if (vulkan_compiled_in()) GTEST_SKIP() << "built with Vulkan; see the gpu-labelled tests";
  std::ostringstream warnings;
  const ComputeBackend b = select_compute_backend(DeviceRequest::Auto, &warnings);
  EXPECT_EQ(b.kind, ComputeBackend::Kind::Cpu);
  const std::string w = warnings.str();
  EXPECT_EQ(std::count(w.begin(), w.end(), '\n'), 1) << w;
  EXPECT_THROW(select_compute_backend(DeviceRequest::Vulkan, nullptr), DeviceError);
}

TEST(ComputeBackendSelection, AutoTakesGpusOnlyUnlessADeviceIsNamed) {
  EXPECT_TRUE(auto_takes_vulkan_device("discrete GPU", false));
  EXPECT_TRUE(auto_takes_vulkan_device("integrated GPU", false));
  EXPECT_TRUE(auto_takes_vulkan_device("virtual GPU", false));
  EXPECT_FALSE(auto_takes_vulkan_device("CPU", false));
  EXPECT_FALSE(auto_takes_vulkan_device("other", false));
  EXPECT_TRUE(auto_takes_vulkan_device("CPU", true));
}

TEST(ComputeBackendSelection, CpuRequestSaysWhy) {
  EXPECT_EQ(select_compute_backend(DeviceRequest::Cpu, nullptr).reason, "--device cpu");
}

}  // namespace
}  // namespace cutwork

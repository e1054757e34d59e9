#pragma once
/// Shared by every *_vk_test.cpp: a fixture whose Context has the Khronos validation layer on
/// (with synchronisation validation) and which FAILS the test on any validation message.
///
/// No usable Vulkan device (no driver, no ICD, no device with shaderFloat64) → the test is skipped,
/// so machines without Vulkan still pass. Anything else that goes wrong — the validation layer
/// missing, a device that exists but cannot be opened — is a failure, so CI cannot silently lose
/// its GPU checks.
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <link.h>

#include <memory>
#include <optional>
#include <string>

#include "host/core/error.h"
#include "host/vulkan/context.h"

namespace cutwork::test {

/// Keeps the Vulkan driver, the layers and the LLVM they JIT with mapped until exit
/// (RTLD_NODELETE). The loader unloads them at vkDestroyInstance, after which LeakSanitizer
/// (CUTWORK_SANITIZE builds) could only report their leftovers as "<unknown module>"; pinned,
/// they keep their names and the suppressions in vulkan_context_vk_test.cpp apply.
inline void pin_vulkan_libraries() {
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void*) -> int {
        const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        for (const char* key : {"vulkan", "VkLayer", "LLVM"}) {
          if (name.find(key) != std::string::npos) {
            // RTLD_NOLOAD: take a reference to an already-loaded library only; never released.
            dlopen(name.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
            break;
          }
        }
        return 0;
      },
      nullptr);
}

/// Empty when some Vulkan device can be opened; else why not. Probed once per process, without
/// validation, so that a missing layer is not mistaken for a missing device.
inline const std::optional<std::string>& vulkan_unavailable_reason() {
  static const std::optional<std::string> reason = []() -> std::optional<std::string> {
    try {
      vulkan::ContextOptions probe = vulkan::ContextOptions::from_environment();
      probe.validation = false;
      probe.print_validation_messages = false;
      probe.require_float64 = true;  // every cutwork kernel computes in double
      vulkan::Context ctx(probe);
      pin_vulkan_libraries();
      return std::nullopt;
    } catch (const DeviceError& e) {
      return std::string(e.what());
    }
  }();
  return reason;
}

/// Options every GPU test starts from: environment device selector, validation on.
inline vulkan::ContextOptions validated_options() {
  vulkan::ContextOptions o = vulkan::ContextOptions::from_environment();
  o.validation = true;
  o.print_validation_messages = true;
  o.require_float64 = true;
  return o;
}

/// Fixture: ctx() is a validated Context (created in SetUp with options()); TearDown fails the
/// test if the validation layer reported anything, listing the messages.
class VulkanTest : public ::testing::Test {
 protected:
  /// Override to change the context (staging, chunking, fp64 …); validation stays forced on.
  virtual vulkan::ContextOptions options() const { return validated_options(); }

  void SetUp() override {
    if (const auto& why = vulkan_unavailable_reason()) GTEST_SKIP() << "no Vulkan device: " << *why;
    vulkan::ContextOptions o = options();
    o.validation = true;
    m_ctx = std::make_shared<vulkan::Context>(o);
    pin_vulkan_libraries();  // now the validation layer is loaded too
  }

  void TearDown() override {
    if (!m_ctx) return;
    expect_no_validation_messages(*m_ctx);
    m_ctx.reset();
  }

  static void expect_no_validation_messages(const vulkan::Context& ctx) {
    const size_t n = ctx.validation_message_count();
    std::string all;
    for (const std::string& m : ctx.validation_messages()) all += "\n  " + m;
    EXPECT_EQ(n, 0u) << "validation layer messages:" << all;
  }

  vulkan::Context& ctx() { return *m_ctx; }
  /// For owners that share the context (ClipFillVk).
  const std::shared_ptr<vulkan::Context>& shared_ctx() { return m_ctx; }

  std::shared_ptr<vulkan::Context> m_ctx;
};

}  // namespace cutwork::test

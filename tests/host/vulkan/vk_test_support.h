#pragma once
/// Shared by every *_vk_test.cpp: a fixture whose Context has the Khronos validation layer on
/// (with synchronisation validation) and which FAILS the test on any validation message.
///
/// No usable Vulkan device (no driver, no ICD, no device with shaderFloat64) → the test is skipped,
/// so machines without Vulkan still pass — unless CUTWORK_REQUIRE_VULKAN=1 (CI sets it), which
/// turns that skip into a failure. Anything else that goes wrong — the validation layer missing,
/// a device that exists but cannot be opened — is always a failure, so CI cannot silently lose
/// its GPU checks. Tests that do not use the fixture start with CUTWORK_SKIP_WITHOUT_VULKAN().
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "host/core/error.h"
#include "host/vulkan/backend.h"
#include "host/vulkan/context.h"

namespace cutwork::test {

/// Whether two arrays hold the same bytes (the parity tests' "bit for bit"); empty arrays are
/// equal without touching their (possibly null) data pointers.
template <class T>
bool same_bits(std::span<const T> a, std::span<const T> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return same_bits(std::span<const T>(a), std::span<const T>(b));
}

/// Whether `ctx` runs on Mesa's lavapipe (llvmpipe): IEEE double arithmetic, so the parity tests
/// demand the CPU twins' bits there.
inline bool is_lavapipe(const vulkan::Context& ctx) {
  std::string id = ctx.info().name + " " + ctx.info().driver;
  std::transform(id.begin(), id.end(), id.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return id.find("llvmpipe") != std::string::npos || id.find("lavapipe") != std::string::npos;
}

/// A Vulkan ComputeBackend on `ctx`, as select_compute_backend would resolve it (for the
/// `for_backend` factories of the twins' interfaces).
inline ComputeBackend vulkan_backend(std::shared_ptr<vulkan::Context> ctx) {
  ComputeBackend backend;
  backend.kind = ComputeBackend::Kind::Vulkan;
  backend.context = std::move(ctx);
  return backend;
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
      return std::nullopt;
    } catch (const DeviceError& e) {
      return std::string(e.what());
    }
  }();
  return reason;
}

/// CUTWORK_REQUIRE_VULKAN is 1 / true / on / yes: a missing Vulkan device fails the GPU tests
/// instead of skipping them.
inline bool vulkan_required() {
  const char* v = std::getenv("CUTWORK_REQUIRE_VULKAN");
  if (v == nullptr) return false;
  std::string s(v);
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return s == "1" || s == "true" || s == "on" || s == "yes";
}

/// Ends the current test (or SetUp) when no Vulkan device can be opened: GTEST_SKIP, or a
/// failure under CUTWORK_REQUIRE_VULKAN=1.
#define CUTWORK_SKIP_WITHOUT_VULKAN()                                                          \
  do {                                                                                         \
    if (const auto& cutwork_why = ::cutwork::test::vulkan_unavailable_reason()) {              \
      if (::cutwork::test::vulkan_required())                                                  \
        GTEST_FAIL() << "CUTWORK_REQUIRE_VULKAN is set but there is no Vulkan device: "        \
                     << *cutwork_why;                                                          \
      GTEST_SKIP() << "no Vulkan device: " << *cutwork_why;                                    \
    }                                                                                          \
  } while (false)

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
    CUTWORK_SKIP_WITHOUT_VULKAN();
    vulkan::ContextOptions o = options();
    o.validation = true;
    m_ctx = std::make_shared<vulkan::Context>(o);
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

// Shared fixture of the GPU, render and ui tests: a validated context on the best device, skipping only when no Vulkan device exists.
#pragma once

#include <gtest/gtest.h>

#include <optional>

#include "gpu/context.h"
#include "volume/brick_volume.h"

namespace dentsim::gpu::test {

// Validation is always on here (as DENTSIM_VALIDATION=1 does under CTest), and any validation
// error or warning seen during a test fails it in TearDown. A suite that draws (render, ui) derives
// from GraphicsGpuTest instead, whose context has a graphics queue.
class GpuTest : public ::testing::Test {
 protected:
  explicit GpuTest(bool graphics = false) : graphics_(graphics) {}

  void SetUp() override {
    ContextOptions options;
    options.enable_validation = true;
    options.graphics = graphics_;
    auto created = Context::create(options);
    if (!created) {
      if (isNoDeviceError(created.error())) GTEST_SKIP() << "no Vulkan device: " << created.message();
      FAIL() << "context creation failed: " << created.message();
    }
    ctx_.emplace(std::move(*created));
  }

  void TearDown() override {
    if (!ctx_) return;
    EXPECT_EQ(ctx_->validationErrorCount(), 0u) << "last validation message: " << ctx_->lastValidationMessage();
    EXPECT_EQ(ctx_->validationWarningCount(), 0u) << "last validation message: " << ctx_->lastValidationMessage();
  }

  Context& ctx() { return *ctx_; }

  std::optional<Context> ctx_;

 private:
  bool graphics_;
};

// The same with ContextOptions::graphics = true, for the render and ui suites.
class GraphicsGpuTest : public GpuTest {
 protected:
  GraphicsGpuTest() : GpuTest(true) {}
};

// Both totals, compared exactly, with a message naming the first difference.
inline ::testing::AssertionResult totalsEqual(const MaterialTotals& gpu, const MaterialTotals& cpu) {
  for (size_t m = 0; m < DS_MATERIAL_COUNT; ++m) {
    if (gpu.voxels[m] != cpu.voxels[m])
      return ::testing::AssertionFailure() << "material " << m << ": GPU " << gpu.voxels[m] << " voxels, CPU " << cpu.voxels[m];
    if (gpu.fill_sum[m] != cpu.fill_sum[m])
      return ::testing::AssertionFailure() << "material " << m << ": GPU fill " << gpu.fill_sum[m] << ", CPU " << cpu.fill_sum[m];
  }
  return ::testing::AssertionSuccess();
}

}  // namespace dentsim::gpu::test

// Tests of src/gpu/device_report.cpp and `dentsim gpu` (src/app/cmd_gpu.cpp).
#include <gtest/gtest.h>

#include <sstream>

#include "gpu/device_report.h"
#include "gpu_fixture.h"
#include "test_support.h"

namespace dentsim::gpu::test {

using DeviceReportTest = GpuTest;  // the fixture skips when there is no device at all

TEST_F(DeviceReportTest, TextReportNamesTheDeviceLimitsAndSelfTest) {
  std::ostringstream out;
  ContextOptions options;
  options.enable_validation = true;
  const Status s = printDeviceReport(out, options, false);
  ASSERT_TRUE(s) << s.message() << "\n" << out.str();
  const std::string text = out.str();
  EXPECT_NE(text.find(ctx().device().name), std::string::npos) << text;
  EXPECT_NE(text.find("maxStorageBufferRange"), std::string::npos) << text;
  EXPECT_NE(text.find("GPU == CPU"), std::string::npos) << text;
  EXPECT_NE(text.find("0 errors"), std::string::npos) << text;
}

TEST_F(DeviceReportTest, JsonReport) {
  std::ostringstream out;
  const Status s = printDeviceReport(out, ContextOptions{}, true);
  ASSERT_TRUE(s) << s.message();
  const std::string text = out.str();
  EXPECT_EQ(text.front(), '{');
  EXPECT_NE(text.find("\"gpu_equals_cpu\": true"), std::string::npos) << text;
  EXPECT_NE(text.find("\"max_storage_buffer_range_bytes\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"subgroup_size\""), std::string::npos) << text;
}

TEST_F(DeviceReportTest, CommandLineSucceedsAndFailsCleanly) {
  const auto ok = dentsim::test::runDentsim("gpu --validation");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_NE(ok.output.find("GPU == CPU"), std::string::npos) << ok.output;
  EXPECT_EQ(ok.output.find("validation error"), std::string::npos) << ok.output;

  const auto bad = dentsim::test::runDentsim("gpu --device no-such-gpu-xyz");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("dentsim: gpu: device override 'no-such-gpu-xyz' matches no Vulkan device"), std::string::npos)
      << bad.output;
}

}  // namespace dentsim::gpu::test

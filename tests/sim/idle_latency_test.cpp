// IdleLatencyRequest: the request reaches the file as one 32-bit integer and lasts while it is held; failures are reported, not thrown, and a file the user may not open names the udev rule; the haptic loop holds it while its thread runs.
#include "sim/idle_latency.h"

#include <fcntl.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "core/permission_advice.h"
#include "sim/haptic_loop.h"
#include "sim/tool_library.h"
#include "sim_fixtures.h"
#include "test_support.h"
#include "unprivileged.h"

namespace dentsim {
namespace {

std::vector<char> bytesOf(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(IdleLatencyRequest, WritesTheBoundAsOneBinaryInteger) {
  // The kernel reads a binary 32-bit integer; a regular file stands in for the device and keeps it.
  const test::TempDir dir;
  const std::filesystem::path file = dir.path() / "qos";
  std::ofstream(file).close();
  {
    const IdleLatencyRequest request(37, file.string());
    EXPECT_TRUE(request.held());
    EXPECT_NE(request.note().find("37 us"), std::string::npos) << request.note();
    EXPECT_NE(request.note().find(file.string()), std::string::npos) << request.note();
    const std::vector<char> bytes = bytesOf(file);
    ASSERT_EQ(bytes.size(), sizeof(int32_t));
    int32_t value = 0;
    std::memcpy(&value, bytes.data(), sizeof value);
    EXPECT_EQ(value, 37);
  }
  // Moving hands the open request over: only the new owner holds it.
  IdleLatencyRequest a(0, file.string());
  ASSERT_TRUE(a.held());
  IdleLatencyRequest b(std::move(a));
  EXPECT_TRUE(b.held());
  EXPECT_FALSE(a.held());  // NOLINT(bugprone-use-after-move): the moved-from state is specified
  IdleLatencyRequest c;
  EXPECT_FALSE(c.held());
  c = std::move(b);
  EXPECT_TRUE(c.held());
  EXPECT_FALSE(b.held());  // NOLINT(bugprone-use-after-move)
}

TEST(IdleLatencyRequest, FailuresNameTheFileAndTheReason) {
  const test::TempDir dir;
  const std::string missing = (dir.path() / "no" / "such").string();
  const IdleLatencyRequest request(0, missing);
  EXPECT_FALSE(request.held());
  EXPECT_EQ(request.note(), missing + ": No such file or directory");
  EXPECT_FALSE(request.denied());  // no rule makes a missing file appear

  // A negative bound asks for nothing and touches nothing.
  const std::filesystem::path file = dir.path() / "untouched";
  std::ofstream(file).close();
  const IdleLatencyRequest none(-1, file.string());
  EXPECT_FALSE(none.held());
  EXPECT_EQ(none.note(), "not requested");
  EXPECT_TRUE(bytesOf(file).empty());
}

TEST(IdleLatencyRequest, AFileTheUserMayNotOpenGetsThePermissionLineAndIsOptional) {
  if (const std::string why = test::whyNotNobody(); !why.empty()) GTEST_SKIP() << why;
  // Root's 0600 file, as /dev/cpu_dma_latency is without the rule; nobody asks for the request.
  const test::TempDir dir;
  test::letEveryoneIn(dir.path());
  const std::filesystem::path file = dir.path() / "cpu_dma_latency";
  std::ofstream(file).close();
  std::filesystem::permissions(file, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write,
                               std::filesystem::perm_options::replace);
  const std::string got = test::inChildAsNobody([&] {
    const IdleLatencyRequest request(0, file.string());
    return std::string(request.held() ? "held " : "") + (request.denied() ? "denied " : "") + request.note();
  });
  EXPECT_EQ(got, "denied " + permissionAdvice(file.string(), RuleTakesEffect::Trigger) +
                     "; optional: the loop runs without it, with slower steps after idle");
  EXPECT_TRUE(bytesOf(file).empty());  // nothing was written

  // Root may open it: the same request is held, and nothing is denied.
  const IdleLatencyRequest as_root(0, file.string());
  EXPECT_TRUE(as_root.held()) << as_root.note();
  EXPECT_FALSE(as_root.denied());
}

// Whether `path` opens with `flags`: the oracle for whether a request can be held. access() is not
// enough: a container's device rules can refuse root an open that the file's mode allows.
bool opens(const char* path, int flags) {
  const int fd = ::open(path, flags | O_CLOEXEC);
  if (fd < 0) return false;
  ::close(fd);
  return true;
}

// The kernel's current bound: reading the device gives the smallest request held by anyone.
bool readKernelBound(int32_t* out) {
  const int fd = ::open(IdleLatencyRequest::kDefaultPath, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const ssize_t got = ::read(fd, out, sizeof *out);
  ::close(fd);
  return got == ssize_t(sizeof *out);
}

TEST(IdleLatencyRequest, TheKernelHoldsTheBoundWhileTheRequestIsOpen) {
  if (!opens(IdleLatencyRequest::kDefaultPath, O_RDWR))
    GTEST_SKIP() << "needs read and write access to " << IdleLatencyRequest::kDefaultPath
                 << " (root, or the udev rule in devices/70-dentsim.rules)";
  const IdleLatencyRequest request(3);
  ASSERT_TRUE(request.held()) << request.note();
  int32_t bound = -1;
  ASSERT_TRUE(readKernelBound(&bound));
  // Others (another test's haptic loop) may ask for less at the same time; never for more.
  EXPECT_GE(bound, 0);
  EXPECT_LE(bound, 3);
}

TEST(IdleLatencyRequest, TheLoopHoldsItWhileItsThreadRuns) {
  test::Block block = test::flatBlock(Material::Enamel);
  auto tool = loadToolModel("round_bur_010", defaultSimParams().point_shell);
  ASSERT_TRUE(tool.ok()) << tool.message();
  HapticLoop loop(block.volume, block.frame, defaultSimParams(), *tool, nullptr, nullptr);
  EXPECT_EQ(loop.idleLatencyUs(), 0);  // asked for by default
  loop.setIdleLatencyUs(-1);
  ASSERT_TRUE(loop.start().ok());
  loop.stop();
  EXPECT_FALSE(loop.idleLatencyHeld());
  EXPECT_EQ(loop.idleLatencyNote(), "not requested");

  loop.setIdleLatencyUs(0);
  ASSERT_TRUE(loop.start().ok());
  loop.stop();
  const bool writable = opens(IdleLatencyRequest::kDefaultPath, O_WRONLY);
  EXPECT_EQ(loop.idleLatencyHeld(), writable) << loop.idleLatencyNote();
  EXPECT_NE(loop.idleLatencyNote().find(IdleLatencyRequest::kDefaultPath), std::string::npos)
      << loop.idleLatencyNote();
}

}  // namespace
}  // namespace dentsim

// Tests for core/permission_advice.h: the one permission line names the node, the rule file, where it goes and what to do next.
#include "core/permission_advice.h"

#include <gtest/gtest.h>

#include <string>

namespace dentsim {
namespace {

TEST(PermissionAdvice, NamesTheNodeTheRuleAndTheReplug) {
  EXPECT_EQ(permissionAdvice("/dev/hidraw3"),
            "permission denied on /dev/hidraw3: install devices/70-dentsim.rules into /etc/udev/rules.d, then replug "
            "(see docs/DEVICES.md)");
}

TEST(PermissionAdvice, ANodeThatIsAlwaysThereIsTriggeredNotReplugged) {
  const std::string line = permissionAdvice("/dev/cpu_dma_latency", RuleTakesEffect::Trigger);
  EXPECT_EQ(line,
            "permission denied on /dev/cpu_dma_latency: install devices/70-dentsim.rules into /etc/udev/rules.d, "
            "then run `sudo udevadm trigger` (see docs/DEVICES.md)");
  EXPECT_EQ(line.find("replug"), std::string::npos);
  EXPECT_EQ(line.find('\n'), std::string::npos);  // one line
}

}  // namespace
}  // namespace dentsim

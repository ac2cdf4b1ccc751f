// permissionAdvice: the one line dentsim prints when a device node exists but this user may not open it, naming the udev rule that fixes it.
//
// Every backend that opens a node (the Falcon's USB node, a pedal's hidraw node, a Touch's serial
// node) and the haptic loop's idle-latency request (/dev/cpu_dma_latency) word it the same way, so
// the user meets one sentence and one fix. It lives in core because sim (the idle-latency request)
// and devices (the backends) may both include core, and neither may include the other.
#pragma once

#include <string>

namespace dentsim {

// The rule file, relative to the source tree; docs/DEVICES.md ("Permissions") explains it.
inline constexpr const char* kUdevRulesFile = "devices/70-dentsim.rules";

// How an installed rule reaches the node: a plugged device gets it when it is plugged in again; a
// node that is always there (/dev/cpu_dma_latency) when udev applies the rules again.
enum class RuleTakesEffect { Replug, Trigger };

// "permission denied on NODE: install devices/70-dentsim.rules into /etc/udev/rules.d, then replug
// (see docs/DEVICES.md)"; with Trigger, "then run `sudo udevadm trigger`" instead of "then replug".
inline std::string permissionAdvice(const std::string& node, RuleTakesEffect takes_effect = RuleTakesEffect::Replug) {
  const char* then = takes_effect == RuleTakesEffect::Replug ? "then replug" : "then run `sudo udevadm trigger`";
  return "permission denied on " + node + ": install " + kUdevRulesFile + " into /etc/udev/rules.d, " + then +
         " (see docs/DEVICES.md)";
}

}  // namespace dentsim

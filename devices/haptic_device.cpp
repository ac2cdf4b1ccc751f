// HapticDevice: state and reason bookkeeping, enable/disable through the safety layer, and the guarded output.
#include "devices/haptic_device.h"

#include <cstdio>

namespace dentsim::devices {

const char* stateName(DeviceState s) {
  switch (s) {
    case DeviceState::Disconnected: return "disconnected";
    case DeviceState::NeedsFirmware: return "needs firmware";
    case DeviceState::NeedsHoming: return "needs homing";
    case DeviceState::Ready: return "ready";
    case DeviceState::Enabled: return "enabled";
    case DeviceState::Fault: return "fault";
  }
  return "?";
}

std::string HapticDevice::reason() const {
  std::lock_guard lock(reason_mutex_);
  return reason_;
}

void HapticDevice::setState(DeviceState s, std::string reason) {
  {
    std::lock_guard lock(reason_mutex_);
    reason_ = std::move(reason);
  }
  // Leaving Enabled for any reason stops the force before anyone sees the new state.
  if (s != DeviceState::Enabled) safety_.disable();
  // A fault also stops the other pen of the same student (SafetyGroup).
  if (s == DeviceState::Fault) safety_.haltGroup();
  state_.store(s, std::memory_order_release);
}

Status HapticDevice::enable() {
  const DeviceState s = state();
  if (s == DeviceState::Enabled) return Ok{};
  if (s != DeviceState::Ready) {
    const std::string why = reason();
    return makeError(name(), std::string("cannot enable: ") + stateName(s) + (why.empty() ? "" : " (" + why + ")"));
  }
  safety_.setLimits(spec().max_force_n, spec().max_torque_n_mm);
  safety_.enable();
  setState(DeviceState::Enabled);
  return Ok{};
}

void HapticDevice::disable() {
  safety_.disable();
  const DeviceState s = state();
  // A watchdog fault clears here; a backend's own fault (device gone) stays until it recovers.
  if (s == DeviceState::Enabled || (s == DeviceState::Fault && safety_.faulted())) setState(DeviceState::Ready);
}

SafetyLayer::Output HapticDevice::output(int64_t now_ns) {
  SafetyLayer::Output out = safety_.output(now_ns);
  if (out.gate == SafetyGate::Watchdog && state() == DeviceState::Enabled)
  {
    char why[128];
    std::snprintf(why, sizeof why, "watchdog: no force command for %.1f ms; zero force until the pen is enabled again",
                  safety_.params().watchdog_ms);
    setState(DeviceState::Fault, why);
  }
  return out;
}

}  // namespace dentsim::devices

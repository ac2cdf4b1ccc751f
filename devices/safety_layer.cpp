// SafetyLayer: clamp, ramp-up, watchdog and the process-wide stop between the haptic loop and a pen's motors.
#include "devices/safety_layer.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <unistd.h>

namespace dentsim::devices {
namespace {

std::atomic<bool> g_all_zero{false};
std::atomic<int> g_signals_seen{0};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

extern "C" void onDeviceSignal(int sig) {
  g_all_zero.store(true, std::memory_order_release);
  // A second signal means the program did not get out in time: leave now. The motors already
  // read zero from every output() since the first one.
  if (g_signals_seen.fetch_add(1, std::memory_order_acq_rel) >= 1) _exit(128 + sig);
}

// v scaled down to length at most `limit`, keeping its direction. True when it was cut.
bool clampLength(Vec3* v, double limit) {
  const double n = norm(*v);
  if (!(n <= limit)) {  // also catches NaN: a non-finite command never reaches a motor
    *v = std::isfinite(n) && n > 0 ? *v * (std::max(limit, 0.0) / n) : Vec3{};
    return true;
  }
  return false;
}

}  // namespace

const char* gateName(SafetyGate g) {
  switch (g) {
    case SafetyGate::Pass: return "pass";
    case SafetyGate::NotEnabled: return "not enabled";
    case SafetyGate::Disarmed: return "waiting for a small first command";
    case SafetyGate::Watchdog: return "watchdog";
    case SafetyGate::Stopping: return "stopping";
    case SafetyGate::OtherPen: return "the other pen faulted";
  }
  return "?";
}

SafetyLayer::SafetyLayer(const SafetyParams& params) : params_(params) {}

void SafetyLayer::setLimits(double max_force_n, double max_torque_n_mm) {
  max_force_n_.store(std::max(0.0, max_force_n), std::memory_order_release);
  max_torque_n_mm_.store(std::max(0.0, max_torque_n_mm), std::memory_order_release);
}

void SafetyLayer::enable() {
  faulted_.store(false, std::memory_order_release);
  enable_serial_.fetch_add(1, std::memory_order_acq_rel);
  enabled_.store(true, std::memory_order_release);
}

void SafetyLayer::disable() { enabled_.store(false, std::memory_order_release); }

void SafetyLayer::command(const Wrench& wrench, int64_t now_ns) { channel_.publish(wrench, now_ns); }

SafetyLayer::Output SafetyLayer::output(int64_t now_ns) {
  Output out;
  if (g_all_zero.load(std::memory_order_acquire)) {
    out.gate = SafetyGate::Stopping;
    return out;
  }
  if (!enabled_.load(std::memory_order_acquire)) {
    out.gate = SafetyGate::NotEnabled;
    return out;
  }
  if (group_ != nullptr && group_->halted()) {
    out.gate = SafetyGate::OtherPen;
    return out;
  }
  const uint32_t serial = enable_serial_.load(std::memory_order_acquire);
  if (serial != seen_serial_) {  // a fresh enable(): disarm and restart the watchdog's clock
    seen_serial_ = serial;
    armed_ = false;
    enabled_at_ns_ = now_ns;
  }
  if (faulted_.load(std::memory_order_acquire)) {
    out.gate = SafetyGate::Watchdog;
    return out;
  }
  const int64_t watchdog_ns = static_cast<int64_t>(params_.watchdog_ms * 1e6);
  // Read without the channel's own staleness: the watchdog decides here, from the stamp.
  ForceOutput::Command c = channel_.current(now_ns, INT64_MAX / 2);
  bool unread_newer = false;  // a newer command was published than the one this side last read
  if (c.busy) {
    // Being replaced right now: the previous command stands until it can be read. If the loop
    // published others since this side last read one, the newest complete stamp says how fresh
    // the loop is (so the watchdog does not fire early), but its force is not at hand: zero.
    c = last_read_;
    const int64_t published = channel_.lastStamp();
    if (published > c.stamp_ns && published != INT64_MIN) {
      c.stamp_ns = published;
      c.stale = false;
      unread_newer = true;
    }
  } else if (!c.stale) {
    last_read_ = c;
  }
  const int64_t fresh_since = c.stale ? enabled_at_ns_ : std::max(c.stamp_ns, enabled_at_ns_);
  if (now_ns - fresh_since > watchdog_ns) {
    faulted_.store(true, std::memory_order_release);
    haltGroup();
    out.gate = SafetyGate::Watchdog;
    return out;
  }
  // Nothing commanded within the watchdog: zero, though not yet a fault while the watchdog still
  // counts from enabling. Past the check above this only happens for a command from before
  // enabling; measured from enabled_at alone, such a command could go out up to twice the watchdog
  // old when the output side first ran late (what DeviceSafety.WatchdogOnAnOutputThread saw under
  // load: a 3.5 ms old command passed).
  if (c.stale || now_ns - c.stamp_ns > watchdog_ns) {
    out.gate = SafetyGate::Disarmed;
    return out;
  }
  if (unread_newer) {  // fresh, but unreadable for this one output: zero force, no fault
    out.gate = SafetyGate::Pass;
    return out;
  }
  Wrench w = c.wrench;
  if (!armed_) {
    if (!(norm(w.force) <= params_.arm_force_n)) {
      out.gate = SafetyGate::Disarmed;
      return out;
    }
    armed_ = true;
    armed_at_ns_ = now_ns;
  }
  const double max_force = max_force_n_.load(std::memory_order_acquire);
  const double ramp = params_.ramp_s > 0 ? std::clamp(double(now_ns - armed_at_ns_) * 1e-9 / params_.ramp_s, 0.0, 1.0) : 1.0;
  const double ceiling = std::min(max_force, params_.arm_force_n + (max_force - params_.arm_force_n) * ramp);
  const double torque_ceiling = max_torque_n_mm_.load(std::memory_order_acquire) * (max_force > 0 ? ceiling / max_force : 0.0);
  out.clamped = clampLength(&w.force, ceiling);
  out.clamped = clampLength(&w.moment, torque_ceiling) || out.clamped;
  out.wrench = w;
  out.gate = SafetyGate::Pass;
  return out;
}

void requestAllDevicesZero() { g_all_zero.store(true, std::memory_order_release); }
bool allDevicesZeroRequested() { return g_all_zero.load(std::memory_order_acquire); }
void clearAllDevicesZeroForTest() {
  g_all_zero.store(false, std::memory_order_release);
  g_signals_seen.store(0, std::memory_order_release);
}

void installDeviceSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onDeviceSignal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) sigaction(sig, &sa, nullptr);
}

}  // namespace dentsim::devices

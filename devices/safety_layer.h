// SafetyLayer: what every pen backend's force goes through on its way to the motors: clamp, ramp-up, watchdog, zero.
//
// The haptic thread command()s the wrench it wants; the device's output side (its USB thread, its
// vendor scheduler callback, or the same thread for a software pen) asks output() what to send.
// The answer is zero unless the device is enabled, the process has not been asked to stop (a
// signal), and the watchdog has not fired. Otherwise:
//   - clamp: |F| is limited to the device's maximum force and |M| to its maximum torque, each keeping
//     its direction (scaling, never per axis, so the student never feels a force turn sideways);
//   - ramp-up: after enable() nothing goes out until the loop sends a small command (|F| at most
//     arm_force_n): a pen enabled while the tool sits deep in the tooth must not kick. From that
//     command on, the force ceiling rises linearly from arm_force_n to the maximum over ramp_s;
//   - watchdog: a command older than watchdog_ms gives zero at once and latches a fault, which only
//     disable() + enable() clears. A stalled haptic loop can never leave the pen pushing.
// Lock-free: command() publishes through a ForceOutput (sequence lock, one writer); output() keeps
// its own state and is called from one thread at a time. Control-thread calls (enable, disable)
// reach the output side through atomics.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/rigid.h"
#include "core/force_output.h"

namespace dentsim::devices {

struct SafetyParams {
  double watchdog_ms = 3.0;   // a command older than this is stale: zero force and a latched fault
  double arm_force_n = 0.5;   // the first command after enable() must be at most this [N]
  double ramp_s = 0.5;        // then the ceiling rises from arm_force_n to the maximum over this [s]
};

// Why output() gave what it gave.
enum class SafetyGate : uint8_t {
  Pass,        // the command went out (clamped or ramped if `clamped`)
  NotEnabled,  // the device is not enabled (disabled, not homed, closed)
  Disarmed,    // enabled, but no small command yet
  Watchdog,    // no fresh command within watchdog_ms: latched fault
  Stopping,    // the process was asked to stop (signal, exit)
  OtherPen,    // another pen of the same student faulted (SafetyGroup): zero until the group is cleared
};
const char* gateName(SafetyGate g);

// The pens of one student: a fault on any of them (its watchdog, or its backend's error) zeroes
// every pen of the group from their next output() on, because the two hands work together: a
// drill that keeps pushing while the mirror hand has lost its pen is not a state to practise in.
// The group stays halted until clear() (the app clears it when a new segment starts). Lock-free:
// halt() may come from any pen's output thread, and from a signal-free servo callback.
class SafetyGroup {
 public:
  // Marks the group halted; the first member to halt it is remembered.
  void halt(int member) {
    int none = -1;
    first_.compare_exchange_strong(none, member, std::memory_order_acq_rel);
    halted_.store(true, std::memory_order_release);
  }
  bool halted() const { return halted_.load(std::memory_order_acquire); }
  int firstFault() const { return first_.load(std::memory_order_acquire); }  // -1: none
  void clear() {
    halted_.store(false, std::memory_order_release);
    first_.store(-1, std::memory_order_release);
  }

 private:
  std::atomic<bool> halted_{false};
  std::atomic<int> first_{-1};
};

class SafetyLayer {
 public:
  explicit SafetyLayer(const SafetyParams& params = {});

  // Control thread, before output runs or any time: the device's limits (torque 0: none rendered).
  void setLimits(double max_force_n, double max_torque_n_mm);
  void enable();    // arms the ramp anew and clears a latched watchdog fault
  void disable();   // zero from the next output() on
  // Control thread, before forces flow: this layer's pen is `member` of `group` (which outlives it).
  void joinGroup(SafetyGroup* group, int member) {
    group_ = group;
    member_ = member;
  }
  // Any thread: this pen failed; every pen of its group (if any) gives zero from its next output().
  void haltGroup() {
    if (group_ != nullptr) group_->halt(member_);
  }
  bool enabled() const { return enabled_.load(std::memory_order_acquire); }

  // Haptic thread: the wrench the loop wants rendered (device frame), stamped with now_ns.
  void command(const Wrench& wrench, int64_t now_ns);

  struct Output {
    Wrench wrench;              // what to send
    SafetyGate gate = SafetyGate::NotEnabled;
    bool clamped = false;       // the maximum or the ramp ceiling cut the command down
  };
  // Output side, one thread at a time: the wrench to send at now_ns.
  Output output(int64_t now_ns);
  // True once the watchdog has fired, until disable() + enable().
  bool faulted() const { return faulted_.load(std::memory_order_acquire); }
  const SafetyParams& params() const { return params_; }
  // Tests only: output() finds the haptic thread's command mid-publish until released.
  void holdCommandForTest(bool held) { channel_.holdPublishForTest(held); }

 private:
  SafetyParams params_;
  ForceOutput channel_;
  std::atomic<double> max_force_n_{0.0};
  std::atomic<double> max_torque_n_mm_{0.0};
  std::atomic<bool> enabled_{false};
  std::atomic<uint32_t> enable_serial_{0};  // bumped by enable(): the output side restarts its ramp
  std::atomic<bool> faulted_{false};
  // output side
  uint32_t seen_serial_ = 0;
  bool armed_ = false;
  int64_t enabled_at_ns_ = 0;  // the first output() after enable(): the watchdog counts from here or the latest command
  int64_t armed_at_ns_ = 0;
  // The newest command output() managed to read. A command found mid-publish (the haptic thread
  // preempted inside command()) is judged by this one instead, or by the newest complete publish's
  // stamp where that is newer (with zero force for that output): the watchdog fires when the loop
  // really has published nothing for too long, never earlier.
  ForceOutput::Command last_read_;
  SafetyGroup* group_ = nullptr;
  int member_ = -1;
};

// Process-wide stop: once requested (by a signal handler or at exit) every SafetyLayer outputs zero.
// Async-signal-safe: it only stores an atomic flag.
void requestAllDevicesZero();
bool allDevicesZeroRequested();
// Installs SIGINT, SIGTERM, SIGHUP and SIGQUIT handlers that call requestAllDevicesZero() and let
// the program finish its frame and close its devices; a second signal ends the process at once.
void installDeviceSignalHandlers();
// For tests: lets output() pass again after requestAllDevicesZero().
void clearAllDevicesZeroForTest();

}  // namespace dentsim::devices

// HapticDevice: the one interface every pen backend implements: state, spec, non-blocking reads, and writes through the safety layer.
//
// Threads. A control thread (the app's frame loop) calls open(), enable(), disable(), service()
// and close(). The haptic thread calls read() and command(), which never block, allocate or throw.
// A backend with its own I/O (a USB event thread, a vendor scheduler) asks output() for the wrench
// to send each time it talks to the motors; output() is the only way a backend gets a force, so
// every force passes the SafetyLayer (clamp, ramp-up, watchdog, zero when not enabled or stopping).
//
// Frames. Readings and commands are in the device's own frame and units: millimetres, newtons,
// newton-millimetres. DevicePen (device_pen.h) maps them into the tooth's world frame.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "devices/safety_layer.h"

namespace dentsim::devices {

enum class DeviceState : uint8_t {
  Disconnected,   // not found, unplugged, or closed
  NeedsFirmware,  // found, but its firmware is not loaded (and no firmware file was given)
  NeedsHoming,    // running, but the position is not known yet: the user must home or calibrate it
  Ready,          // reads are valid; no force goes out
  Enabled,        // reads are valid and forces go out through the safety layer
  Fault,          // an error (watchdog, USB error, device gone); zero force until re-enabled
};
const char* stateName(DeviceState s);
// Ready or Enabled: read() gives valid poses.
inline bool tracking(DeviceState s) { return s == DeviceState::Ready || s == DeviceState::Enabled; }

struct DeviceSpec {
  std::string model;                 // "Novint Falcon", "Touch", "virtual pen", ...
  double max_force_n = 0.0;          // the largest force it may be sent [N]; > 0
  double max_torque_n_mm = 0.0;      // the largest moment [N mm]; 0: the device renders none
  double max_stiffness_n_per_mm = 0.0;  // the stiffest spring it renders stably at its rate [N/mm]
  double max_damping_n_s_per_mm = 0.0;  // [N s/mm]
  Vec3 workspace_min_mm;             // the box the grip point reaches, device frame [mm]
  Vec3 workspace_max_mm;
  double rate_hz = 1000.0;           // the rate it is serviced at
  bool senses_rotation = false;      // read() reports the stylus' rotation (otherwise identity)
  bool physical = true;              // false for software pens: no motors, and time is loop time
};

struct DeviceReading {
  Pose pose;                 // the grip point [mm] and the stylus rotation, device frame
  Vec3 velocity;             // of the grip point [mm/s]
  Vec3 angular_velocity;     // [rad/s]
  uint32_t buttons = 0;      // button bits: bit 0 the main button
  bool has_pedal = false;    // software pens carry the pedal in their path; hardware pens do not
  double pedal = 0.0;        // [0, 1] where has_pedal
  int64_t stamp_ns = 0;      // when it was sampled: steady clock (physical) or loop time (software)
};

class HapticDevice {
 public:
  explicit HapticDevice(const SafetyParams& safety = {}) : safety_(safety) {}
  virtual ~HapticDevice() = default;
  HapticDevice(const HapticDevice&) = delete;
  HapticDevice& operator=(const HapticDevice&) = delete;

  // The name it was opened by ("falcon:0", "openhaptics:Default", "virtual", "replay:s.dses").
  virtual std::string name() const = 0;
  virtual const DeviceSpec& spec() const = 0;

  // Any thread.
  DeviceState state() const { return state_.load(std::memory_order_acquire); }
  // Why it is not enabled, in words the user can act on ("not homed: move the grip through its whole
  // range", "permission denied on /dev/bus/usb/001/004: install devices/70-dentsim.rules").
  std::string reason() const;

  // ---- control thread ----
  // Connects, loads firmware where needed, starts I/O. Afterwards the state is NeedsHoming, Ready or
  // (on error, also returned) Disconnected, NeedsFirmware or Fault.
  virtual Status open() = 0;
  // Ready -> Enabled: forces may go out (through the ramp). An error when the state is not Ready.
  virtual Status enable();
  // Enabled or Fault -> Ready (or stays where it is): zero force from the next output on.
  virtual void disable();
  // Zero force, stop I/O, Disconnected. Idempotent; the destructor of a backend calls it.
  virtual void close() = 0;
  // Called at frame rate: homing progress, hot-unplug and replug, watchdog faults surfacing.
  virtual void service() {}

  // ---- haptic thread: never block ----
  // The latest sample at loop time t_s. False when there is none (not tracking).
  virtual bool read(double t_s, DeviceReading* out) = 0;
  // The wrench the loop wants rendered, device frame, stamped now_ns (steady clock for physical
  // devices, loop time for software pens). Goes to the safety layer, never straight out.
  void command(const Wrench& wrench, int64_t now_ns) { safety_.command(wrench, now_ns); }

  const SafetyLayer& safety() const { return safety_; }
  // Control thread, before enabling: the pens of one student stand or fall together (SafetyGroup).
  void joinSafetyGroup(SafetyGroup* group, int member) { safety_.joinGroup(group, member); }

 protected:
  void setState(DeviceState s, std::string reason = {});
  // Output side: the only wrench a backend may send to its motors at now_ns. A watchdog fault found
  // here moves the device to Fault.
  SafetyLayer::Output output(int64_t now_ns);
  SafetyLayer& safetyLayer() { return safety_; }

 private:
  SafetyLayer safety_;
  std::atomic<DeviceState> state_{DeviceState::Disconnected};
  mutable std::mutex reason_mutex_;  // the reason string only; never taken on the haptic thread
  std::string reason_;
};

}  // namespace dentsim::devices

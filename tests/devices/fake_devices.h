// Fakes for the device tests: a pen whose motors, plug and homing the test controls, and a pedal it sets.
#pragma once

#include <atomic>
#include <mutex>
#include <vector>

#include "devices/foot_pedal.h"
#include "devices/haptic_device.h"

namespace dentsim::devices::test {

// A 3-DOF pen with a 10 N limit and a 100 mm cube workspace centred on its origin. The test moves
// the grip, unplugs and replugs it, and plays its output side with sendToMotors().
class FakePen final : public HapticDevice {
 public:
  explicit FakePen(const SafetyParams& safety = {}) : HapticDevice(safety) {
    spec_.model = "fake pen";
    spec_.max_force_n = 10.0;
    spec_.max_stiffness_n_per_mm = 2.0;
    spec_.max_damping_n_s_per_mm = 0.01;
    spec_.workspace_min_mm = {-50, -50, -50};
    spec_.workspace_max_mm = {50, 50, 50};
  }
  ~FakePen() override { FakePen::close(); }
  std::string name() const override { return "fake:0"; }
  const DeviceSpec& spec() const override { return spec_; }
  Status open() override {
    if (!plugged_) {
      setState(DeviceState::Disconnected, "not plugged in");
      return makeError(name(), "not plugged in");
    }
    setState(homed_ ? DeviceState::Ready : DeviceState::NeedsHoming, homed_ ? "" : "not homed");
    return Ok{};
  }
  void close() override {
    setState(DeviceState::Disconnected);  // first: from here on the safety layer gives zero
    sendToMotors(0);
  }
  bool read(double, DeviceReading* out) override {
    if (!plugged_.load() || !tracking(state())) return false;
    std::lock_guard lock(m_);
    *out = reading_;
    return true;
  }

  // ---- the test's side ----
  void setGrip(const Vec3& p, const Vec3& v = {}) {
    std::lock_guard lock(m_);
    reading_.pose.position = p;
    reading_.velocity = v;
  }
  void home() {
    homed_ = true;
    if (state() == DeviceState::NeedsHoming) setState(DeviceState::Ready);
  }
  void unplug() {
    plugged_ = false;
    homed_ = false;
    setState(DeviceState::Disconnected, "device gone");
  }
  void replug() {
    plugged_ = true;
    (void)open();
  }
  // What the output side sends at now_ns, and a record of it.
  SafetyLayer::Output sendToMotors(int64_t now_ns) {
    const SafetyLayer::Output o = output(now_ns);
    std::lock_guard lock(m_);
    sent_.push_back(o);
    return o;
  }
  std::vector<SafetyLayer::Output> sent() const {
    std::lock_guard lock(m_);
    return sent_;
  }

 private:
  DeviceSpec spec_;
  mutable std::mutex m_;
  DeviceReading reading_;
  std::vector<SafetyLayer::Output> sent_;
  std::atomic<bool> plugged_{true};
  std::atomic<bool> homed_{true};
};

// A pedal whose position the test sets.
class FakePedal final : public FootPedal {
 public:
  std::string name() const override { return "fake pedal"; }
  Status open() override {
    setState(DeviceState::Ready);
    return Ok{};
  }
  void close() override { setState(DeviceState::Disconnected); }
  double value() const override { return state() == DeviceState::Ready ? value_.load() : 0.0; }
  void press(double v) { value_ = v; }

 private:
  std::atomic<double> value_{0.0};
};

}  // namespace dentsim::devices::test

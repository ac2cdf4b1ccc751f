// DevicePen: a HapticDevice as the haptic loop's PenSource: device frame to the tooth's frame, the foot pedal, a frozen pen while the device is away.
//
// The loop reads pens in the world frame of the tooth [mm] and commands wrenches there; a device
// speaks in its own frame. The mapping puts the device's workspace around the tooth (a rigid
// placement and a scale: hand motion of 1 mm moves the tool `scale` mm). Forces are rotated back
// into the device frame and never scaled, so the student feels newtons as computed.
//
// Unplugged or faulted, a device gives no reading. The pen then stays frozen where it was last
// seen, at rest, and the session goes on: the loop keeps stepping (the other pen, the recording),
// this pen's force is zero (the safety layer sees no enabled device), and the turbine stops. When
// the device tracks again the pen moves on from wherever it is.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/pen_source.h"
#include "core/rigid.h"
#include "devices/foot_pedal.h"
#include "devices/haptic_device.h"

namespace dentsim::devices {

struct DeviceMapping {
  Pose device_in_world;   // the device frame's origin and axes in the tooth's world frame [mm]
  double scale = 1.0;     // world mm per device mm, > 0
  Quat tool_rotation;     // the tool's world rotation for pens that sense none (3-DOF)
};

class DevicePen final : public PenSource {
 public:
  // `pedal` (may be null) overrides any pedal the device carries. Both must outlive the pen.
  DevicePen(HapticDevice& device, const DeviceMapping& mapping, const FootPedal* pedal = nullptr);

  bool read(double t_s, PenReading* out) override;
  void display(const Wrench& wrench, double t_s) override;

  HapticDevice& device() { return device_; }
  bool frozen() const { return frozen_.load(std::memory_order_relaxed); }
  uint64_t frozenReads() const { return frozen_reads_.load(std::memory_order_relaxed); }
  const DeviceMapping& mapping() const { return mapping_; }

 private:
  HapticDevice& device_;
  DeviceMapping mapping_;
  const FootPedal* pedal_;
  bool seen_ = false;     // a reading has come at least once
  PenReading last_;       // the latest reading, world frame
  std::atomic<bool> frozen_{false};
  std::atomic<uint64_t> frozen_reads_{0};
};

// Where a device's workspace goes: its centre on `grip` (the tool's grip point at rest, world), its
// axes turned by `axes` (the app passes the camera's: the device's x right, y up and z toward the
// user then move the tool right, up and toward the viewer on screen), scaled so that the
// workspace's smallest side spans `reach_mm`. An unbounded workspace (a software pen) maps 1:1.
DeviceMapping mapWorkspace(const DeviceSpec& spec, const Pose& grip, double reach_mm, const Quat& axes = {});

}  // namespace dentsim::devices

// DevicePen: device readings into the tooth's frame, wrenches back into the device's, the pedal merged, a frozen pen on loss.
#include "devices/device_pen.h"

#include <algorithm>
#include <cmath>

#include "core/steady_clock.h"

namespace dentsim::devices {

DevicePen::DevicePen(HapticDevice& device, const DeviceMapping& mapping, const FootPedal* pedal)
    : device_(device), mapping_(mapping), pedal_(pedal) {}

bool DevicePen::read(double t_s, PenReading* out) {
  DeviceReading r;
  if (device_.read(t_s, &r)) {
    const Quat& q = mapping_.device_in_world.rotation;
    last_.grip.position = mapping_.device_in_world.apply(r.pose.position * mapping_.scale);
    last_.grip.rotation = device_.spec().senses_rotation ? (q * r.pose.rotation).normalized() : mapping_.tool_rotation;
    last_.velocity = q.rotate(r.velocity) * mapping_.scale;
    last_.angular_velocity = device_.spec().senses_rotation ? q.rotate(r.angular_velocity) : Vec3{};
    last_.buttons = r.buttons;
    last_.pedal = pedal_ ? pedal_->value() : (r.has_pedal ? r.pedal : 0.0);
    seen_ = true;
    frozen_.store(false, std::memory_order_relaxed);
    *out = last_;
    return true;
  }
  if (!seen_) return false;
  // Frozen: where it was, at rest, no buttons, and the turbine off.
  last_.velocity = {};
  last_.angular_velocity = {};
  last_.buttons = 0;
  last_.pedal = 0.0;
  frozen_.store(true, std::memory_order_relaxed);
  frozen_reads_.fetch_add(1, std::memory_order_relaxed);
  *out = last_;
  return true;
}

void DevicePen::display(const Wrench& wrench, double t_s) {
  const Quat back = mapping_.device_in_world.rotation.conjugate();
  const Wrench local{back.rotate(wrench.force), back.rotate(wrench.moment)};
  // Physical pens are stamped on the clock their output side reads; software pens on loop time.
  const int64_t now_ns = device_.spec().physical ? steadyNowNs() : std::llround(t_s * 1e9);
  device_.command(local, now_ns);
}

DeviceMapping mapWorkspace(const DeviceSpec& spec, const Pose& grip, double reach_mm, const Quat& axes) {
  DeviceMapping m;
  m.tool_rotation = grip.rotation;
  const Vec3 lo = spec.workspace_min_mm, hi = spec.workspace_max_mm;
  const double side = std::min({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const bool bounded = std::isfinite(side) && side > 0;
  m.scale = bounded && reach_mm > 0 ? reach_mm / side : 1.0;
  if (!bounded) return m;  // software pens already speak world coordinates
  const Vec3 centre = (lo + hi) * 0.5;
  m.device_in_world.rotation = axes;
  // The workspace's centre lands on the grip: grip = origin + axes (scale centre).
  m.device_in_world.position = grip.position - axes.rotate(centre * m.scale);
  return m;
}

}  // namespace dentsim::devices

// SoftwarePen: software pens as devices, on loop time, through the same safety layer as hardware.
#include "devices/software_pen.h"

#include <cmath>
#include <limits>

namespace dentsim::devices {

SoftwarePen::SoftwarePen(std::string name, std::unique_ptr<PenSource> source, DeviceSpec spec,
                         std::shared_ptr<const void> keep_alive, const SafetyParams& safety)
    : HapticDevice(safety), name_(std::move(name)), source_(std::move(source)), spec_(std::move(spec)),
      keep_alive_(std::move(keep_alive)) {}

Status SoftwarePen::open() {
  setState(DeviceState::Ready);
  return Ok{};
}

void SoftwarePen::close() { setState(DeviceState::Disconnected); }

bool SoftwarePen::read(double t_s, DeviceReading* out) {
  const int64_t now_ns = std::llround(t_s * 1e9);
  // The motors this pen does not have get what the safety layer lets out now.
  last_output_ = output(now_ns);
  source_->display(last_output_.wrench, t_s);
  if (!tracking(state())) return false;
  PenReading r;
  if (!source_->read(t_s, &r)) return false;
  out->pose = r.grip;
  out->velocity = r.velocity;
  out->angular_velocity = r.angular_velocity;
  out->buttons = r.buttons;
  out->has_pedal = true;
  out->pedal = r.pedal;
  out->stamp_ns = now_ns;
  return true;
}

DeviceSpec softwarePenSpec(const std::string& model, double max_force_n, double max_torque_n_mm) {
  DeviceSpec s;
  s.model = model;
  s.max_force_n = max_force_n;
  s.max_torque_n_mm = max_torque_n_mm;
  const double inf = std::numeric_limits<double>::infinity();
  s.max_stiffness_n_per_mm = inf;
  s.max_damping_n_s_per_mm = inf;
  s.workspace_min_mm = {-inf, -inf, -inf};
  s.workspace_max_mm = {inf, inf, inf};
  s.senses_rotation = true;
  s.physical = false;
  return s;
}

}  // namespace dentsim::devices

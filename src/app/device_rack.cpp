// The run's pens and pedal: made from their names, opened, enabled per segment, serviced per frame.
#include "app/device_rack.h"

#include "devices/device_registry.h"
#include "devices/software_pen.h"
#include "io/pen_playback.h"

namespace dentsim::app {

Status DeviceRack::checkNames() const {
  for (const std::string* pen : {&o_.drill_pen, &o_.mirror_pen}) {
    if (pen->empty() || (pen == &o_.mirror_pen && *pen == "none")) continue;
    if (auto name = devices::parsePenName(*pen); !name)
      return makeError(pen == &o_.drill_pen ? "drill pen" : "mirror pen", name.message());
  }
  if (Status st = devices::checkPedalName(o_.pedal); !st) return makeError("pedal", st.message());
  return Ok{};
}

Status DeviceRack::open(const PenPath* script, bool with_mirror, const RackPlacement& at, const DeviceParams& device_params,
                        bool lockstep) {
  // The pedal first: the drill's pen reads it.
  if (!o_.pedal.empty() && o_.pedal != "none") {
    auto pedal = devices::makePedal(o_.pedal);
    if (!pedal) return makeError("pedal", pedal.message());
    pedal_ = std::move(*pedal);
    if (Status st = pedal_->open(); !st) return makeError("pedal", st.message());
    shown_pedal_state_ = pedal_->state();
  }
  bool physical = false;
  for (PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    if (role == PenRole::Mirror && !with_mirror) continue;
    const size_t r = size_t(role);
    const std::string& chosen = role == PenRole::Drill ? o_.drill_pen : o_.mirror_pen;
    const std::string where = std::string(penRoleName(role)) + " pen";
    const Pose& start = role == PenRole::Drill ? at.drill_start : at.mirror_start;
    if (chosen.empty() && script) {
      std::unique_ptr<PenSource> source = std::make_unique<ScriptedPen>(*script, role);
      std::shared_ptr<const void> keep_alive;
      if (o_.script_hand) {
        // The hand holds the script's pen and gives way to what the safety layer lets out.
        auto scripted = std::shared_ptr<PenSource>(std::move(source));
        source = std::make_unique<YieldingHand>(*scripted, *o_.script_hand);
        keep_alive = scripted;
      }
      devices_[r] = std::make_unique<devices::SoftwarePen>(
          "script", std::move(source),
          devices::softwarePenSpec("pen script", device_params.max_force_n, device_params.max_torque_n_mm),
          std::move(keep_alive));
    } else {
      auto name = devices::parsePenName(chosen.empty() ? "virtual" : chosen);
      if (!name) return makeError(where, name.message());
      devices::PenContext pc;
      pc.role = role;
      pc.start_grip = start;
      pc.max_force_n = device_params.max_force_n;
      pc.max_torque_n_mm = device_params.max_torque_n_mm;
      pc.options = o_.backends;
      auto made = devices::makePen(*name, pc);
      if (!made) return makeError(where, made.message());
      devices_[r] = std::move(*made);
    }
    devices::HapticDevice& device = *devices_[r];
    device.joinSafetyGroup(&hands_, int(r));
    if (Status st = device.open(); !st) return makeError(where, st.message());
    shown_state_[r] = device.state();
    if (device.state() != devices::DeviceState::Ready)
      note_(where + " " + device.name() + ": " + devices::stateName(device.state()) + " (" + device.reason() + ")");
    physical = physical || device.spec().physical;
    if (auto* sw = dynamic_cast<devices::SoftwarePen*>(&device)) virtual_[r] = dynamic_cast<devices::VirtualPen*>(&sw->source());
    pens_[r] = std::make_unique<devices::DevicePen>(device, devices::mapWorkspace(device.spec(), start, o_.backends.reach_mm, at.screen),
                                                    role == PenRole::Drill ? pedal_.get() : nullptr);
  }
  if (physical) {
    if (lockstep) return makeError("run", "a hardware pen needs the real-time haptic thread: drop --headless and --lockstep");
    // Ctrl-C and friends zero every pen at once; the frame loop then ends the run cleanly.
    devices::installDeviceSignalHandlers();
  }
  return Ok{};
}

void DeviceRack::enable() {
  // A new segment: a pen that faulted in the last one no longer holds the other at zero.
  hands_.clear();
  hands_told_ = false;
  for (auto& d : devices_) {
    if (!d) continue;
    if (d->state() == devices::DeviceState::Fault) d->disable();  // a watchdog fault clears on a new segment
    if (d->state() != devices::DeviceState::Ready) continue;
    if (Status st = d->enable(); !st) note_(st.message());
  }
}

void DeviceRack::disable() {
  for (auto& d : devices_)
    if (d) d->disable();
}

bool DeviceRack::service(bool loop_running) {
  const bool zero = devices::allDevicesZeroRequested();
  if (zero && !zero_told_) {
    note_("dentsim: stopping on a signal; every pen's force is zero");
    zero_told_ = true;
  }
  for (size_t r = 0; r < devices_.size(); ++r) {
    devices::HapticDevice* d = devices_[r].get();
    if (!d) continue;
    d->service();
    // A pen back from an unplug (replugged and homed) takes force again while the loop runs.
    if (loop_running && !hands_.halted() && d->state() == devices::DeviceState::Ready)
      if (Status st = d->enable(); !st) note_(st.message());
    const devices::DeviceState now = d->state();
    // Ready and Enabled are the usual states; a pen leaving them or coming back is news.
    if (now != shown_state_[r] && !(devices::tracking(now) && devices::tracking(shown_state_[r]))) {
      const std::string why = d->reason();
      note_(std::string(penRoleName(PenRole(r))) + " pen " + d->name() + ": " + devices::stateName(now) +
            (why.empty() ? "" : " (" + why + ")"));
      if (pen_change_) pen_change_(PenRole(r), devices::stateName(now), why);
    }
    shown_state_[r] = now;
  }
  if (hands_.halted() && !hands_told_ && devices_[0] && devices_[1]) {
    const int first = hands_.firstFault();
    if (first == 0 || first == 1)
      note_(std::string(penRoleName(PenRole(first))) + " pen failed: both pens' forces are zero until the next segment");
    hands_told_ = true;
  }
  if (pedal_) {
    pedal_->service();
    if (pedal_->state() != shown_pedal_state_) {
      shown_pedal_state_ = pedal_->state();
      const std::string why = pedal_->reason();
      note_("pedal " + pedal_->name() + ": " + devices::stateName(shown_pedal_state_) + (why.empty() ? "" : " (" + why + ")"));
    }
  }
  return zero;
}

void DeviceRack::close() {
  for (auto& d : devices_)
    if (d) d->close();
  if (pedal_) pedal_->close();
}

}  // namespace dentsim::app

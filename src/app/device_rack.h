// The pens and the pedal of a run: which devices, opening them, force on and off with the segments, and their news every frame.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/result.h"
#include "core/rigid.h"
#include "core/pen_source.h"
#include "devices/device_options.h"
#include "devices/device_pen.h"
#include "devices/foot_pedal.h"
#include "devices/haptic_device.h"
#include "devices/virtual_pen.h"
#include "io/pen_path_file.h"
#include "sim/sim_params.h"
#include "sim/yielding_hand.h"

namespace dentsim::app {

// Every option of the devices, in one place: `run` fills it from the command line.
struct DeviceRackOptions {
  // The pens' devices (devices/device_registry.h): "virtual", "falcon:0", "openhaptics:Default",
  // "script:FILE", "replay:FILE". Empty: the pen script where there is one, else the virtual pen.
  // The mirror's "none" means no mirror at all.
  std::string drill_pen;
  std::string mirror_pen;
  std::string pedal;              // "none", "hid[:...]"; empty: none (the script, the wheel or keys set the speed)
  devices::DeviceOptions backends;  // the backends' own options (the Falcon's firmware, ...) and the pens' reach
  std::optional<HandSettings> script_hand;  // a pen script is held by a hand that gives way to the force; none: rigid
};

// Where the pens start, and how the screen is turned: a hardware pen's workspace is mapped around
// its tool's start, turned with the camera.
struct RackPlacement {
  Pose drill_start, mirror_start;
  Quat screen;
};

class DeviceRack {
 public:
  using Note = std::function<void(const std::string&)>;  // tells the user (terminal and status line)
  // A pen's device changed state: which pen, its new state's name and the reason (for the session).
  using PenChange = std::function<void(PenRole, const std::string& state, const std::string& reason)>;
  DeviceRack(DeviceRackOptions options, Note note) : o_(std::move(options)), note_(std::move(note)) {}
  DeviceRack(const DeviceRack&) = delete;
  DeviceRack& operator=(const DeviceRack&) = delete;

  // The names alone, before anything loads, so that a mistyped pen or pedal fails at once.
  Status checkNames() const;
  // Opens the pedal, then the pens (the mirror's only `with_mirror`). A pen with no device named
  // plays `script` when there is one. A hardware pen needs the real-time haptic thread: with
  // `lockstep` it is an error.
  Status open(const PenPath* script, bool with_mirror, const RackPlacement& at, const DeviceParams& device, bool lockstep);

  PenSource* pen(PenRole role) const { return pens_[size_t(role)].get(); }
  devices::VirtualPen* virtualPen(PenRole role) const { return virtual_[size_t(role)]; }
  bool hasPedal() const { return pedal_ != nullptr; }
  bool hasVirtualPen() const { return virtual_[0] || virtual_[1]; }

  // Where pen state changes go besides the note (the app records them in the session).
  void onPenChange(PenChange sink) { pen_change_ = std::move(sink); }

  // Force on at a segment's start (the watchdog counts from here), off before its loop stops.
  void enable();
  void disable();
  // Every frame: reconnections, and a pen or the pedal changing state is news. `loop_running`:
  // a pen back from an unplug takes force again, unless the other pen faulted in this segment
  // (both pens stay at zero until the next segment: the student's hands work together). Returns true when a signal asked every pen for zero force.
  bool service(bool loop_running);
  void close();  // once, at the run's end

 private:
  DeviceRackOptions o_;
  Note note_;
  PenChange pen_change_;
  // The two pens are one student's hands: a fault on either zeroes both (devices::SafetyGroup).
  // Declared before the devices, whose safety layers point at it.
  devices::SafetyGroup hands_;
  bool hands_told_ = false;  // the "both pens at zero" line was shown for this halt
  std::array<std::unique_ptr<devices::HapticDevice>, 2> devices_;
  std::array<std::unique_ptr<devices::DevicePen>, 2> pens_;
  std::array<devices::VirtualPen*, 2> virtual_{};  // into devices_, where a pen is virtual
  std::array<devices::DeviceState, 2> shown_state_{};
  std::unique_ptr<devices::FootPedal> pedal_;
  devices::DeviceState shown_pedal_state_ = devices::DeviceState::Disconnected;
  bool zero_told_ = false;
};

}  // namespace dentsim::app

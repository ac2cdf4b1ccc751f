// VirtualPen: the mouse and keyboard as a pen: a lock-free, critically damped follower of targets the UI thread sets.
//
// Threads. Exactly one UI thread calls the setters; exactly one haptic thread calls read(). They
// share only a TripleBuffer of commands: the UI publishes its whole command after every change, and
// read() takes the newest one without waiting. SoftwarePen (software_pen.h) puts it behind the
// HapticDevice interface as the "virtual" backend; ui::PenInput turns window events into targets.
//
// Smoothing. A mouse moves the target in jumps (one per event, 60..1000 Hz, often several mm). Fed
// straight to the coupling, a jump would be an impulse: a huge velocity for one step and a kick in
// the force. So read() runs a critically damped follower, x'' = w^2 (target - x) - 2 w x', with
// w = 1 / follow_time_s, and reports the follower. Each read() integrates it exactly over the time
// since the previous read, taking the target to move linearly from the previous command to the new
// one over that step. This never overshoots, is stable for any step, answers a jump D with a speed
// of at most D w / e, and tracks a target moving at a steady speed c with exactly speed c, a lag of
// 2 c / w behind it. The rotation follows the same law on the rotation vector of (follower *
// target^-1) in the world frame: exact for rotations about a fixed axis, a linearisation otherwise.
#pragma once

#include <cstdint>

#include "core/pen_source.h"
#include "core/rigid.h"
#include "core/triple_buffer.h"

namespace dentsim::devices {

struct VirtualPenParams {
  double follow_time_s = 0.004;  // 1 / w of the follower [s], > 0: the lag per unit speed is twice this
};

class VirtualPen final : public PenSource {
 public:
  // The pen starts at `grip` (the grip frame, as in sim/tool_library.h), at rest, pedal up.
  explicit VirtualPen(const Pose& grip = {}, const VirtualPenParams& params = {});

  // ---- UI thread ----
  void setTarget(const Pose& grip);    // where the pen should go; the rotation is normalized
  void setButtons(uint32_t buttons);   // button bits, passed through unsmoothed
  void setPedal(double pedal);         // turbine command, clamped to [0, 1], passed through unsmoothed
  void reset(const Pose& grip);        // puts target and follower at grip, at rest (no glide there)
  const Pose& target() const { return command_.grip; }  // the latest target set
  uint32_t buttons() const { return command_.buttons; }
  double pedal() const { return command_.pedal; }

  // ---- haptic thread ----
  // The follower at loop time t_s [s], stepped from the previous read. Never blocks or allocates;
  // always true. The first read, a read after reset(), and a read whose t_s runs backward put the
  // follower on the target at rest.
  bool read(double t_s, PenReading* out) override;

 private:
  struct Command {
    Pose grip;                 // target grip frame [mm]
    uint32_t buttons = 0;      // button bits
    double pedal = 0.0;        // [0, 1]
    uint32_t reset_count = 0;  // bumped by reset(): the follower jumps instead of gliding
  };
  void publish();

  const double omega_;            // follower rate w [1/s]
  // UI side
  Command command_;               // the UI thread's copy, published whole after every change
  TripleBuffer<Command> channel_; // UI -> haptic
  // haptic side
  bool started_ = false;          // the follower has a state
  uint32_t reset_seen_ = 0;       // reset_count of the last command read
  double last_t_s_ = 0.0;         // time of the last read [s]
  Pose last_target_;              // target at the last read
  Pose follower_;                 // the follower's grip frame
  Vec3 velocity_;                 // [mm/s]
  Vec3 angular_velocity_;         // [rad/s]
};

}  // namespace dentsim::devices

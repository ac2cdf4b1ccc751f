// ScriptedPen and ReplayPen: a timed pen path and a recorded session played as pens (core/pen_source.h), with no hardware.
//
// They live beside the files they play, so that the loop (sim) and the registry of pens
// (devices/) both use them without one depending on the other; the scripted pen lets every test
// and benchmark drill without a device.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/pen_source.h"
#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "io/session_file.h"

namespace dentsim {

// Plays one pen's samples from a pen path: position interpolated linearly and rotation by slerp
// between samples, velocities from the segment, buttons and pedal held from the latest sample.
// Before the first sample it holds the first; after the last, the last, at rest.
class ScriptedPen final : public PenSource {
 public:
  // Takes the samples of `role` from the path (there may be none: read() then returns false).
  ScriptedPen(const PenPath& path, PenRole role);

  bool read(double t_s, PenReading* out) override;
  void display(const Wrench& wrench, double t_s) override;

  double endTime() const;                     // time of the last sample [s]; 0 when empty
  const Wrench& lastDisplayed() const { return last_; }  // the latest wrench the loop sent

 private:
  std::vector<PenSample> samples_;  // this pen's samples, in time order
  size_t cursor_ = 0;               // segment of the last read: reads move forward in time mostly
  Wrench last_;
};

// Plays one pen of a recorded session: the n-th read() returns exactly the reading the loop consumed
// at the session's n-th step (none where the pen had none, and none past the end), whatever the
// time asked. The loop reads each attached pen once a step, so a replay from the session's first
// step feeds every step the reading it had.
class ReplayPen final : public PenSource {
 public:
  // Keeps a view: `steps` must outlive the pen.
  ReplayPen(std::span<const SessionStep> steps, PenRole role) : steps_(steps), role_(size_t(role)) {}

  bool read(double t_s, PenReading* out) override;
  size_t position() const { return next_; }  // steps read so far

 private:
  std::span<const SessionStep> steps_;
  size_t role_;
  size_t next_ = 0;
};

}  // namespace dentsim

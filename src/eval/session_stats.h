// Session statistics that the scores take from a recorded session: elapsed time, contact samples, force and tilt errors.
#pragma once

#include <cstdint>

#include "eval/task.h"
#include "io/session_file.h"

namespace dentsim {

// What a session contributes to a score. A sample is one haptic step.
struct SessionStats {
  double rate_hz = 0.0;           // the loop rate the session ran at [Hz]
  uint64_t steps = 0;             // step records in the file
  uint64_t lost_steps = 0;        // steps the recorder dropped (gaps); they ran, but their readings are unknown
  double elapsed_s = 0.0;         // (steps + lost_steps) / rate_hz: the whole recorded session [s]
  uint64_t contact_samples = 0;   // steps whose drill reading has contacts > 0
  uint64_t force_over = 0;        // contact samples with |drill force| > task.force_error_n
  uint64_t parallel_over = 0;     // contact samples with the bur tilted > cavity.parallel_error_deg off the axis
  double max_force_n = 0.0;       // largest |drill force| over contact samples [N]
  double mean_force_n = 0.0;      // mean |drill force| over contact samples [N]; 0 without any
  double max_tilt_deg = 0.0;      // largest tilt from task.insertion_axis over contact samples [deg]
};

// The bur's tilt from `axis` (unit) [deg], in [0, 180]: the angle between the drill grip frame's +z
// (the tip points along -z) and the axis.
double burTiltDeg(const Pose& grip, const Vec3& axis);

// Counts over the whole recording. A step without a drill reading is not in contact. The tilt is
// measured against task.insertion_axis for either kind of task (a caries task reports it too).
SessionStats sessionStats(const SessionRecording& session, const Task& task);

}  // namespace dentsim

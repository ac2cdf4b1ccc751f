// Session statistics: one pass over the recorded steps.
#include "eval/session_stats.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dentsim {

namespace {
constexpr size_t kDrill = 0;  // PenRole::Drill's index in SessionStep's arrays
}  // namespace

double burTiltDeg(const Pose& grip, const Vec3& axis) {
  const Vec3 bur = grip.rotation.rotate(Vec3{0, 0, 1});
  // atan2 of |a x b| and a.b stays exact for small angles, where acos of the dot loses digits.
  return std::atan2(norm(cross(bur, axis)), dot(bur, axis)) * (180.0 / std::numbers::pi);
}

SessionStats sessionStats(const SessionRecording& session, const Task& task) {
  SessionStats s;
  s.rate_hz = session.info.rate_hz;
  s.steps = session.steps.size();
  for (const SessionGap& g : session.gaps) s.lost_steps += g.steps;
  s.elapsed_s = s.rate_hz > 0 ? double(s.steps + s.lost_steps) / s.rate_hz : 0.0;
  for (const SessionStep& step : session.steps) {
    if (!step.hasReading(kDrill) || step.contacts[kDrill] == 0) continue;
    ++s.contact_samples;
    const double force = norm(step.force_n[kDrill]);
    if (force > task.force_error_n) ++s.force_over;
    const double tilt = burTiltDeg(step.reading[kDrill].grip, task.insertion_axis);
    if (tilt > task.cavity.parallel_error_deg) ++s.parallel_over;
    s.max_force_n = std::max(s.max_force_n, force);
    s.mean_force_n += force;
    s.max_tilt_deg = std::max(s.max_tilt_deg, tilt);
  }
  if (s.contact_samples > 0) s.mean_force_n /= double(s.contact_samples);
  return s;
}

}  // namespace dentsim

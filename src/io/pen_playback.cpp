// ScriptedPen and ReplayPen: a pen path interpolated, and a recorded session played back, for the haptic loop.
#include "io/pen_playback.h"

namespace dentsim {

ScriptedPen::ScriptedPen(const PenPath& path, PenRole role) {
  for (const PenSample& s : path.samples)
    if (s.pen == role) samples_.push_back(s);
}

double ScriptedPen::endTime() const { return samples_.empty() ? 0.0 : samples_.back().t_s; }

bool ScriptedPen::read(double t_s, PenReading* out) {
  if (samples_.empty()) return false;
  // The segment [cursor_, cursor_+1] that holds t_s; reads usually move forward a little.
  if (cursor_ >= samples_.size() || samples_[cursor_].t_s > t_s) cursor_ = 0;
  while (cursor_ + 1 < samples_.size() && samples_[cursor_ + 1].t_s <= t_s) ++cursor_;
  const PenSample& a = samples_[cursor_];
  *out = PenReading{};
  out->buttons = a.buttons;
  out->pedal = a.pedal;
  if (t_s <= a.t_s || cursor_ + 1 >= samples_.size()) {
    out->grip = a.pose;
    return true;
  }
  const PenSample& b = samples_[cursor_ + 1];
  const double span = b.t_s - a.t_s;
  const double u = span > 0 ? (t_s - a.t_s) / span : 1.0;
  out->grip.position = a.pose.position + (b.pose.position - a.pose.position) * u;
  out->grip.rotation = slerp(a.pose.rotation, b.pose.rotation, u);
  if (span > 0) {
    out->velocity = (b.pose.position - a.pose.position) / span;
    out->angular_velocity = (b.pose.rotation * a.pose.rotation.conjugate()).rotationVector() / span;
  }
  return true;
}

void ScriptedPen::display(const Wrench& wrench, double t_s) {
  (void)t_s;
  last_ = wrench;
}

bool ReplayPen::read(double t_s, PenReading* out) {
  (void)t_s;
  if (next_ >= steps_.size()) return false;
  const SessionStep& s = steps_[next_++];
  if (!s.hasReading(role_)) return false;
  const SessionPenReading& r = s.reading[role_];
  *out = PenReading{};
  out->grip = r.grip;
  out->velocity = r.velocity;
  out->angular_velocity = r.angular_velocity;
  out->buttons = r.buttons;
  out->pedal = r.pedal;
  return true;
}

}  // namespace dentsim

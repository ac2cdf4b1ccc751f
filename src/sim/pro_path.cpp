// ProPath: sampling a session's pens into tool poses through the coupling's springs, interpolation and the nearest pose.
#include "sim/pro_path.h"

#include <algorithm>
#include <cmath>

#include "sim/sim_params.h"

namespace dentsim {

namespace {

// Where the tool's grip stood, from the pen's reading and the wrench the coupling rendered:
// the rendered force is k (tool - pen), the moment k_rot rotvec(tool * pen^-1), damping aside.
Pose toolGrip(const SessionPenReading& pen, const Vec3& force, const CouplingParams& k) {
  Pose grip = pen.grip;
  if (k.stiffness_n_per_mm > 0) grip.position += force / k.stiffness_n_per_mm;
  return grip;
}

Pose lerpPose(const Pose& a, const Pose& b, double u) {
  return {a.position + (b.position - a.position) * u, slerp(a.rotation, b.rotation, u)};
}

}  // namespace

Result<ProPath> ProPath::fromSession(const SessionRecording& session, const std::string& where) {
  auto params = parseSimParams(session.info.params_json, where + ": parameters");
  if (!params) return params.error();
  const CouplingParams& k = params->coupling;
  const double rate = session.info.rate_hz > 0 ? session.info.rate_hz : 1000.0;
  const auto stride = std::max<uint64_t>(1, uint64_t(std::llround(kSampleEveryS * rate)));
  const uint64_t first_gap = session.gaps.empty() ? UINT64_MAX : session.gaps.front().first_step;

  ProPath path;
  path.drill_tool_ = session.info.drill_tool;
  path.mirror_tool_ = session.info.mirror_tool;
  path.task_ = session.info.task;
  path.tooth_hash_ = session.info.tooth_hash;
  ProPose held;
  bool any_drill = false;
  for (const SessionStep& s : session.steps) {
    if (s.step >= first_gap) break;
    held.drill_held = s.hasReading(0);
    held.mirror_held = s.hasReading(1);
    if (held.drill_held) {
      held.drill = toolGrip(s.reading[0], s.force_n[0], k);
      any_drill = true;
    }
    if (held.mirror_held) held.mirror = toolGrip(s.reading[1], s.force_n[1], k);
    if (s.step % stride != 0 || !any_drill) continue;
    held.t_s = double(s.step) / rate;
    path.poses_.push_back(held);
  }
  if (path.poses_.empty()) return makeError(where, "the session has no drill reading to follow");
  return path;
}

ProPose ProPath::at(double t_s) const {
  if (poses_.empty()) return {};
  if (!(t_s > poses_.front().t_s)) return poses_.front();
  if (t_s >= poses_.back().t_s) return poses_.back();
  const auto it = std::upper_bound(poses_.begin(), poses_.end(), t_s,
                                   [](double t, const ProPose& p) { return t < p.t_s; });
  const ProPose& b = *it;
  const ProPose& a = *(it - 1);
  const double u = (t_s - a.t_s) / (b.t_s - a.t_s);
  ProPose out = u < 0.5 ? a : b;  // the readings' flags from the nearer sample
  out.t_s = t_s;
  out.drill = lerpPose(a.drill, b.drill, u);
  out.mirror = lerpPose(a.mirror, b.mirror, u);
  return out;
}

size_t ProPath::nearestDrill(const Vec3& p, size_t from, size_t window) const {
  if (poses_.empty()) return 0;
  from = std::min(from, poses_.size() - 1);
  const size_t end = window == 0 ? poses_.size() : std::min(poses_.size(), from + window);
  size_t best = from;
  double best_d2 = dot(poses_[from].drill.position - p, poses_[from].drill.position - p);
  for (size_t i = from + 1; i < end; ++i) {
    const Vec3 d = poses_[i].drill.position - p;
    const double d2 = dot(d, d);
    if (d2 < best_d2) {
      best_d2 = d2;
      best = i;
    }
  }
  return best;
}

}  // namespace dentsim

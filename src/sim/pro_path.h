// ProPath: a professional's recorded session as a path the student's run can follow, the poses the ghost shows and the line the guide's spring pulls toward.
//
// A session records what each pen read and the force it was told to render, not where the tool
// itself stood. The tool is the coupling's other end: with the coupling's spring k and the
// rendered force F, the tool's grip stood at the pen's grip plus F / k (and turned by M / k_rot).
// That ignores the coupling's damping (a fraction of a millimetre at drilling speeds) and is exact
// whenever the force was not clamped; it saves replaying the professional's whole cut on the
// student's tooth just to know where the bur was.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "io/session_file.h"

namespace dentsim {

// One moment of the professional's session.
struct ProPose {
  double t_s = 0.0;          // loop time in the professional's session [s]
  Pose drill;                // the drill's grip frame where its tool stood [mm]
  Pose mirror;               // the mirror's grip frame where its tool stood [mm]
  bool drill_held = false;   // the drill pen gave a reading (else the pose is the last one held)
  bool mirror_held = false;
};

class ProPath {
 public:
  static constexpr double kSampleEveryS = 0.01;  // poses kept: 100 a second of the session

  // The path of `session`'s pens, sampled every kSampleEveryS up to its first gap. Errors (one
  // line naming `where`): a parameter set that does not parse, no drill reading at all.
  static Result<ProPath> fromSession(const SessionRecording& session, const std::string& where);

  bool empty() const { return poses_.empty(); }
  const std::vector<ProPose>& poses() const { return poses_; }
  double durationS() const { return poses_.empty() ? 0.0 : poses_.back().t_s; }
  const std::string& drillTool() const { return drill_tool_; }
  const std::string& mirrorTool() const { return mirror_tool_; }  // empty: the session had no mirror
  const std::string& task() const { return task_; }
  const std::string& toothHash() const { return tooth_hash_; }  // the tooth the professional cut

  // The pose at loop time t_s, interpolated between the samples (position linearly, rotation by
  // slerp); before the start the first pose, after the end the last.
  ProPose at(double t_s) const;
  // The index of the pose whose drill grip point is nearest to `p` among poses [from, from + window)
  // (window 0: to the end). Ties go to the earlier pose, so a path that passes a point twice
  // answers with its first pass from `from`.
  size_t nearestDrill(const Vec3& p, size_t from = 0, size_t window = 0) const;

 private:
  std::vector<ProPose> poses_;
  std::string drill_tool_, mirror_tool_, task_, tooth_hash_;
};

}  // namespace dentsim

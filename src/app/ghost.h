// The professional's ghost in `dentsim run`: a recorded session's drill and mirror, posed by loop time or beside the student's bur, for the renderer to draw translucent.
//
// The ghost is drawn only: it never enters the haptic loop, so it can neither cut the tooth nor
// push the student's pen. Its poses come from sim/pro_path.h (the tools where they stood, from the
// pens' readings and the forces the coupling rendered).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "render/scene_renderer.h"
#include "sim/pro_path.h"
#include "sim/sim_params.h"
#include "volume/brick_volume.h"

namespace dentsim::app {

// How the ghost moves: with the student's task time, or standing where the professional's bur
// came nearest to the student's.
enum class GhostFollow { Time, Nearest };

inline constexpr const char* kGhostFollowNames[] = {"time", "nearest"};
std::optional<GhostFollow> parseGhostFollow(const std::string& name);

class Ghost {
 public:
  // Nearest follow looks this far along the professional's path from its last answer [s]: far
  // enough to keep up with a student who works faster, near enough that a path crossing itself
  // later does not pull the ghost ahead.
  static constexpr double kNearestWindowS = 2.0;

  // The session at `path`, its path and its own tools' grip points (the professional's bur, which
  // may not be the student's). Errors: one line naming the file (unreadable, not a session, no
  // drill reading, a tool the simulator does not know).
  static Result<Ghost> load(const std::string& path, const PointShellParams& spacing);

  const std::string& source() const { return source_; }
  const ProPath& path() const { return path_; }
  // A warning when the session started on another tooth than `initial` (the ghost still shows,
  // but its cut is not this tooth's); empty when the same.
  std::string toothWarning(const ToothVolume& initial) const;

  // A new segment: nearest follow starts again from the professional's start.
  void restart() { nearest_ = 0; }
  // Time follow: the professional's pose at `task_time_s` since the segment's start.
  void followTime(double task_time_s);
  // Nearest follow: the pose nearest the student's drill grip (tool frame `student_tool` with
  // grip point `student_grip_local`), searched forward from the last answer.
  void followNearest(const Pose& student_tool, const Vec3& student_grip_local);

  // The ghost's tool frames (ProPose's grips turned into the frames the renderer draws) in `frame`.
  void show(render::FrameState& frame, float opacity) const;

 private:
  std::string source_;
  ProPath path_;
  Vec3 drill_grip_local_, mirror_grip_local_;
  std::string tooth_hash_;
  ProPose now_;
  size_t nearest_ = 0;
};

}  // namespace dentsim::app

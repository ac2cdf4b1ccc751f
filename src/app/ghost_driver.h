// GhostDriver: the professional's session as the ghost follows it, read once with the warnings it earns on this run's tooth, then posed by task time or beside the student's bur; nothing drawn, so it is tested without a window.
//
// The simulator reads a ghost in two places (--ghost at set-up, the task's ideal when the panel
// first shows it); both go through load(), so both warn alike. app/ghost.h turns the pose into the
// frames the renderer draws.
//
// Header-only because the app tests link sim, volume and io but none of the dentsim binary's own
// sources; everything here comes from those three.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "io/session_file.h"
#include "sim/pro_path.h"
#include "sim/sim_params.h"
#include "sim/tool_library.h"
#include "volume/brick_volume.h"
#include "volume/volume_hash.h"

namespace dentsim::app {

class GhostDriver {
 public:
  // Nearest follow looks this far along the professional's path from its last answer [s]: far
  // enough to keep up with a student who works faster, near enough that a path crossing itself
  // later does not pull the ghost ahead.
  static constexpr double kNearestWindowS = 2.0;

  // The session at `path`, its path and its own tools' grip points (the professional's bur, which
  // may not be the student's), with the warnings it earns against `initial`, this run's starting
  // tooth. Errors: one line naming the file (unreadable, not a session, no drill reading, a tool
  // the simulator does not know).
  static Result<GhostDriver> load(const std::string& path, const PointShellParams& spacing, const ToothVolume& initial);

  const std::string& source() const { return source_; }  // the path it was read from
  const ProPath& path() const { return path_; }
  // One line each, for the terminal and the panel: the session started on another tooth than this
  // run's (the ghost still shows, but its cut is not this tooth's). Empty: nothing to say.
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Vec3& drillGripLocal() const { return drill_grip_local_; }    // the professional's drill [mm, tool frame]
  const Vec3& mirrorGripLocal() const { return mirror_grip_local_; }  // zero when the session had no mirror
  const ProPose& now() const { return now_; }  // the pose the last follow chose; the start's after load

  // A new segment: nearest follow starts again from the professional's start.
  void restart() { nearest_ = 0; }
  // Time follow: the professional's pose at `task_time_s` since the segment's start [s].
  const ProPose& followTime(double task_time_s);
  // Nearest follow: the pose nearest the student's drill grip (tool frame `student_tool` with grip
  // point `student_grip_local` [mm]), searched forward from the last answer.
  const ProPose& followNearest(const Pose& student_tool, const Vec3& student_grip_local);

 private:
  std::string source_;
  ProPath path_;
  std::vector<std::string> warnings_;
  Vec3 drill_grip_local_, mirror_grip_local_;
  ProPose now_;
  size_t nearest_ = 0;  // index into path_.poses() of nearest follow's last answer
};

// ---------------------------------------------------------------------------------------------
// Details

inline Result<GhostDriver> GhostDriver::load(const std::string& path, const PointShellParams& spacing,
                                             const ToothVolume& initial) {
  auto session = readSessionFile(path);
  if (!session) return session.error();
  auto pro = ProPath::fromSession(*session, path);
  if (!pro) return pro.error();
  GhostDriver g;
  g.source_ = path;
  // Only the grip points are needed; the point shells the models carry are the haptic loop's.
  auto drill = loadToolModel(pro->drillTool(), spacing);
  if (!drill) return makeError(path, "the professional's drill: " + drill.message());
  g.drill_grip_local_ = drill->grip_local;
  if (!pro->mirrorTool().empty()) {
    auto mirror = loadToolModel(pro->mirrorTool(), spacing);
    if (!mirror) return makeError(path, "the professional's mirror: " + mirror.message());
    g.mirror_grip_local_ = mirror->grip_local;
  }
  // A session without a tooth hash (hand-made) cannot be told apart, so it earns no warning.
  const std::string& recorded = session->info.tooth_hash;
  if (const std::string hash = volumeHashHex(initial.voxels, initial.frame); !recorded.empty() && recorded != hash)
    g.warnings_.push_back(path + ": recorded on another tooth (hash " + recorded + ") than this run's (hash " + hash +
                          "): the ghost shows a cut made on that one");
  g.path_ = std::move(*pro);
  g.now_ = g.path_.at(0.0);
  return g;
}

inline const ProPose& GhostDriver::followTime(double task_time_s) {
  now_ = path_.at(task_time_s);
  return now_;
}

inline const ProPose& GhostDriver::followNearest(const Pose& student_tool, const Vec3& student_grip_local) {
  if (path_.empty()) return now_;
  const auto window = size_t(std::ceil(kNearestWindowS / ProPath::kSampleEveryS));
  nearest_ = path_.nearestDrill(student_tool.apply(student_grip_local), nearest_, window);
  now_ = path_.poses()[nearest_];
  return now_;
}

}  // namespace dentsim::app

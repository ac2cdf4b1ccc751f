// The professional's ghost: loading a session's path and tools, following the student by time or by the nearest pose, and posing the tools for the renderer.
#include "app/ghost.h"

#include <algorithm>
#include <cmath>

#include "io/session_file.h"
#include "sim/tool_library.h"
#include "volume/volume_hash.h"

namespace dentsim::app {

std::optional<GhostFollow> parseGhostFollow(const std::string& name) {
  if (name == kGhostFollowNames[0]) return GhostFollow::Time;
  if (name == kGhostFollowNames[1]) return GhostFollow::Nearest;
  return std::nullopt;
}

Result<Ghost> Ghost::load(const std::string& path, const PointShellParams& spacing) {
  auto session = readSessionFile(path);
  if (!session) return session.error();
  auto pro = ProPath::fromSession(*session, path);
  if (!pro) return pro.error();
  Ghost g;
  g.source_ = path;
  g.tooth_hash_ = session->info.tooth_hash;
  // Only the grip points are needed; the point shells the models carry are the haptic loop's.
  auto drill = loadToolModel(pro->drillTool(), spacing);
  if (!drill) return makeError(path, "the professional's drill: " + drill.message());
  g.drill_grip_local_ = drill->grip_local;
  if (!pro->mirrorTool().empty()) {
    auto mirror = loadToolModel(pro->mirrorTool(), spacing);
    if (!mirror) return makeError(path, "the professional's mirror: " + mirror.message());
    g.mirror_grip_local_ = mirror->grip_local;
  }
  g.path_ = std::move(*pro);
  g.now_ = g.path_.at(0.0);
  return g;
}

std::string Ghost::toothWarning(const ToothVolume& initial) const {
  const std::string hash = volumeHashHex(initial.voxels, initial.frame);
  if (tooth_hash_.empty() || tooth_hash_ == hash) return "";
  return source_ + ": recorded on another tooth (hash " + tooth_hash_ + ") than this run's (hash " + hash +
         "): the ghost shows a cut made on that one";
}

void Ghost::followTime(double task_time_s) { now_ = path_.at(task_time_s); }

void Ghost::followNearest(const Pose& student_tool, const Vec3& student_grip_local) {
  if (path_.empty()) return;
  const auto window = size_t(std::ceil(kNearestWindowS / ProPath::kSampleEveryS));
  nearest_ = path_.nearestDrill(student_tool.apply(student_grip_local), nearest_, window);
  now_ = path_.poses()[nearest_];
}

void Ghost::show(render::FrameState& frame, float opacity) const {
  if (path_.empty()) return;
  // A grip pose to the tool frame, as ToolProxy::toolPose does for the student's own tools.
  const auto tool = [](const Pose& grip, const Vec3& grip_local) {
    return Pose{grip.position - grip.rotation.rotate(grip_local), grip.rotation};
  };
  frame.ghost_drill_shown = true;
  frame.ghost_drill = tool(now_.drill, drill_grip_local_);
  frame.ghost_bur = path_.drillTool();
  frame.ghost_mirror_shown = !path_.mirrorTool().empty();
  frame.ghost_mirror = tool(now_.mirror, mirror_grip_local_);
  frame.ghost_opacity = std::clamp(opacity, 0.0f, 1.0f);
}

}  // namespace dentsim::app

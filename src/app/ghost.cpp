// The professional's ghost: the follow mode by name, and the driver's pose turned into the tool frames the renderer draws.
#include "app/ghost.h"

#include <algorithm>

namespace dentsim::app {

std::optional<GhostFollow> parseGhostFollow(const std::string& name) {
  if (name == kGhostFollowNames[0]) return GhostFollow::Time;
  if (name == kGhostFollowNames[1]) return GhostFollow::Nearest;
  return std::nullopt;
}

void poseGhost(const GhostDriver& ghost, float opacity, render::FrameState& frame) {
  const ProPath& path = ghost.path();
  if (path.empty()) return;
  // A grip pose to the tool frame, as ToolProxy::toolPose does for the student's own tools.
  const auto tool = [](const Pose& grip, const Vec3& grip_local) {
    return Pose{grip.position - grip.rotation.rotate(grip_local), grip.rotation};
  };
  frame.ghost_drill_shown = true;
  frame.ghost_drill = tool(ghost.now().drill, ghost.drillGripLocal());
  frame.ghost_bur = path.drillTool();
  frame.ghost_mirror_shown = !path.mirrorTool().empty();
  frame.ghost_mirror = tool(ghost.now().mirror, ghost.mirrorGripLocal());
  frame.ghost_opacity = std::clamp(opacity, 0.0f, 1.0f);
}

}  // namespace dentsim::app

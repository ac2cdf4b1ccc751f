// The professional's ghost in `dentsim run`: how it follows the student, and its drill and mirror posed for the renderer to draw translucent (the session and its poses: app/ghost_driver.h).
//
// The ghost is drawn only: it never enters the haptic loop, so it can neither cut the tooth nor
// push the student's pen. Its poses come from sim/pro_path.h (the tools where they stood, from the
// pens' readings and the forces the coupling rendered).
#pragma once

#include <optional>
#include <string>

#include "app/ghost_driver.h"
#include "render/scene_renderer.h"

namespace dentsim::app {

// How the ghost moves: with the student's task time, or standing where the professional's bur
// came nearest to the student's.
enum class GhostFollow { Time, Nearest };

inline constexpr const char* kGhostFollowNames[] = {"time", "nearest"};
std::optional<GhostFollow> parseGhostFollow(const std::string& name);

// The ghost's tool frames (ProPose's grips turned into the frames the renderer draws) at the pose
// `ghost` last chose, drawn at `opacity` (clamped to [0, 1]), in `frame`.
void poseGhost(const GhostDriver& ghost, float opacity, render::FrameState& frame);

}  // namespace dentsim::app

// Where the simulator's tools start: the drill upright over the crown, the mirror where a dentist holds it beside the tooth.
#pragma once

#include <vector>

#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "sim/surface_probe.h"

namespace dentsim::app {

// The drill's grip with the bur upright (tip down, axis +Z) and its tip `above_mm` over the crown's centre.
Pose drillStartGrip(const TissueBox& box, double above_mm);

// Where the demo (and a virtual mirror at start) holds the mirror: beside the crown's distal side,
// a little lingual, turned the way a dentist turns it: its normal halves the angle between the eye
// and the crown, so the eye sees the crown's distal and lingual surfaces in it. The handle (-X)
// leaves away from the tooth. Seen from below the occlusal surface (eye.z under the crown's top),
// the mirror is held above the crown instead, distally, where it shows the occlusal surface.
// Returns the grip frame.
Pose mirrorGrip(const TissueBox& box, const Vec3& eye);

// Points along the tools where they stand [mm], for the view keys to keep off the tooth
// (ui::CameraControl::showPreset): the drill from its bur's tip up the shank to 30 % past its grip
// (the handpiece's head), and, when given, the mirror's face as a disc of `mirror_diameter_mm`
// (its centre, and rings at half and full radius) and its handle to the grip.
std::vector<Vec3> toolSightPoints(const Pose& drill_grip, const Pose* mirror_grip, double mirror_diameter_mm);

// Mirror samples for a scripted path that has none: held still at `grip` for the whole path.
void addStillMirror(PenPath& path, const Pose& grip);

// The time of the path's last sample [s].
double pathEnd(const PenPath& path);

}  // namespace dentsim::app

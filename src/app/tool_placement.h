// Where the simulator's tools start: the drill upright over the crown, the mirror where a dentist holds it beside the tooth.
#pragma once

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

// Mirror samples for a scripted path that has none: held still at `grip` for the whole path.
void addStillMirror(PenPath& path, const Pose& grip);

// The time of the path's last sample [s].
double pathEnd(const PenPath& path);

}  // namespace dentsim::app

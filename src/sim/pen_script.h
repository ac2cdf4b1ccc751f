// A pen script as the simulation plays it: a tooth-frame path turned into the simulation frame, and the warnings a first script needs before anything runs.
#pragma once

#include <string>
#include <vector>

#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "volume/brick_volume.h"

namespace dentsim {

// The tooth frame's pose in the simulation frame: origin at the occlusal centre, x distal (the
// opposite of mesial), z the crown axis, y = z x x.
Pose toothFramePose(const ToothVolume& tooth);

// The path with every pose in the simulation frame (a simulation-frame path comes back unchanged).
PenPath penPathInSimulationFrame(const PenPath& path, const ToothVolume& tooth);

// What is wrong with where a simulation-frame path starts, one line each, starting "<where>: ": the
// bur's head or the mirror's face inside the tooth at the first sample of its pen. Empty when
// nothing is.
std::vector<std::string> penPathStartWarnings(const PenPath& path, const ToothVolume& tooth, const std::string& where);

}  // namespace dentsim

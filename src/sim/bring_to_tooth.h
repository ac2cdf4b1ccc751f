// "Bring to tooth": where the drill goes when a student at the mouse asks for the bur at the task's target, just clear of the tissue where the professional's path first touches it.
//
// A student with a mouse has no hand to feel the tooth: a bur started above the crown took six wheel
// steps, found by trial, to reach it. The professional's path for the task (the scripted preparation
// or the teacher's recorded one) says where the work starts and how the bur is held there; the
// drill is put there, backed off along its own axis until no point of its shell is in tissue, and
// then `clearance_mm` further, so that the lower key (or a short drag) brings it into contact.
#pragma once

#include <optional>

#include "core/rigid.h"
#include "io/pen_path_file.h"
#include "sim/tool_proxy.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct BringToTooth {
  Pose grip;                 // the drill's grip frame to put the pen at
  double first_contact_s;    // the professional path's time of its first contact [s]
  double backed_off_mm;      // how far the grip was moved back along the tool's axis from there [mm]
};

// Searches `pro`'s drill samples in time order for the first whose shell has a point in tissue
// (the field's phi > 0 at the point, as the haptic loop tests it). nullopt when the path never
// touches the tooth, or has no drill samples. The back-off is searched in steps of a quarter voxel,
// at most 20 mm.
std::optional<BringToTooth> bringToTooth(const PenPath& pro, const ToolModel& drill, const BrickVolume& volume,
                                         const VolumeFrame& frame, double clearance_mm);

// Whether any point of `drill`'s shell, held at `grip`, is in tissue.
bool shellTouches(const ToolModel& drill, const Pose& grip, const BrickVolume& volume, const VolumeFrame& frame);

}  // namespace dentsim

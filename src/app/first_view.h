// The first camera view the simulator and the replay window open on: a view preset about the tooth's tissue, raised as from the chair, widened to take in the mirror where it starts.
#pragma once

#include <optional>
#include <string>

#include "core/result.h"
#include "eval/task.h"
#include "render/camera.h"
#include "sim/surface_probe.h"

namespace dentsim::app {

// A side view from the chair looks down on a lower crown: raised 30 degrees [rad].
inline constexpr float kChairElevationRad = 0.52f;

struct FirstView {
  render::ViewPreset preset = render::ViewPreset::Buccal;
  float elevation_rad = kChairElevationRad;  // the eye raised above a side preset [rad]; the occlusal view ignores it
  bool mirror = false;                       // a mirror starts beside the tooth: the view widens to take it in
  bool fixed = false;                        // the task locks the mouse and keys out of the camera
};

// --view (empty: none), else the task's view (none: buccal from the chair). A task's elevation and
// lock hold only for the task's own view. Errors: an unknown view name.
Result<FirstView> chooseFirstView(const std::string& view_option, const std::optional<TaskView>& task_view, bool mirror);

// The box the first view frames, and the drill and mirror start beside: the treated tooth's
// (toothBox, sim/scripted_paths.h), so that a tooth between neighbours is centred and fills the
// view, its neighbours in sight at the sides. Without neighbours it is tissueBox.
TissueBox firstViewBox(const BrickVolume& volume, const VolumeFrame& frame);

// Places `camera` on `view` of the tooth whose tissue fills `box`. With a mirror the target moves
// halfway to the mirror's face (mirrorGrip's, seen from the preset's eye) and the distance grows by
// the half-gap, then comes in to 0.8 of that, so tooth and mirror both fill the frame.
void placeFirstView(render::OrbitCamera& camera, const TissueBox& box, const FirstView& view);

}  // namespace dentsim::app

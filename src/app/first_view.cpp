// The first camera view, shared by the simulator and the replay window, so that a replay opens where its session's student started.
#include "app/first_view.h"

#include <numbers>

#include "app/tool_placement.h"
#include "sim/scripted_paths.h"
#include "sim/tool_library.h"

namespace dentsim::app {

Result<FirstView> chooseFirstView(const std::string& view_option, const std::optional<TaskView>& task_view, bool mirror) {
  const bool task_owns_view = view_option.empty() && task_view;
  auto preset = render::parseViewPreset(!view_option.empty() ? view_option : task_view ? task_view->camera : "buccal");
  if (!preset) return preset.error();
  FirstView v;
  v.preset = *preset;
  if (task_owns_view) v.elevation_rad = float(task_view->elevation_deg * std::numbers::pi / 180.0);
  v.mirror = mirror;
  v.fixed = task_owns_view && task_view->fixed;
  return v;
}

TissueBox firstViewBox(const BrickVolume& volume, const VolumeFrame& frame) { return toothBox(volume, frame); }

void placeFirstView(render::OrbitCamera& camera, const TissueBox& box, const FirstView& view) {
  const Vec3 c = box.centre();
  const double radius = 0.5 * norm(box.hi - box.lo);
  camera.setView(view.preset, render::toGlm(c), float(radius));
  if (view.preset != render::ViewPreset::Occlusal) camera.orbit(0.0f, view.elevation_rad);
  if (!view.mirror) return;
  const Vec3 face = mirrorGrip(box, render::fromGlm(camera.eye())).apply(-kMirrorGripLocal);
  camera.setTarget(render::toGlm((c + face) * 0.5));
  camera.setDistance(camera.distance() * float((radius + 0.5 * norm(face - c)) / radius) * 0.8f);
}

}  // namespace dentsim::app

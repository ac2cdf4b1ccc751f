// What the mouse and keys may do to the simulator's camera: orbit, pan, zoom and the five preset views, all refused while the task's view is fixed.
//
// A fixed view is the indirect-vision exercise (eval/task.h, TaskView::fixed): the eye stays where
// the task put it, so the cavity can be seen only in the mirror. The window's callbacks
// (app/window_input) ask this class rather than the camera, so that no input path can go around
// the lock.
#pragma once

#include <span>

#include "core/rigid.h"
#include "render/camera.h"

namespace dentsim::ui {

class CameraControl {
 public:
  explicit CameraControl(render::OrbitCamera& camera) : camera_(camera) {}

  void setFixed(bool fixed) { fixed_ = fixed; }
  bool fixed() const { return fixed_; }

  // Each returns false, leaving the camera as it was, when the view is fixed.
  // A right drag of (dx, dy) pixels turns the eye about the target, kOrbitRadPerPx a pixel.
  bool orbit(double dx_px, double dy_px);
  // A middle drag slides the view so that the target follows the cursor; viewport_h [px] > 0.
  bool pan(double dx_px, double dy_px, int viewport_h);
  // Alt + wheel: each notch up moves 10 % closer.
  bool zoom(double notches);
  // Keys 1 to 5: the preset's view of a tooth centred at `centre` with `radius_mm`, turned off the
  // preset where a tool would hide the tooth: when a point of `tools` (points along the tools where
  // they stand [mm]) outside the tooth's sphere stands in front of its centre and over its middle
  // on screen (within half its radius), the eye is
  // lowered (or turned aside), 5 degrees at a time up to kMaxDodgeRad, to the first view clear of
  // them all. The top view over an upright drill looked down the handpiece.
  bool showPreset(render::ViewPreset preset, const Vec3& centre, float radius_mm, std::span<const Vec3> tools = {});
  // Whether a point of `tools` hides the tooth from the camera as it is.
  bool toolsHideTooth(const Vec3& centre, float radius_mm, std::span<const Vec3> tools) const;
  static constexpr double kMaxDodgeRad = 0.7854;  // 45 degrees

  static constexpr double kOrbitRadPerPx = 0.008;  // [rad/px]

 private:
  render::OrbitCamera& camera_;
  bool fixed_ = false;
};

}  // namespace dentsim::ui

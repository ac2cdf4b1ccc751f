// PenInput: mouse drags, wheel and keys turned into pen targets through the orbit camera, for the virtual pens.
#pragma once

#include <array>
#include <cstdint>

#include "core/rigid.h"
#include "devices/virtual_pen.h"
#include "io/pen_path_file.h"
#include "render/camera.h"
#include "sim/tool_proxy.h"

namespace dentsim::ui {

using devices::VirtualPen;

struct PenInputParams {
  double wheel_mm_per_step = 0.5;     // pen travel along the view direction per wheel step [mm]
  double pedal_per_step = 0.05;       // pedal change per wheel step (with the modifier) [0..1]
  double key_lift_mm = 0.1;           // travel along the tool's axis per lift or lower key press [mm]
};

// Turns window events into pen targets. GLFW-free: the window calls these from its callbacks. Both
// pens' targets live here; either VirtualPen may be null (that pen is a real device), and input
// for a null pen only moves the target kept here. The camera is read at each call, so orbiting,
// zooming and panning between drags are taken into account; it must outlive this object.
class PenInput {
 public:
  PenInput(const render::OrbitCamera& camera, VirtualPen* drill, VirtualPen* mirror,
           const PenInputParams& params = {});

  void setViewport(int width, int height);  // framebuffer pixels, > 0
  void setActive(PenRole role);             // which pen drags, the wheel and rotate() move
  PenRole active() const { return active_; }

  // Moves the active pen in the view plane at its own depth: it stays under a cursor that moves
  // (dpx, dpy) pixels (screen y down). Nothing moves before setViewport().
  void drag(float dpx, float dpy);
  // Moves the active pen along the view direction: positive steps push it away from the viewer.
  void wheel(float steps);
  // Lifts (mm > 0) or lowers (mm < 0) the active tool along its own axis (the grip frame's +z,
  // away from the bur's tip), whatever the view: the keys that bring a bur down onto the tooth.
  void alongTool(double mm);
  // Tilts the active tool about its grip point: dyaw about the camera's up, dpitch about its right [rad].
  void rotate(double dyaw_rad, double dpitch_rad);
  // The drill's pedal (the mirror has none), clamped to [0, 1].
  void wheelPedal(float steps);
  void setPedal(double pedal);
  double pedal() const { return pedal_; }
  void setButtons(uint32_t buttons);  // the active pen's buttons
  // Puts the active pen (or the given one) at pose at once, at rest.
  void reset(const Pose& pose) { reset(active_, pose); }
  void reset(PenRole role, const Pose& pose);

  const Pose& target(PenRole role) const { return targets_[size_t(role)]; }
  const PenInputParams& params() const { return params_; }

 private:
  VirtualPen* pen(PenRole role) const { return pens_[size_t(role)]; }
  void moveActive(const Pose& pose);

  const render::OrbitCamera& camera_;
  std::array<VirtualPen*, 2> pens_;  // indexed by PenRole; null for a pen driven by hardware
  std::array<Pose, 2> targets_;      // each pen's target grip frame [mm]
  PenInputParams params_;
  PenRole active_ = PenRole::Drill;
  int width_ = 0, height_ = 0;       // viewport [px]; 0 until setViewport()
  double pedal_ = 0.0;               // [0, 1]
};

}  // namespace dentsim::ui

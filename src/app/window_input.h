// The simulator window's mouse and keys: the virtual pens (drag, wheel, arrows, W and S along the tool, B to the tooth), the camera (orbit, pan, zoom, views 1 to 5; none of them while the task's view is fixed), the turbine (wheel with Ctrl, Page keys, Space), F1 for the controls and Escape.
//
// ui/controls_help.cpp names these same controls to the student; a key added here is named there.
#pragma once

#include <functional>
#include <vector>

#include "render/camera.h"
#include "sim/surface_probe.h"
#include "ui/camera_control.h"
#include "ui/imgui_layer.h"
#include "ui/pen_input.h"
#include "ui/window.h"

namespace dentsim::app {

class WindowInput {
 public:
  // What the keys and the wheel change beyond the pens and the camera.
  struct Hooks {
    std::function<void(double)> turbine_speed;  // the virtual pedal moved to this [0, 1]
    std::function<void()> quit;                 // Escape
    std::function<void()> bring_to_tooth;       // B: the drill just over the task's target (may be empty)
    std::function<void()> toggle_help;          // F1: the controls overlay shown or hidden (may be empty)
  };
  WindowInput(render::OrbitCamera& camera, const TissueBox& box, Hooks hooks)
      : camera_(camera), control_(camera), box_(box), hooks_(std::move(hooks)) {}

  // Installs GLFW's callbacks on the window; they must go in before the panel's, which chain to them
  // (ui/imgui_layer.h). The window and this object must outlive the callbacks' use.
  void attach(ui::Window& window);
  // The pens the mouse moves (none: only the camera) and the panel that takes the mouse first (none: no panel).
  void setPens(ui::PenInput* pens) { pens_ = pens; }
  void setPanel(const ui::ImGuiLayer* panel) { panel_ = panel; }
  // The mirror's face diameter [mm]; 0: no mirror on screen (its pen's target is then no tool the
  // view keys must keep off the tooth).
  void setMirrorDiameter(double mm) { mirror_diameter_mm_ = mm; }
  // A fixed view (the task's, for indirect vision): the mouse and keys leave the camera alone.
  void setViewFixed(bool fixed) { control_.setFixed(fixed); }
  bool viewFixed() const { return control_.fixed(); }

  void onMouseButton(int button, int action, int mods);
  void onCursor(double x, double y);
  void onScroll(double dx, double dy);
  void onKey(int key, int action, int mods);
  // The wheel with the modifiers given rather than read from the window (onScroll reads them):
  // app/scripted_input.h's wheel events.
  void scroll(double dy, int mods);
  // A left drag by (dx, dy) window pixels from where the cursor is: press, move, release.
  void dragBy(double dx, double dy, int mods);

 private:
  render::OrbitCamera& camera_;
  // Points along both tools where they stand [mm]: what the view keys keep from hiding the tooth.
  std::vector<Vec3> toolPoints() const;
  ui::CameraControl control_;  // every camera move goes through its lock
  const TissueBox& box_;
  Hooks hooks_;
  ui::Window* window_ = nullptr;
  ui::PenInput* pens_ = nullptr;
  const ui::ImGuiLayer* panel_ = nullptr;
  double mirror_diameter_mm_ = 0.0;
  bool dragging_pen_ = false, orbiting_ = false, panning_ = false;
  double cursor_x_ = 0, cursor_y_ = 0;
};

}  // namespace dentsim::app

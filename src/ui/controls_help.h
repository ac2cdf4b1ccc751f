// The student's help in the window: the controls overlay (the pen in use, the task, the bur), the guidance switch on the Tools page, and the guide's pull drawn at the bur.
//
// A student at a school PC has no manual. The overlay names every control of the pen they hold
// (for the mouse and keys: move, lift and lower, tilt, the turbine, the mirror hand, the view, and
// B to bring the bur to the tooth; for a haptic pen: the stylus and the pedal), with the task's
// instructions and the bur, on first use and again from Help or F1. The keys it names are the ones
// app/window_input.cpp handles: a key added there is named here.
#pragma once

#include <string>
#include <vector>

#include "ui/panel_widgets.h"

namespace dentsim::ui {

// One line of the overlay's table: the control and what it does.
struct ControlLine {
  std::string control;  // "W / S", "left drag"
  std::string action;   // "lift / lower the bur along its axis, 0.1 mm a press"
};

// The controls named for `input` (a script: only the view's and the panel's).
std::vector<ControlLine> controlLines(DrillInput input, bool pedal_present);

namespace panel {

// The "Controls" window while state.help.shown: the task's title and instructions, the bur, the
// controls' table, and its buttons ("Bring the bur to the tooth", "Got it").
void controlsWindow(const Frame& f);

// Guidance on the Tools page: the switch, the stiffness and where the path comes from; disabled
// with a tooltip saying why when there is no path.
void guidanceSection(const Frame& f);

}  // namespace panel

// The guide's pull on the overlay: a bar of its force against its cap and, when it pulls across the
// view, an arrow from the bur's tip. Needs an ImGui frame; draws nothing while no segment is guided.
void drawGuidePull(const GuidanceView& guidance);

}  // namespace dentsim::ui

// Scripted window input (`run --input T EVENT`): keys, wheel steps, mouse drags and panel clicks at given loop times, fed through the same handlers as the student's own mouse and keys.
//
// The window's new parts are tested the way a student uses them, with no pen script: what a test
// presses here goes through WindowInput (keys, wheel, drags) and through ImGui's own hit testing
// (a click lands on a panel widget's rectangle), not around them. An event's time is the frame's:
// frames / fps with --lockstep (or headless), which is the loop time while a segment runs, so a
// scripted attempt is reproducible; else seconds since the run began. Not the loop time itself,
// which stands still while the segment is stopped: a click on Reset after Stop would never come.
//
// EVENT is one of
//   key:NAME          a key pressed and released: A-Z, 0-9, Space, PageUp, PageDown, Up, Down,
//                     Left, Right, Escape, F1; "shift+" before NAME holds Shift (the mirror hand)
//   wheel:STEPS       the wheel turned STEPS notches (negative: toward the student); "ctrl+",
//                     "alt+" or "shift+" before "wheel" holds that key
//   drag:DX,DY        a left drag by (DX, DY) pixels of the window; "shift+" holds Shift
//   click:WIDGET      a left click in the middle of a panel widget, by its key (ui/param_panel.h,
//                     WidgetRects: "start", "score", "help", ...), pressed one frame, let go the next
#pragma once

#include <string>
#include <vector>

#include "core/result.h"

namespace dentsim::app {

struct ScriptedInput {
  enum class Kind { Key, Wheel, Drag, Click };
  double t_s = 0.0;        // the frame time it happens at [s]
  Kind kind = Kind::Key;
  int key = 0;             // GLFW key code (Key)
  int mods = 0;            // GLFW modifier bits held
  double dx = 0, dy = 0;   // wheel notches (dy), or drag pixels
  std::string widget;      // Click: the widget's key
  std::string text;        // as given, for messages
};

// One event from its loop time and text; errors are one line naming the text and what is wrong.
Result<ScriptedInput> parseScriptedInput(double t_s, const std::string& text);

// The option's values (pairs of time and event text, as the command line gave them), sorted by
// time; a stable sort keeps the order of events given for one time.
Result<std::vector<ScriptedInput>> parseScriptedInputs(const std::vector<std::pair<double, std::string>>& given);

}  // namespace dentsim::app

// The controls overlay, the guidance section and the guide's arrow.
#include "ui/controls_help.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dentsim::ui {

std::vector<ControlLine> controlLines(DrillInput input, bool pedal_present) {
  std::vector<ControlLine> lines;
  const char* turbine = pedal_present ? "the foot pedal: press for speed (Space stops it)"
                                      : "Space: on / off;  PageUp / PageDown or Ctrl + wheel: speed";
  switch (input) {
    case DrillInput::Mouse:
      lines = {{"B", "bring the bur to the tooth, just above where the work starts"},
               {"W / S", "lift / lower the bur along its axis, 0.1 mm a press (hold to repeat)"},
               {"left drag", "move the bur across the screen"},
               {"wheel", "push the bur away from you / pull it closer, 0.5 mm a notch"},
               {"arrow keys", "tilt the bur, 3 degrees a press"},
               {"turbine", turbine},
               {"Shift + any", "the same for the mirror hand"},
               {"R", "both tools back to where they started"}};
      break;
    case DrillInput::HapticPen:
      lines = {{"the stylus", "move and turn it: the bur follows, and you feel the tooth"},
               {"turbine", turbine},
               {"stylus buttons", "not used: the pen's position is all dentsim reads"},
               {"the second pen", "the mirror, when one is connected"}};
      break;
    case DrillInput::Script:
      lines = {{"the pen script", "moves the tools; the keys below move the view only"}};
      break;
  }
  lines.push_back({"right / middle drag", "turn / slide the view;  Alt + wheel: zoom"});
  lines.push_back({"1 to 5", "occlusal, buccal, lingual, mesial, distal view"});
  lines.push_back({"Start / Stop / Score", "the buttons at the top of the panel"});
  lines.push_back({"F1", "show or hide this help"});
  return lines;
}

namespace panel {

void controlsWindow(const Frame& f) {
  UiState& s = f.state;
  if (!s.help.shown) return;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  // Left, under the overlay's readouts, clear of the panel on the right; the tooth stays in view
  // to its right on a 1280 x 800 window.
  const float width = std::min(440.0f, std::max(240.0f, display.x * 0.36f));
  const float top = std::min(190.0f, display.y * 0.25f);
  ImGui::SetNextWindowPos(ImVec2(10.0f, top), ImGuiCond_Appearing);
  // A fixed size: wrapped text in a table would feed an auto-fitting window's size back into its
  // own width for a frame or two. What does not fit scrolls.
  ImGui::SetNextWindowSize(ImVec2(width, std::max(160.0f, std::min(440.0f, display.y - top - 10.0f))), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.88f);
  bool open = true;
  if (ImGui::Begin("Controls", &open, ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoCollapse)) {
    if (!s.task_title.empty()) {
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.45f, 1.0f), "%s", s.task_title.c_str());
      f.record("help.task");
    }
    if (!s.task_instructions.empty()) {
      ImGui::TextWrapped("%s", s.task_instructions.c_str());
      f.record("help.instructions");
    }
    if (!s.help.bur.empty()) ImGui::TextWrapped("bur: %s", s.help.bur.c_str());
    if (!s.help.device.empty()) ImGui::TextDisabled("drill: %s", s.help.device.c_str());
    ImGui::Separator();
    if (ImGui::BeginTable("controls", 2, ImGuiTableFlags_RowBg)) {
      ImGui::TableSetupColumn("control", ImGuiTableColumnFlags_WidthFixed, 0.36f * width);
      ImGui::TableSetupColumn("does", ImGuiTableColumnFlags_WidthStretch);
      for (const ControlLine& l : controlLines(s.help.input, s.pedal_present)) {
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(l.control.c_str());
        ImGui::TableNextColumn();
        ImGui::TextWrapped("%s", l.action.c_str());
      }
      ImGui::EndTable();
    }
    f.record("help.table");
    if (s.help.input == DrillInput::Mouse) {
      const char* why_not = s.help.bring_available ? nullptr
                                                   : "This task has no professional's path to start from: move the bur with the mouse.";
      ImGui::BeginDisabled(why_not != nullptr);
      f.actions.bring_to_tooth |= ImGui::Button("Bring the bur to the tooth (B)");
      f.record("help.bring");
      ImGui::EndDisabled();
      if (why_not) tooltip(why_not);
      ImGui::SameLine();
    }
    if (ImGui::Button("Got it")) open = false;
    f.record("help.close");
  }
  const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
  f.actions.help_rect = {int(pos.x), int(pos.y), int(size.x), int(size.y)};
  ImGui::End();
  if (!open) {
    s.help.shown = false;
    f.actions.help_closed = true;
  }
}

void guidanceSection(const Frame& f) {
  GuidanceView& g = f.state.guidance;
  ImGui::Spacing();
  ImGui::TextDisabled("guidance: a spring toward the professional's path");
  const char* why_not = g.available ? nullptr : g.source.empty() ? "No professional's path: the task has no recorded ideal and --guide was not given." : g.source.c_str();
  ImGui::BeginDisabled(why_not != nullptr);
  bool on = g.on;
  if (ImGui::Checkbox("guide my bur", &on) && on != g.on) {
    g.on = on;
    f.actions.guidance_changed = true;
  }
  f.record("guidance");
  ImGui::EndDisabled();
  tooltip(why_not ? why_not : "Pulls the bur toward where the professional's bur was at this stage of the work. "
                              "Applies from the next Start or Reset, so that a session replays as it was felt.");
  ImGui::BeginDisabled(why_not != nullptr || !g.on);
  double k = g.stiffness_n_per_mm;
  if (sliderDouble(f, "guidance.stiffness", "guide spring [N/mm]", k, 0.1, 5.0, "%.2f") && k != g.stiffness_n_per_mm) {
    g.stiffness_n_per_mm = k;
    f.actions.guidance_changed = true;
  }
  ImGui::EndDisabled();
  if (!g.on && g.available) tooltip("Switch guidance on first.");
  if (g.available) {
    ImGui::TextDisabled("path: %s", g.source.c_str());
    if (g.on != g.active) ImGui::TextWrapped("%s", g.on ? "Guidance starts with the next Start or Reset." : "Guidance ends with the next Start or Reset.");
  }
}

}  // namespace panel

void drawGuidePull(const GuidanceView& g) {
  if (!g.active) return;
  const double fraction = g.max_n > 0.0 ? std::clamp(g.pull_n / g.max_n, 0.0, 1.0) : 0.0;
  char text[48];
  std::snprintf(text, sizeof text, "guide %.2f N / %.1f N", g.pull_n, g.max_n);
  ImGui::PushStyleColor(ImGuiCol_PlotHistogram, ImVec4(0.25f, 0.65f, 0.95f, 1.0f));
  ImGui::ProgressBar(float(fraction), ImVec2(220.0f, 0.0f), text);
  ImGui::PopStyleColor();
  // The arrow at the bur, on the foreground: 80 px at the guide's cap, none under 1 % of it.
  const float len = float(80.0 * fraction);
  const float ux = g.pull_px[0], uy = g.pull_px[1];
  if (len < 1.0f || ux * ux + uy * uy < 0.25f) return;
  ImDrawList* dl = ImGui::GetForegroundDrawList();
  const ImVec2 a(g.tip_px[0], g.tip_px[1]), b(a.x + ux * len, a.y + uy * len);
  const ImU32 colour = IM_COL32(64, 166, 242, 230);
  dl->AddLine(a, b, colour, 3.0f);
  const float head = std::min(12.0f, 0.4f * len + 4.0f);
  const ImVec2 side(-uy * head * 0.5f, ux * head * 0.5f), back(b.x - ux * head, b.y - uy * head);
  dl->AddTriangleFilled(b, ImVec2(back.x + side.x, back.y + side.y), ImVec2(back.x - side.x, back.y - side.y), colour);
}

}  // namespace dentsim::ui

// The replay window's transport and timeline, drawn with ImGui's widgets and its draw list.
#include "ui/replay_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

namespace dentsim::ui {

namespace {

constexpr float kPanelHeight = 168.0f;  // the window along the bottom edge [px]
constexpr float kStripHeight = 72.0f;   // the force strip [px]
constexpr float kContactBand = 6.0f;    // the contact band under the force bars [px]
constexpr size_t kDrill = 0;            // PenRole::Drill's index in SessionStep's arrays

PixelRect rectOf(ImVec2 lo, ImVec2 hi) {
  return PixelRect{int(std::floor(lo.x)), int(std::floor(lo.y)), int(std::ceil(hi.x - lo.x)), int(std::ceil(hi.y - lo.y))};
}

// The strip's full scale: a little above the largest force, on a quarter newton. A careful
// session stays far below the threshold; scaled to the threshold its bars would be a few pixels
// high, so the threshold's line only shows when some force comes near it.
float stripTop(const std::vector<ForceColumn>& columns) {
  float top = 0.0f;
  for (const ForceColumn& c : columns) top = std::max(top, c.max_force_n);
  return std::max(0.25f, std::ceil(top * 1.15f * 4.0f) / 4.0f);
}

}  // namespace

std::optional<int> replaySpeedIndex(double speed) {
  for (size_t i = 0; i < kReplaySpeeds.size(); ++i)
    if (kReplaySpeeds[i] == speed) return int(i);
  return std::nullopt;
}

std::vector<ForceColumn> forceColumns(std::span<const SessionStep> steps, double threshold_n, int columns) {
  columns = std::max(columns, 1);
  std::vector<ForceColumn> out(static_cast<size_t>(columns));
  const size_t n = steps.size();
  for (size_t c = 0; c < out.size(); ++c) {
    const size_t lo = c * n / out.size(), hi = (c + 1) * n / out.size();
    ForceColumn& col = out[c];
    for (size_t k = lo; k < hi; ++k) {
      const SessionStep& s = steps[k];
      const double force = norm(s.force_n[kDrill]);
      col.max_force_n = std::max(col.max_force_n, float(force));
      // As the score counts it: only a step with a drill reading and the drill in tissue.
      const bool contact = s.hasReading(kDrill) && s.contacts[kDrill] > 0;
      col.contact = col.contact || contact;
      col.over = col.over || (contact && force > threshold_n);
    }
  }
  return out;
}

std::string replayClock(double seconds) {
  seconds = std::max(0.0, seconds);
  const int tenths = int(std::floor(seconds * 10.0 + 1e-6));
  char text[32];
  std::snprintf(text, sizeof text, "%d:%02d.%d", tenths / 600, (tenths / 10) % 60, tenths % 10);
  return text;
}

ReplayPanelActions drawReplayPanel(ReplayPanelState& s) {
  ReplayPanelActions a;
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(0.0f, std::max(0.0f, display.y - kPanelHeight)), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(display.x, std::min(kPanelHeight, display.y)), ImGuiCond_Always);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoScrollbar;
  const std::string title = "Replay: " + s.title + "###replay";
  if (!ImGui::Begin(title.c_str(), nullptr, flags)) {
    ImGui::End();
    return a;
  }
  a.panel_rect = rectOf(ImGui::GetWindowPos(), ImVec2(ImGui::GetWindowPos().x + ImGui::GetWindowSize().x,
                                                      ImGui::GetWindowPos().y + ImGui::GetWindowSize().y));

  // Back to the run, first, where a student reviewing an attempt looks for the way out.
  if (s.back_shown) {
    if (ImGui::Button("Back to the score")) a.back = true;
    ImGui::SameLine(0.0f, 16.0f);
  }
  // The transport: Play/Pause (Space), the speeds, the clock.
  if (ImGui::Button(s.playing ? "Pause" : "Play", ImVec2(64.0f, 0.0f))) a.toggle_play = true;
  if (!ImGui::GetIO().WantTextInput && ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Space), false))
    a.toggle_play = true;
  ImGui::SameLine(0.0f, 16.0f);
  ImGui::TextUnformatted("speed");
  for (size_t i = 0; i < kReplaySpeeds.size(); ++i) {
    ImGui::SameLine();
    char label[16];
    std::snprintf(label, sizeof label, "%gx", kReplaySpeeds[i]);
    if (ImGui::RadioButton(label, s.speed_index == int(i)) && s.speed_index != int(i)) {
      s.speed_index = int(i);
      a.speed_changed = true;
    }
  }
  ImGui::SameLine(0.0f, 24.0f);
  const std::string clock = replayClock(s.time_s) + " / " + replayClock(s.duration_s);
  ImGui::TextUnformatted(clock.c_str());

  // The strip: one column a pixel, the force as bars (red where over the threshold), the contact
  // as a band under them, the threshold as a line, the playhead as a white line.
  const float width = std::max(16.0f, ImGui::GetContentRegionAvail().x);
  const int columns = int(width);
  if (columns != s.columns_width) {
    s.columns = forceColumns(s.steps, s.threshold_n, columns);
    s.columns_width = columns;
    s.strip_top_n = stripTop(s.columns);
  }
  const ImVec2 lo = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##timeline", ImVec2(width, kStripHeight));
  const ImVec2 hi(lo.x + width, lo.y + kStripHeight);
  a.strip_rect = rectOf(lo, hi);
  const float mouse_x = ImGui::GetIO().MousePos.x;
  const double at_mouse = std::clamp(double(mouse_x - lo.x) / double(width), 0.0, 1.0) * s.duration_s;
  if (ImGui::IsItemActive()) {
    s.drag_s = at_mouse;
  } else if (s.drag_s) {
    a.seek_s = *s.drag_s;
    s.drag_s.reset();
  }
  if (ImGui::IsItemHovered()) a.hover_s = at_mouse;

  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(lo, hi, IM_COL32(24, 26, 32, 255));
  const float bars_bottom = hi.y - kContactBand - 1.0f, bars_height = bars_bottom - lo.y - 2.0f;
  for (int c = 0; c < columns && c < int(s.columns.size()); ++c) {
    const ForceColumn& col = s.columns[size_t(c)];
    const float x = lo.x + float(c);
    if (col.contact) draw->AddRectFilled(ImVec2(x, hi.y - kContactBand), ImVec2(x + 1.0f, hi.y), IM_COL32(70, 170, 90, 255));
    if (col.max_force_n <= 0.0f) continue;
    const float h = std::min(1.0f, col.max_force_n / s.strip_top_n) * bars_height;
    const ImU32 colour = col.over ? IM_COL32(230, 60, 50, 255) : col.contact ? IM_COL32(225, 190, 90, 255) : IM_COL32(110, 120, 140, 255);
    draw->AddRectFilled(ImVec2(x, bars_bottom - h), ImVec2(x + 1.0f, bars_bottom), colour);
  }
  char label[64];
  if (s.threshold_n < double(s.strip_top_n)) {
    const float threshold_y = bars_bottom - float(s.threshold_n) / s.strip_top_n * bars_height;
    draw->AddLine(ImVec2(lo.x, threshold_y), ImVec2(hi.x, threshold_y), IM_COL32(230, 60, 50, 160));
    std::snprintf(label, sizeof label, "%.1f N", s.threshold_n);
    draw->AddText(ImVec2(lo.x + 4.0f, threshold_y - ImGui::GetTextLineHeight()), IM_COL32(240, 120, 110, 255), label);
  } else {
    std::snprintf(label, sizeof label, "every force below the %.1f N threshold", s.threshold_n);
    draw->AddText(ImVec2(lo.x + 4.0f, lo.y + 2.0f), IM_COL32(170, 175, 185, 255), label);
  }
  std::snprintf(label, sizeof label, "%.2f N", double(s.strip_top_n));
  draw->AddText(ImVec2(hi.x - ImGui::CalcTextSize(label).x - 4.0f, lo.y + 2.0f), IM_COL32(170, 175, 185, 255), label);
  const double shown = s.drag_s ? *s.drag_s : s.time_s;
  const float head_x = lo.x + float(s.duration_s > 0 ? shown / s.duration_s : 0.0) * (width - 1.0f);
  draw->AddLine(ImVec2(head_x, lo.y), ImVec2(head_x, hi.y), IM_COL32(255, 255, 255, 255), 2.0f);
  draw->AddRect(lo, hi, IM_COL32(90, 95, 110, 255));

  // The legend, and where a drag or the pointer is.
  ImGui::TextColored(ImVec4(0.88f, 0.75f, 0.35f, 1.0f), "drill force");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.90f, 0.24f, 0.20f, 1.0f), "over %.1f N in contact", s.threshold_n);
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.27f, 0.67f, 0.35f, 1.0f), "contact");
  ImGui::SameLine(0.0f, 24.0f);
  if (s.drag_s) ImGui::Text("seek to %s", replayClock(*s.drag_s).c_str());
  else if (a.hover_s) ImGui::Text("drag to seek: %s", replayClock(*a.hover_s).c_str());
  else ImGui::TextUnformatted("drag the strip to seek; Space plays and pauses");
  if (!s.status.empty()) ImGui::TextUnformatted(s.status.c_str());
  ImGui::End();
  return a;
}

}  // namespace dentsim::ui

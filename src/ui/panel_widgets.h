// The parameter window's widgets, shared by its pages (param_panel.cpp, task_page.cpp): the frame's context, rectangle recording, sliders with their values beside them; private to ui.
#pragma once

#include <string>

#include <imgui.h>

#include "ui/param_panel.h"

namespace dentsim::ui::panel {

// What the panel and its tests need from ImGui's internals, behind this one wrapper so that no
// other file includes imgui_internal.h (an interface ImGui may change in any release):
// whether the slider `id` is being typed into (Ctrl+click), so that it shows its own text;
bool sliderBeingTyped(const char* id);
// a window's place on the screen and whether its content scrolls, for the tests that check the
// panel fits (false when no window has that name);
struct WindowLayout {
  WidgetRect rect;
  float scroll_max_y = 0;    // how far its content scrolls [px]; 0: it all shows
  float content_height = 0;  // [px]
};
bool windowLayout(const char* name, WindowLayout* layout);
// and the windows begun but not ended in this frame (0 after a whole frame: every Begin has its End).
int windowsLeftOpen();

inline constexpr float kLabelWidth = 170.0f;  // room left for a widget's label [px]
inline constexpr float kValueWidth = 64.0f;   // a slider's value, beside its track: "100000.0" in the 7 px font [px]

// Drawing context shared by the sections of one frame.
struct Frame {
  UiState& state;
  PanelActions& actions;
  WidgetRects* rects;

  // Remembers the last item's rectangle under `key`, for tests and tutorials.
  void record(const std::string& key) const {
    if (!rects) return;
    ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    (*rects)[key] = WidgetRect{lo.x, lo.y, hi.x, hi.y};
  }
};

// Where the next labelled widget's frame will be. ImGui's item rectangle of a labelled widget
// takes in the label too, which is not where the slider's track is.
struct Probe {
  const Frame& f;
  ImVec2 pos = ImGui::GetCursorScreenPos();
  float width = ImGui::CalcItemWidth();

  // Records the frame (the input part, without the label) under `key`.
  void record(const std::string& key) const {
    if (!f.rects) return;
    (*f.rects)[key] = WidgetRect{pos.x, pos.y, pos.x + width, pos.y + ImGui::GetFrameHeight()};
  }
};

// A slider row: the track, its value right-aligned in a column of its own, then the label where
// ImGui puts a label. ImGui writes the value in the middle of the track, where the grab covers it
// whenever the value sits mid-range; here the track's own text is drawn transparent (except while
// Ctrl+click typing, which needs it) and the value stands beside the track instead. `slider(id)`
// draws the track under the hidden label it is given and returns whether the value changed;
// `text()` then formats the value as the track would have written it.
template <class Slider, class Text>
inline bool sliderRow(const Frame& f, const std::string& key, const char* label, Slider slider, Text text,
               bool* hovered = nullptr) {
  const ImGuiStyle& style = ImGui::GetStyle();
  const std::string hidden = std::string("##") + label;
  const float track = std::max(40.0f, ImGui::CalcItemWidth() - kValueWidth - style.ItemInnerSpacing.x);
  const bool typing = sliderBeingTyped(hidden.c_str());
  Probe probe{f};
  probe.width = track;
  ImGui::SetNextItemWidth(track);
  if (!typing) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0, 0, 0, 0));
  const bool changed = slider(hidden.c_str());
  if (!typing) ImGui::PopStyleColor();
  probe.record(key);
  if (hovered) *hovered = ImGui::IsItemHovered();
  // The value, right-aligned in its column, then the label.
  const std::string value = text();
  ImGui::SameLine(0.0f, style.ItemInnerSpacing.x);
  const float column_x = ImGui::GetCursorPosX();
  const float text_w = ImGui::CalcTextSize(value.c_str()).x;
  ImGui::SetCursorPosX(column_x + std::max(0.0f, kValueWidth - text_w));
  ImGui::TextUnformatted(value.c_str());
  f.record("value." + key);
  ImGui::SameLine(0.0f, 0.0f);
  ImGui::SetCursorPosX(column_x + kValueWidth + style.ItemInnerSpacing.x);
  ImGui::TextUnformatted(label);
  return changed;
}

// A slider on a double, clamped to [lo, hi] for drags and for Ctrl+click typing alike. The bounds
// are sub-ranges of sim_params.cpp's table, so an edited set always saves.
// `format` is ImGui's, and must be "%.<digits>f" (a literal): the value beside the track is printed
// from its digits, so no format string of ours reaches snprintf.
bool sliderDouble(const Frame& f, const std::string& key, const char* label, double& v, double lo, double hi,
                  const char* format, bool logarithmic = false, bool* hovered = nullptr);

// A colour picker over three doubles; only the components the user moved are written back.
bool colourEdit(const Frame& f, const std::string& key, const char* label, double& r, double& g, double& b);

// A collapsing header, recorded as "section.<key>"; true when open.
bool section(const Frame& f, const char* key, const char* label, ImGuiTreeNodeFlags flags = 0);

// An error line: red, wrapped, after the widget it belongs to; nothing when `text` is empty.
void errorLine(const std::string& text);

// A tooltip for the last item, disabled or not.
void tooltip(const char* text);
// The text of the tooltip shown this frame (the last one tooltip() opened), for the tests; empty
// when none. drawParamPanel clears it at the start of each frame.
const std::string& shownTooltip();
void clearShownTooltip();

}  // namespace dentsim::ui::panel

// The parameter window's shared widgets: sliders on doubles, colour pickers, section headers, error lines and tooltips.
#include "ui/panel_widgets.h"

#include <imgui_internal.h>  // the one file that does: see panel_widgets.h

#include <algorithm>
#include <cassert>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace dentsim::ui::panel {

bool sliderBeingTyped(const char* id) { return ImGui::TempInputIsActive(ImGui::GetID(id)); }

bool windowLayout(const char* name, WindowLayout* layout) {
  const ImGuiWindow* window = ImGui::FindWindowByName(name);
  if (window == nullptr) return false;
  layout->rect = WidgetRect{window->Pos.x, window->Pos.y, window->Pos.x + window->Size.x, window->Pos.y + window->Size.y};
  layout->scroll_max_y = window->ScrollMax.y;
  layout->content_height = window->ContentSize.y;
  return true;
}

int windowsLeftOpen() { return GImGui->CurrentWindowStack.Size; }

namespace {
// The digits of a fixed-point format "%.<digits>f", the only shape the sliders use.
int fixedDigits(const char* format) {
  assert(format[0] == '%' && format[1] == '.' && std::isdigit(uint8_t(format[2])) && "a slider format is \"%.<digits>f\"");
  const int digits = std::atoi(format + 2);
  assert(format[std::strlen(format) - 1] == 'f' && digits <= 9);
  return std::clamp(digits, 0, 9);
}
}  // namespace

// A slider on a double, clamped to [lo, hi] for drags and for Ctrl+click typing alike. The bounds
// are sub-ranges of sim_params.cpp's table, so an edited set always saves.
bool sliderDouble(const Frame& f, const std::string& key, const char* label, double& v, double lo, double hi,
                  const char* format, bool logarithmic, bool* hovered) {
  const ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp | (logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
  return sliderRow(
      f, key, label, [&](const char* id) { return ImGui::SliderScalar(id, ImGuiDataType_Double, &v, &lo, &hi, format, flags); },
      [&] {
        char buf[48];
        std::snprintf(buf, sizeof buf, "%.*f", fixedDigits(format), v);
        return std::string(buf);
      },
      hovered);
}

// A colour picker over three doubles. ImGui edits floats; a component is written back only when
// its float differs from the float of the stored double, so the untouched components keep their
// exact values (0.26 does not come back as 0.25999999).
bool colourEdit(const Frame& f, const std::string& key, const char* label, double& r, double& g, double& b) {
  float c[3] = {float(r), float(g), float(b)};
  const Probe probe{f};
  bool edited = ImGui::ColorEdit3(label, c, ImGuiColorEditFlags_Float);
  probe.record(key);
  if (!edited) return false;
  bool changed = false;
  double* dst[3] = {&r, &g, &b};
  for (int i = 0; i < 3; ++i) {
    float v = std::clamp(c[i], 0.0f, 1.0f);
    if (v != float(*dst[i])) {
      *dst[i] = double(v);
      changed = true;
    }
  }
  return changed;
}

// A collapsing header, recorded as "section.<key>"; true when open.
bool section(const Frame& f, const char* key, const char* label, ImGuiTreeNodeFlags flags) {
  bool open = ImGui::CollapsingHeader(label, flags);
  f.record(std::string("section.") + key);
  return open;
}

// An error line: red, wrapped, after the widget it belongs to.
void errorLine(const std::string& text) {
  if (text.empty()) return;
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.40f, 0.35f, 1.0f));
  ImGui::TextWrapped("%s", text.c_str());
  ImGui::PopStyleColor();
}

// A tooltip for the last item, disabled or not.
namespace {
std::string g_shown_tooltip;  // one ImGui context is drawn at a time, from one thread
}  // namespace

void tooltip(const char* text) {
  if (!ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) return;
  ImGui::SetTooltip("%s", text);
  g_shown_tooltip = text;
}

const std::string& shownTooltip() { return g_shown_tooltip; }
void clearShownTooltip() { g_shown_tooltip.clear(); }

}  // namespace dentsim::ui::panel

// The parameter window and the overlay: one function per section, each editing UiState and raising PanelActions.
//
// Contents
//   1. Sizes and the force gauge (the shared widgets are in panel_widgets.h)
//   2. Pages and their sections: tissues, tools (bur, turbine, sound), view (surface, ghost), presets (and
//      advanced), score; the run's buttons above them (the Task page is task_page.cpp)
//   3. drawParamPanel, the score picture window beside the tooth, drawOverlay
//   4. applyPresetActions
#include "ui/param_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>

#include "model/tool_generator.h"
#include "ui/controls_help.h"
#include "ui/panel_widgets.h"
#include "ui/review_panel.h"
#include "ui/task_page.h"
#include "volume/tissue_table.h"

namespace dentsim::ui {
namespace {

using namespace panel;  // the shared widgets and the pages kept in files of their own

// ---- 1. sizes and the gauge -------------------------------------------------------------------------

constexpr float kPanelWidth = 380.0f;       // [px]
constexpr float kMargin = 10.0f;            // from the display's edges [px]
constexpr float kPictureBox = 320.0f;       // the score picture fits in this square [px]
constexpr float kMinPictureBox = 120.0f;    // ... and shrinks no further to stay off the tooth [px]
constexpr float kGaugeWidth = 220.0f;       // the overlay's force gauge [px]
constexpr double kWheelSpeedStep = 0.05;    // turbine speed per wheel notch [-]
constexpr double kKeySpeedStep = 0.1;       // turbine speed per PageUp/PageDown [-]

// Green while light, amber when firm, red near the device's clamp.
ImVec4 gaugeColour(double fraction) {
  if (fraction < 0.5) return ImVec4(0.20f, 0.75f, 0.30f, 1.0f);
  if (fraction < 0.85) return ImVec4(0.95f, 0.70f, 0.10f, 1.0f);
  return ImVec4(0.90f, 0.20f, 0.15f, 1.0f);
}

// The drill force as a bar and the contact as a word; shared by the panel and the overlay.
void forceGauge(const ForceGauge& g, float width) {
  double fraction = g.max_force_n > 0.0 ? std::clamp(g.force_n / g.max_force_n, 0.0, 1.0) : 0.0;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f N / %.1f N", g.force_n, g.max_force_n);
  ImGui::PushStyleColor(ImGuiCol_PlotHistogram, gaugeColour(fraction));
  ImGui::ProgressBar(float(fraction), ImVec2(width, 0.0f), text);
  ImGui::PopStyleColor();
  if (g.contact)
    ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.10f, 1.0f), "CONTACT");
  else
    ImGui::TextDisabled("no contact");
}

const char* runStateName(RunState s) {
  switch (s) {
    case RunState::Idle: return "idle";
    case RunState::Running: return "running";
    case RunState::Stopped: return "stopped";
  }
  return "?";
}

// ---- 2. sections ---------------------------------------------------------------------------------------

// How one tissue feels and looks: a tab per tissue, the tactile fields, then the Phong colours.
void tissueTab(const Frame& f, Material m) {
  const std::string name = materialName(m);
  const std::string t = "tissues." + name + ".", l = "looks." + name + ".";
  TissueParams& tp = f.state.params.tissue(m);
  TissueLook& lk = f.state.looks.look(m);
  bool changed = false;

  ImGui::TextDisabled("touch");
  changed |= sliderDouble(f, t + "stiffness_n_per_mm3", "spring [N/mm^3]", tp.stiffness_n_per_mm3, 1.0, 1e5, "%.1f",
                          true);
  changed |= sliderDouble(f, t + "damping_s_per_mm", "damper [s/mm]", tp.damping_s_per_mm, 0.0, 0.1, "%.5f", true);
  changed |= sliderDouble(f, t + "friction", "friction", tp.friction, 0.0, 2.0, "%.3f");
  changed |= sliderDouble(f, t + "hardness", "hardness", tp.hardness, 0.0, 1.0, "%.3f");

  ImGui::TextDisabled("look (Phong)");
  changed |= colourEdit(f, l + "diffuse", "colour (diffuse)", lk.diffuse_r, lk.diffuse_g, lk.diffuse_b);
  changed |= sliderDouble(f, l + "alpha", "alpha", lk.alpha, 0.0, 1.0, "%.3f");
  changed |= colourEdit(f, l + "ambient", "ambient", lk.ambient_r, lk.ambient_g, lk.ambient_b);
  changed |= colourEdit(f, l + "specular", "specular", lk.specular_r, lk.specular_g, lk.specular_b);
  changed |= sliderDouble(f, l + "shininess", "shininess", lk.shininess, 1.0, 512.0, "%.1f", true);
  f.actions.params_changed |= changed;
}

void tissuesPage(const Frame& f) {
  if (!ImGui::BeginTabBar("tissues")) return;
  for (Material m : kTissues) {
    const std::string name = materialName(m);
    bool open = ImGui::BeginTabItem(name.c_str());
    f.record("tab." + name);
    if (!open) continue;
    tissueTab(f, m);
    ImGui::EndTabItem();
  }
  ImGui::EndTabBar();
}

// The burs offered: the catalog's, then any other name a preset brought in.
std::vector<std::string> burNames(const SimParams& params) {
  std::vector<std::string> names;
  for (const ToolSpec& t : toolCatalog())
    if (isBur(t.kind)) names.emplace_back(t.name);
  for (const auto& [name, bur] : params.burs)
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  return names;
}

// Sets the speed and raises speed_changed when `speed` (clamped) differs.
void setSpeed(const Frame& f, double speed) {
  speed = std::clamp(speed, 0.0, 1.0);
  if (speed == f.state.turbine_speed) return;
  f.state.turbine_speed = speed;
  f.actions.speed_changed = true;
}

// Without a pedal, PageUp/PageDown step the speed (keys the GLFW backend maps; a headless context
// maps none) unless a text field has the keyboard. Runs whether or not the panel is folded.
void turbineKeys(const Frame& f) {
  if (f.state.pedal_present || ImGui::GetIO().WantTextInput) return;
  const int steps = int(ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_PageUp))) -
                    int(ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_PageDown)));
  if (steps != 0) setSpeed(f, f.state.turbine_speed + kKeySpeedStep * steps);
}

// With a pedal, a bar showing its speed; without, a slider that the wheel also turns while hovered.
void turbineSpeed(const Frame& f) {
  UiState& s = f.state;
  if (s.pedal_present) {
    char text[32];
    std::snprintf(text, sizeof text, "pedal %.0f%%", s.turbine_speed * 100.0);
    ImGui::ProgressBar(float(std::clamp(s.turbine_speed, 0.0, 1.0)), ImVec2(-kLabelWidth, 0.0f), text);
    f.record("turbine.speed");
    ImGui::SameLine(0.0f, ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::TextUnformatted("speed (pedal)");
    return;
  }
  double speed = s.turbine_speed;
  bool hovered = false;
  sliderDouble(f, "turbine.speed", "speed (no pedal)", speed, 0.0, 1.0, "%.2f", false, &hovered);
  const float wheel = ImGui::GetIO().MouseWheel;
  if (hovered && wheel != 0.0f) speed += kWheelSpeedStep * double(wheel);
  setSpeed(f, speed);
}

void burSection(const Frame& f) {
  ImGui::TextDisabled("bur and turbine");
  UiState& s = f.state;

  const std::vector<std::string> names = burNames(s.params);
  const Probe bur_probe{f};
  bool opened = ImGui::BeginCombo("bur", s.bur.c_str());
  bur_probe.record("bur");
  if (opened) {
    for (const std::string& n : names) {
      if (ImGui::Selectable(n.c_str(), n == s.bur) && n != s.bur) {
        s.bur = n;
        f.actions.bur_changed = true;
      }
    }
    ImGui::EndCombo();
  }
  // Read through cuttingAbility so that merely showing an unknown bur adds no entry to the map.
  double ability = s.params.cuttingAbility(s.bur);
  if (sliderDouble(f, "bur.cutting_ability", "cutting ability", ability, 0.0, 1.0, "%.3f")) {
    s.params.burs[s.bur].cutting_ability = ability;
    f.actions.params_changed = true;
  }

  turbineSpeed(f);
  f.actions.params_changed |= sliderDouble(f, "turbine.max_rpm", "max speed [rpm]", s.params.turbine.max_rpm, 1000.0,
                                           400000.0, "%.0f", true);
  ImGui::Text("turbine %.0f rpm", s.turbine_speed * s.params.turbine.max_rpm);
  forceGauge(s.force, -kLabelWidth);
}

// Volume and mute; the output line says where the sound goes (or why there is none).
void soundSection(const Frame& f) {
  ImGui::Spacing();
  ImGui::TextDisabled("sound");
  SoundControls& snd = f.state.sound;
  f.actions.sound_changed |= sliderDouble(f, "sound.volume", "volume", snd.volume, 0.0, 1.0, "%.2f");
  f.actions.sound_changed |= ImGui::Checkbox("mute", &snd.mute);
  f.record("sound.mute");
  if (!snd.output.empty()) ImGui::TextDisabled("%s", snd.output.c_str());
}

void viewPage(const Frame& f) {
  UiState& s = f.state;
  ImGui::TextUnformatted("normals averaged over (voxels)");
  for (NormalMode mode : kNormalModes) {
    ImGui::SameLine();
    const std::string label = normalModeName(mode);
    if (ImGui::RadioButton(label.c_str(), s.looks.view.normals == mode) && s.looks.view.normals != mode) {
      s.looks.view.normals = mode;
      f.actions.normal_mode_changed = true;
      f.actions.params_changed = true;
    }
    f.record("view.normal_neighbours." + label);
  }
  // A new level rebuilds the tooth, which a running task must not see.
  ImGui::BeginDisabled(s.run_state == RunState::Running);
  int level = s.level;
  const bool moved = sliderRow(
      f, "level", "voxel level",
      [&](const char* id) { return ImGui::SliderInt(id, &level, kMinLevel, kMaxLevel, "%d", ImGuiSliderFlags_AlwaysClamp); },
      [&] { return std::to_string(level); });
  if (moved && level != s.level) {
    s.level = level;
    f.actions.level_changed = true;
  }
  ImGui::EndDisabled();
  if (s.run_state == RunState::Running) tooltip("Stop first: a new level rebuilds the tooth.");
  ImGui::Text("%d voxels per side", 1 << std::clamp(s.level, kMinLevel, kMaxLevel));
}

// The professional's ghost: shown or not, and how it moves. The app loads its session when the box
// is first ticked, so that a run which never shows it never reads it.
void ghostSection(const Frame& f) {
  UiState& s = f.state;
  ImGui::Spacing();
  ImGui::TextDisabled("the professional's ghost");
  ImGui::BeginDisabled(!s.ghost_available);
  ImGui::Checkbox("show the ghost", &s.ghost_shown);
  f.record("ghost");
  if (!s.ghost_available)
    tooltip(s.ghost_source.empty() ? "No professional's session: the task has no recorded ideal and --ghost was not given."
                                   : s.ghost_source.c_str());
  ImGui::TextUnformatted("follows");
  ImGui::SameLine();
  if (ImGui::RadioButton("task time", !s.ghost_nearest)) s.ghost_nearest = false;
  f.record("ghost.follow.time");
  ImGui::SameLine();
  if (ImGui::RadioButton("nearest to the bur", s.ghost_nearest)) s.ghost_nearest = true;
  f.record("ghost.follow.nearest");
  double opacity = s.ghost_opacity;
  if (sliderDouble(f, "ghost.opacity", "ghost opacity", opacity, 0.1, 0.9, "%.2f")) s.ghost_opacity = float(opacity);
  ImGui::EndDisabled();
  if (!s.ghost_source.empty()) ImGui::TextWrapped("%s", s.ghost_source.c_str());
}

// The crown preparation's reduction map, as a depth gauge is used on a typodont: where more must
// come off, seen before asking for the score. Crown tasks only; the app computes and shows it.
void reductionSection(const Frame& f) {
  ReductionMapView& r = f.state.reduction;
  if (!r.available) return;
  ImGui::Spacing();
  ImGui::TextDisabled("the crown's reduction");
  ImGui::Checkbox("Reduction map", &r.shown);
  f.record("reduction_map");
  if (!r.shown) return;
  ImGui::TextColored(ImVec4(0.20f, 0.80f, 0.30f, 1.0f), "green: within");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.30f, 0.50f, 1.00f, 1.0f), "blue: take more off");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.95f, 0.25f, 0.20f, 1.0f), "red: too much off");
  if (!r.legend.empty()) ImGui::TextWrapped("%s", r.legend.c_str());
  if (!r.status.empty()) ImGui::TextWrapped("%s", r.status.c_str());
}

// Start, Stop, Reset and Score with the run's state: above the pages, so that every page has them.
void runButtons(const Frame& f) {
  UiState& s = f.state;
  const bool running = s.run_state == RunState::Running;
  // Each disabled button says why in its tooltip: a greyed-out Score with no reason was the first
  // thing a student asked about.
  ImGui::BeginDisabled(running);
  f.actions.start |= ImGui::Button("Start");
  f.record("start");
  ImGui::EndDisabled();
  tooltip(running ? "Already running: the bur cuts while the turbine turns. Stop ends this segment."
                  : "Starts a segment: the loop runs and the tools move.");
  ImGui::SameLine();
  ImGui::BeginDisabled(!running);
  f.actions.stop |= ImGui::Button("Stop");
  f.record("stop");
  ImGui::EndDisabled();
  tooltip(running ? "Ends this segment; then Score scores the cut." : "Nothing is running: Start first.");
  ImGui::SameLine();
  ImGui::BeginDisabled(running);
  f.actions.reset |= ImGui::Button("Reset");
  f.record("reset");
  ImGui::EndDisabled();
  tooltip(running ? "Stop first: Reset puts the uncut tooth back." : "Puts the uncut tooth back and starts again.");
  ImGui::SameLine();
  ImGui::BeginDisabled(s.run_state != RunState::Stopped);
  f.actions.score |= ImGui::Button("Score");
  f.record("score");
  ImGui::EndDisabled();
  tooltip(running ? "Press Stop first: a cut is scored once its segment has ended."
          : s.run_state == RunState::Idle ? "Nothing to score yet: press Start and drill, then Stop."
                                          : "Scores the cut against the professional's.");
  ImGui::SameLine();
  if (ImGui::Button(s.help.shown ? "Hide help" : "Help")) s.help.shown = !s.help.shown;
  f.record("help");
  tooltip("The controls for the pen in use, the task and the bur (F1).");
  ImGui::SameLine();
  ImGui::Text("(%s)", runStateName(s.run_state));
}

void presetSection(const Frame& f) {
  UiState& s = f.state;
  const Probe preset_probe{f};
  bool opened = ImGui::BeginCombo("preset", s.selected_preset.c_str());
  preset_probe.record("preset");
  if (opened) {
    for (const std::string& n : s.presets)
      if (ImGui::Selectable(n.c_str(), n == s.selected_preset)) s.selected_preset = n;
    ImGui::EndCombo();
  }
  ImGui::SameLine();
  if (ImGui::Button("Load")) f.actions.load_preset = s.selected_preset;
  f.record("load");

  // A fixed buffer: Debian's libimgui has no std::string InputText. Names longer than 64 are
  // invalid anyway; the store says so.
  char buf[80] = {};
  s.save_name.copy(buf, sizeof buf - 1);
  const Probe name_probe{f};
  if (ImGui::InputText("save as", buf, sizeof buf)) s.save_name = buf;
  name_probe.record("save_name");
  ImGui::SameLine();
  ImGui::BeginDisabled(s.save_name.empty());
  if (ImGui::Button("Save")) f.actions.save_preset = s.save_name;
  f.record("save");
  ImGui::EndDisabled();
  if (s.save_name.empty()) tooltip("Type a name in \"save as\" first.");
}

// The rest of SimParams, folded away: the coupling, the device, the cutting and the point shells.
void advancedSection(const Frame& f) {
  if (!section(f, "advanced", "Advanced")) return;
  SimParams& p = f.state.params;
  bool c = false;
  ImGui::TextDisabled("cutting");
  c |= sliderDouble(f, "cutting.removal_rate_mm3_per_s", "removal [mm^3/s]", p.cutting.removal_rate_mm3_per_s, 0.0,
                    100.0, "%.3f", true);
  c |= sliderDouble(f, "cutting.reach_mm", "reach [mm]", p.cutting.reach_mm, 0.0, 0.5, "%.3f");
  ImGui::TextDisabled("coupling");
  c |= sliderDouble(f, "coupling.stiffness_n_per_mm", "spring [N/mm]", p.coupling.stiffness_n_per_mm, 0.01, 100.0,
                    "%.3f", true);
  c |= sliderDouble(f, "coupling.damping_n_s_per_mm", "damper [N s/mm]", p.coupling.damping_n_s_per_mm, 0.0, 1.0,
                    "%.4f", true);
  c |= sliderDouble(f, "coupling.rot_stiffness_n_mm_per_rad", "rot. spring [N mm/rad]",
                    p.coupling.rot_stiffness_n_mm_per_rad, 1.0, 10000.0, "%.1f", true);
  c |= sliderDouble(f, "coupling.rot_damping_n_mm_s_per_rad", "rot. damp [N mm s/rad]",
                    p.coupling.rot_damping_n_mm_s_per_rad, 0.0, 100.0, "%.3f", true);
  c |= sliderDouble(f, "coupling.proxy_damping_n_s_per_mm", "proxy drag [N s/mm]", p.coupling.proxy_damping_n_s_per_mm,
                    0.0, 1.0, "%.4f", true);
  c |= sliderDouble(f, "coupling.max_proxy_speed_mm_per_s", "proxy speed [mm/s]", p.coupling.max_proxy_speed_mm_per_s,
                    1.0, 10000.0, "%.0f", true);
  ImGui::TextDisabled("device");
  c |= sliderDouble(f, "device.max_force_n", "max force [N]", p.device.max_force_n, 0.1, 50.0, "%.2f", true);
  c |= sliderDouble(f, "device.max_torque_n_mm", "max torque [N mm]", p.device.max_torque_n_mm, 0.0, 1000.0, "%.1f",
                    true);
  c |= sliderDouble(f, "device.stale_after_ms", "stale after [ms]", p.device.stale_after_ms, 0.1, 100.0, "%.2f", true);
  c |= sliderDouble(f, "device.rate_hz", "haptic rate [Hz]", p.device.rate_hz, 100.0, 10000.0, "%.0f", true);
  ImGui::TextDisabled("point shells");
  c |= sliderDouble(f, "point_shell.head_spacing_mm", "head spacing [mm]", p.point_shell.head_spacing_mm, 0.005, 0.5,
                    "%.3f", true);
  c |= sliderDouble(f, "point_shell.shank_spacing_mm", "shank spacing [mm]", p.point_shell.shank_spacing_mm, 0.005,
                    0.5, "%.3f", true);
  c |= sliderDouble(f, "point_shell.mirror_spacing_mm", "mirror spacing [mm]", p.point_shell.mirror_spacing_mm, 0.005,
                    0.5, "%.3f", true);
  f.actions.params_changed |= c;
}

void scorePage(const Frame& f) {
  const ScoreSummary& sc = f.state.score;
  ImGui::Text("total %.1f / %.0f", sc.total, sc.total_max);
  if (!sc.rows.empty() && ImGui::BeginTable("score rows", 2, ImGuiTableFlags_RowBg)) {
    for (const ScoreRow& r : sc.rows) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.label.c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(r.value.c_str());
    }
    ImGui::EndTable();
  }
  ImGui::TextColored(ImVec4(0.95f, 0.25f, 0.20f, 1.0f), "red: over-cut");
  ImGui::SameLine();
  ImGui::TextColored(ImVec4(0.30f, 0.50f, 1.00f, 1.0f), "blue: under-cut");
  reviewSection(f);  // review_panel.cpp
}

// ---- 3. windows ----------------------------------------------------------------------------------------

// The picture's size on screen: its own aspect, fitted into a square of `box` pixels.
ImVec2 pictureSize(const ScoreSummary& sc, float box) {
  if (sc.image_width <= 0 || sc.image_height <= 0) return ImVec2(box * 0.8f, box * 0.8f);
  float scale = std::min(box / float(sc.image_width), box / float(sc.image_height));
  return ImVec2(std::floor(float(sc.image_width) * scale), std::floor(float(sc.image_height) * scale));
}

// Where the score picture's window goes, and how big its picture is: beside the tooth's rectangle
// `keep` in the room the panel leaves (x below `free_right`), right of the tooth if it fits there,
// else left of it, else on the roomier side, shrunk to fit (to no less than kMinPictureBox). With
// no tooth given, at the right of that room.
struct PicturePlace {
  ImVec2 pos;
  float box = kPictureBox;
};
PicturePlace placePicture(const ScoreSummary& sc, const PixelRect& keep, float free_right, float display_h) {
  const ImGuiStyle& style = ImGui::GetStyle();
  const float chrome_w = 2.0f * style.WindowPadding.x;
  const float chrome_h = 2.0f * style.WindowPadding.y + ImGui::GetFrameHeight();
  auto window_w = [&](float box) { return pictureSize(sc, box).x + chrome_w; };
  const float top = std::clamp(keep.empty() ? 180.0f : float(keep.y), kMargin,
                               std::max(kMargin, display_h - pictureSize(sc, kPictureBox).y - chrome_h - kMargin));
  if (keep.empty()) return {ImVec2(std::max(kMargin, free_right - window_w(kPictureBox)), top), kPictureBox};
  const float right_room = free_right - float(keep.x + keep.width) - kMargin;  // beside the tooth's right edge
  const float left_room = float(keep.x) - 2.0f * kMargin;                       // between the display's left edge and the tooth
  if (window_w(kPictureBox) <= right_room) return {ImVec2(float(keep.x + keep.width) + kMargin, top), kPictureBox};
  if (window_w(kPictureBox) <= left_room) return {ImVec2(float(keep.x) - kMargin - window_w(kPictureBox), top), kPictureBox};
  // Shrunk: the box that fits the roomier side.
  const bool right = right_room >= left_room;
  const float room = std::max(right_room, left_room);
  float box = kPictureBox;
  while (box > kMinPictureBox && window_w(box) > room) box -= 4.0f;
  const float w = window_w(box);
  return {ImVec2(right ? float(keep.x + keep.width) + kMargin : std::max(kMargin, float(keep.x) - kMargin - w), top), box};
}

// A window with no background around an empty item: the renderer draws the picture into the
// item's visible rectangle before ImGui draws its frame, so the title bar and border sit over it.
// It follows the tooth, so it stays beside it when the view turns or zooms.
PixelRect scorePictureWindow(const char* title, const ScoreSummary& sc, const PixelRect& keep, float free_right) {
  const ImGuiStyle& style = ImGui::GetStyle();
  const PicturePlace place = placePicture(sc, keep, free_right, ImGui::GetIO().DisplaySize.y);
  const ImVec2 pic = pictureSize(sc, place.box);
  // The exact size up front: an auto-resizing window would hide its first frame while measuring.
  const ImVec2 size(pic.x + 2.0f * style.WindowPadding.x,
                    pic.y + 2.0f * style.WindowPadding.y + ImGui::GetFrameHeight());
  ImGui::SetNextWindowPos(place.pos, ImGuiCond_Always);
  ImGui::SetNextWindowSize(size, ImGuiCond_Always);
  PixelRect out;
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoBackground | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                                 ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoSavedSettings;
  if (ImGui::Begin(title, nullptr, flags)) {
    ImGui::Dummy(pic);
    ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
    // Only the visible part: inside the window's clip rectangle and on the display.
    const ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    lo = ImVec2(std::max({lo.x, dl->GetClipRectMin().x, 0.0f}), std::max({lo.y, dl->GetClipRectMin().y, 0.0f}));
    hi = ImVec2(std::min({hi.x, dl->GetClipRectMax().x, display.x}),
                std::min({hi.y, dl->GetClipRectMax().y, display.y}));
    out.x = int(std::lround(lo.x));
    out.y = int(std::lround(lo.y));
    out.width = std::max(0, int(std::lround(hi.x)) - out.x);
    out.height = std::max(0, int(std::lround(hi.y)) - out.y);
  }
  ImGui::End();
  return out;
}

// One page of the panel as a tab, recorded as "page.<key>".
template <class Draw>
void page(const Frame& f, const char* key, const char* label, Draw draw, ImGuiTabItemFlags flags = 0) {
  const bool open = ImGui::BeginTabItem(label, nullptr, flags);
  f.record(std::string("page.") + key);
  if (!open) return;
  draw();
  ImGui::EndTabItem();
}

}  // namespace

PanelActions drawParamPanel(UiState& state, WidgetRects* rects) {
  IM_ASSERT(ImGui::GetCurrentContext() && "drawParamPanel needs an ImGui frame");
  PanelActions actions;
  const Frame f{state, actions, rects};
  const ImVec2 display = ImGui::GetIO().DisplaySize;
  clearShownTooltip();
  turbineKeys(f);

  ImGui::SetNextWindowPos(ImVec2(std::max(0.0f, display.x - kPanelWidth - kMargin), kMargin), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(kPanelWidth, std::max(200.0f, display.y - 2.0f * kMargin)), ImGuiCond_FirstUseEver);
  if (ImGui::Begin("Parameters", nullptr, ImGuiWindowFlags_NoSavedSettings)) {
    ImGui::PushItemWidth(-kLabelWidth);
    runButtons(f);
    // The score page comes forward once, the frame a score first shows.
    ImGuiStorage* storage = ImGui::GetStateStorage();
    const ImGuiID score_seen = ImGui::GetID("score seen");
    const bool new_score = state.score.valid && !storage->GetBool(score_seen);
    storage->SetBool(score_seen, state.score.valid);
    // As the View page, which holds its switch and legend, the frame the reduction map first shows.
    const ImGuiID map_seen = ImGui::GetID("reduction map seen");
    const bool new_map = state.reduction.on_screen && !storage->GetBool(map_seen);
    storage->SetBool(map_seen, state.reduction.on_screen);
    if (ImGui::BeginTabBar("pages")) {
      page(f, "task", "Task", [&] { taskPage(f); });
      page(f, "tissues", "Tissues", [&] { tissuesPage(f); });
      page(f, "tools", "Tools", [&] {
        burSection(f);
        guidanceSection(f);
        soundSection(f);
      });
      page(
          f, "view", "View",
          [&] {
            viewPage(f);
            ghostSection(f);
            reductionSection(f);
          },
          new_map ? ImGuiTabItemFlags_SetSelected : 0);
      page(f, "presets", "Presets", [&] {
        presetSection(f);
        advancedSection(f);
      });
      if (state.score.valid)
        page(f, "score", "Score", [&] { scorePage(f); }, new_score ? ImGuiTabItemFlags_SetSelected : 0);
      ImGui::EndTabBar();
    }
    ImGui::PopItemWidth();
    ImGui::Separator();
    ImGui::TextWrapped("%s", state.status.c_str());
  }
  // Where the window is, collapsed or not: the scene centres itself in what the panel leaves free.
  const ImVec2 panel_pos = ImGui::GetWindowPos(), panel_size = ImGui::GetWindowSize();
  actions.panel_rect = {int(panel_pos.x), int(panel_pos.y), int(panel_size.x), int(panel_size.y)};
  ImGui::End();

  controlsWindow(f);

  studentPrompt(f);  // the first run's name, below the view (review_panel.cpp)
  // One picture window: the reduction map while the app shows it, else the score's picture.
  const ReductionMapView& map = state.reduction;
  const float free_right = std::min(display.x, panel_pos.x) - kMargin;
  if (map.on_screen && map.image_width > 0 && map.image_height > 0) {
    ScoreSummary size;
    size.image_width = map.image_width;
    size.image_height = map.image_height;
    actions.score_image_rect = scorePictureWindow("Reduction map", size, state.keep_clear, free_right);
  } else if (state.score.valid) {
    actions.score_image_rect = scorePictureWindow("Score picture", state.score, state.keep_clear, free_right);
  }
  return actions;
}

void drawOverlay(const UiState& state) {
  IM_ASSERT(ImGui::GetCurrentContext() && "drawOverlay needs an ImGui frame");
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                                 ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                                 ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs | ImGuiWindowFlags_NoMove;
  ImGui::SetNextWindowPos(ImVec2(kMargin, kMargin), ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.45f);
  if (ImGui::Begin("##overlay", nullptr, flags)) {
    const OverlayStats& st = state.stats;
    ImGui::Text("frame    %7.2f ms", st.frame_ms);
    ImGui::Text("haptics  %7.0f Hz", st.haptic_rate_hz);
    ImGui::Text("re-mesh  %7.2f ms", st.remesh_ms);
    ImGui::Text("triangles %llu", static_cast<unsigned long long>(st.triangles));
    if (st.detail_progress < 1.0) ImGui::Text("full detail %5.0f %%", 100.0 * st.detail_progress);
    ImGui::Text("turbine  %7.0f rpm%s", state.turbine_speed * state.params.turbine.max_rpm,
                state.pedal_present ? "" : " (keys)");
    forceGauge(state.force, kGaugeWidth);
    drawGuidePull(state.guidance);
  }
  ImGui::End();
}

// ---- 4. presets ------------------------------------------------------------------------------------------

void applyPresetActions(PanelActions& actions, const PresetStore& store, UiState& state) {
  if (!actions.load_preset.empty()) {
    Result<Preset> loaded = store.load(actions.load_preset);
    if (!loaded) {
      state.status = loaded.message();
    } else {
      if (loaded->looks.view.normals != state.looks.view.normals) actions.normal_mode_changed = true;
      state.params = std::move(loaded->sim);
      state.looks = std::move(loaded->looks);
      state.selected_preset = actions.load_preset;
      state.status = "preset '" + actions.load_preset + "' loaded";
      actions.params_changed = true;
    }
  }
  if (!actions.save_preset.empty()) {
    Status saved = store.save(actions.save_preset, Preset{state.params, state.looks});
    if (!saved) {
      state.status = saved.message();
    } else {
      state.presets = store.list();
      state.selected_preset = actions.save_preset;
      state.status = "preset '" + actions.save_preset + "' saved";
    }
  }
}

}  // namespace dentsim::ui
